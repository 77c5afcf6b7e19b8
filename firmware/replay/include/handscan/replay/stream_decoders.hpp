// Passive decoders of recorded device streams: the sensor->host bytes a driver received (as the
// recorder's tap stored them, with host receive times) back into typed samples, through the same
// codecs, parsers and clock mapping the live drivers use. Replay, `handscan decode` and the
// hardware-in-the-loop tests use them; the live drivers add the command side on top.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "handscan/core/clock_mapper.hpp"
#include "handscan/core/config.hpp"
#include "handscan/core/samples.hpp"
#include "handscan/hokuyo/scan_timestamper.hpp"
#include "handscan/hokuyo/scip_stream_parser.hpp"
#include "handscan/hokuyo/sensor_parameters.hpp"
#include "handscan/motor/position_unwrapper.hpp"
#include "handscan/xsens/xbus_parser.hpp"

namespace handscan::replay {

struct StreamCounters {
    std::uint64_t messages = 0;           // samples decoded
    std::uint64_t checksum_failures = 0;
    std::uint64_t resyncs = 0;
    std::uint64_t gaps = 0;               // lost messages (counter / sequence gaps)
    std::uint64_t errors = 0;             // other faults (device errors, unusable frames)
    std::string last_error;               // the newest fault, for status displays
};

// SCIP 2.0 stream of a UTM-30LX-class sensor: the PP reply gives the geometry, each ME/MD frame a
// LaserScan with per-step host times from the 24-bit millisecond clock.
class HokuyoStreamDecoder {
public:
    explicit HokuyoStreamDecoder(hokuyo::ScanTimingConfig timing = {}) : timestamper_(timing) {}
    void feed(TimeNs t_rx, std::span<const std::uint8_t> bytes, std::vector<LaserScan>& out);
    StreamCounters counters() const;
    const std::optional<hokuyo::SensorParameters>& parameters() const { return params_; }

private:
    hokuyo::ScipStreamParser parser_;
    hokuyo::ScanTimestamper timestamper_;
    std::optional<hokuyo::SensorParameters> params_;
    std::optional<std::uint32_t> last_t_device_;
    std::vector<hokuyo::ScipEvent> events_;
    StreamCounters c_;
};

// Xbus stream of an MTi: MTData2 packets with SampleTimeFine, Acceleration and RateOfTurn become
// ImuSamples on the host clock.
class XsensStreamDecoder {
public:
    XsensStreamDecoder();
    void feed(TimeNs t_rx, std::span<const std::uint8_t> bytes, std::vector<ImuSample>& out);
    StreamCounters counters() const;

private:
    xsens::XbusParser parser_;
    ClockMapper clock_;
    std::optional<std::uint16_t> last_counter_;
    StreamCounters c_;
};

// CANopen traffic of a CiA 406 encoder, one candump -l line per message: TPDO1 positions become
// EncoderSamples. The encoder sends TPDO1 on its own cyclic timer, so the n-th TPDO left the
// encoder at t0 + n * period on the encoder's clock: mapping that count onto the receive times
// with the lower-envelope ClockMapper removes the bus and host latency jitter from the angle's
// time stamps (1 ms of jitter at 1 rev/s would otherwise be 6 mrad, 6 cm at 10 m).
struct EncoderStreamConfig {
    std::uint8_t node_id = 1;
    motor::UnwrapperConfig unwrapper;
    TimeNs tpdo_period_ns = 5 * kNsPerMs;   // 6200h cyclic timer as configured
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
EncoderStreamConfig encoderStreamConfig(const DeviceConfig& device);

}  // namespace handscan::replay
