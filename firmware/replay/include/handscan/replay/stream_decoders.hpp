// Passive decoders of recorded device streams: the sensor->host bytes a driver received (as the
// recorder's tap stored them, with host receive times) back into typed samples. The Hokuyo and
// Xsens ones are the drivers' own receive sides (hokuyo::ScanStreamDecoder,
// xsens::ImuStreamDecoder, which the live devices delegate to) with replay's counters on top.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "handscan/core/clock_mapper.hpp"
#include "handscan/core/config.hpp"
#include "handscan/core/samples.hpp"
#include "handscan/hokuyo/scan_stream_decoder.hpp"
#include "handscan/motor/position_unwrapper.hpp"
#include "handscan/xsens/imu_stream_decoder.hpp"

namespace handscan::replay {

struct StreamCounters {
    std::uint64_t messages = 0;  // samples decoded
    std::uint64_t checksum_failures = 0;
    std::uint64_t resyncs = 0;
    std::uint64_t gaps = 0;    // lost messages (counter / sequence gaps)
    std::uint64_t errors = 0;  // other faults (device errors, unusable frames)
    std::string last_error;    // the newest fault, for status displays
};

// SCIP 2.0 stream of a UTM-30LX-class sensor: the PP reply gives the geometry, each ME/MD frame a
// LaserScan with per-step host times from the 24-bit millisecond clock.
class HokuyoStreamDecoder {
public:
    explicit HokuyoStreamDecoder(hokuyo::ScanTimingConfig timing = {}) : decoder_(timing) {}
    void feed(TimeNs t_rx, std::span<const std::uint8_t> bytes, std::vector<LaserScan>& out);
    StreamCounters counters() const;
    const std::optional<hokuyo::SensorParameters>& parameters() const {
        return decoder_.parameters();
    }

private:
    hokuyo::ScanStreamDecoder decoder_;
    std::vector<hokuyo::ScipEvent> events_;
    std::uint64_t faults_ = 0;
    std::string last_fault_;
};

// Xbus stream of an MTi: MTData2 packets with SampleTimeFine, Acceleration and RateOfTurn become
// ImuSamples on the host clock.
class XsensStreamDecoder {
public:
    explicit XsensStreamDecoder(xsens::ImuFrameTiming timing = {}) : decoder_("Xsens", timing) {}
    void feed(TimeNs t_rx, std::span<const std::uint8_t> bytes, std::vector<ImuSample>& out) {
        decoder_.feed(t_rx, bytes, out);
    }
    StreamCounters counters() const;

private:
    xsens::ImuStreamDecoder decoder_;
};

// CANopen traffic of a CiA 406 encoder, one candump -l line per message: TPDO1 positions become
// EncoderSamples. The encoder sends TPDO1 on its own cyclic timer, so the n-th TPDO left the
// encoder at t0 + n * period on the encoder's clock: mapping that count onto the receive times
// with the lower-envelope ClockMapper removes the bus and host latency jitter from the angle's
// time stamps (1 ms of jitter at 1 rev/s would otherwise be 6 mrad, 6 cm at 10 m).
struct EncoderStreamConfig {
    std::uint8_t node_id = 1;
    motor::UnwrapperConfig unwrapper;
    TimeNs tpdo_period_ns = 5 * kNsPerMs;  // 6200h cyclic timer as configured
    TimeNs tpdo_latency_ns = 0;  // position sampled -> frame received (motor.tpdo_latency_ms)
};

class EncoderStreamDecoder {
public:
    explicit EncoderStreamDecoder(EncoderStreamConfig config);
    void feed(TimeNs t_rx, std::span<const std::uint8_t> line, std::vector<EncoderSample>& out);
    StreamCounters counters() const { return c_; }

private:
    EncoderStreamConfig cfg_;
    motor::PositionUnwrapper unwrapper_;
    ClockMapper tpdo_clock_;
    std::optional<TimeNs> last_rx_;
    std::optional<TimeNs> last_sample_t_;
    std::int64_t tpdo_index_ = 0;
    StreamCounters c_;
};

// The decoders' settings from device.yaml: what the streams themselves do not carry.
hokuyo::ScanTimingConfig hokuyoTiming(const DeviceConfig& device);
xsens::ImuFrameTiming xsensTiming(const DeviceConfig& device);
EncoderStreamConfig encoderStreamConfig(const DeviceConfig& device);

}  // namespace handscan::replay
