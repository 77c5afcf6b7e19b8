#include "handscan/motor/motor_setup.hpp"

#include <numbers>

namespace handscan::motor {
namespace {

EncoderEmulatorConfig encoderConfig(const handscan::MotorConfig& c, TimeNs start) {
    EncoderEmulatorConfig e;
    e.node = static_cast<std::uint8_t>(c.encoder_node_id);
    e.units_per_revolution = static_cast<std::uint32_t>(c.encoder_counts_per_rev);
    e.total_range = e.units_per_revolution;  // single-turn, as ours
    e.speed_radps = 2.0 * std::numbers::pi * c.target_speed_rev_s;
    e.power_on = start;
    return e;
}

DriveEmulatorConfig driveConfig(const handscan::MotorConfig& c) {
    DriveEmulatorConfig d;
    d.node = static_cast<std::uint8_t>(c.drive_node_id > 0 ? c.drive_node_id : 2);
    return d;
}

}  // namespace

MotorConfig motorDeviceConfig(const handscan::MotorConfig& c) {
    MotorConfig m;
    m.interface = c.can_interface;
    m.encoder_node = static_cast<std::uint8_t>(c.encoder_node_id);
    m.unwrap.units_per_revolution = static_cast<std::uint32_t>(c.encoder_counts_per_rev);
    m.unwrap.total_range = m.unwrap.units_per_revolution;  // single-turn encoder
    m.cyclic_timer_ms = static_cast<std::uint16_t>(c.tpdo_period_ms);
    m.tpdo_latency = fromSeconds(c.tpdo_latency_ms * 1e-3);
    m.heartbeat_timeout = fromSeconds(c.heartbeat_timeout_s);
    m.drive = DriveConfig{};
    m.drive->node = static_cast<std::uint8_t>(c.drive_node_id);
    return m;
}

EmulatedMotorNodes::EmulatedMotorNodes(const handscan::MotorConfig& c, TimeNs start)
    : bus_(start), encoder_(encoderConfig(c, start)), drive_(driveConfig(c)) {
    bus_.addNode(&encoder_);
    if (c.drive_node_id > 0) bus_.addNode(&drive_);
}

}  // namespace handscan::motor
