#include "handscan/sources/stream_config.hpp"

namespace handscan::sources {

hokuyo::ScanTimingConfig hokuyoTiming(const DeviceConfig& device) {
    hokuyo::ScanTimingConfig timing;
    timing.extra_latency_ns = fromSeconds(device.hokuyo.frame_latency_ms * 1e-3);
    return timing;
}

xsens::ImuFrameTiming xsensTiming(const DeviceConfig& device) {
    xsens::ImuFrameTiming timing;
    timing.frame_latency_ns = fromSeconds(device.xsens.frame_latency_ms * 1e-3);
    timing.baud = device.xsens.transport == "serial" ? device.xsens.baud : 0;
    return timing;
}

motor::EncoderStreamConfig encoderStreamConfig(const DeviceConfig& device) {
    motor::EncoderStreamConfig c;
    c.node_id = static_cast<std::uint8_t>(device.motor.encoder_node_id);
    c.unwrapper.units_per_revolution =
        static_cast<std::uint32_t>(device.motor.encoder_counts_per_rev);
    // Our encoder is single-turn: its position (6004h) wraps after one revolution (6002h = 6001h).
    c.unwrapper.total_range = c.unwrapper.units_per_revolution;
    c.tpdo_period_ns = device.motor.tpdo_period_ms * kNsPerMs;
    c.tpdo_latency_ns = fromSeconds(device.motor.tpdo_latency_ms * 1e-3);
    return c;
}

}  // namespace handscan::sources
