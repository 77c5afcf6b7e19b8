// Passive decoders of recorded device streams: the sensor->host bytes a driver received (as the
// recorder's tap stored them, with host receive times) back into typed samples. The Hokuyo and
// Xsens ones are the drivers' own receive sides (hokuyo::ScanStreamDecoder,
// xsens::ImuStreamDecoder, which the live devices delegate to) with replay's counters on top; the
// encoder's is the motor driver's (motor::EncoderStreamDecoder, stamped by the EncoderSampleClock
// the live MotorDevice uses).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "handscan/core/config.hpp"
#include "handscan/core/samples.hpp"
#include "handscan/core/stream_counters.hpp"
#include "handscan/hokuyo/scan_stream_decoder.hpp"
#include "handscan/motor/encoder_stream_decoder.hpp"
#include "handscan/xsens/imu_stream_decoder.hpp"

namespace handscan::replay {

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

// The decoders' settings from device.yaml: what the streams themselves do not carry.
hokuyo::ScanTimingConfig hokuyoTiming(const DeviceConfig& device);
xsens::ImuFrameTiming xsensTiming(const DeviceConfig& device);
motor::EncoderStreamConfig encoderStreamConfig(const DeviceConfig& device);

}  // namespace handscan::replay
