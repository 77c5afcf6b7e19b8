// The motor thread: the CANopen encoder (and drive) through MotorDevice. A fault (silent encoder,
// reboot, emergency, interface down) is latched by the device; this thread reports it, stops,
// and starts the device again after a back-off.
#include <numbers>

#include "handscan/motor/motor_device.hpp"
#include "handscan/motor/motor_setup.hpp"
#include "handscan/pipeline_daemon/sensor_sources.hpp"

namespace handscan::pipeline_daemon {
namespace {

class MotorSource final : public SensorSource {
public:
    explicit MotorSource(const SourceContext& c)
        : SensorSource("encoder", 1000.0f / static_cast<float>(c.config.motor.tpdo_period_ms)),
          config_(c.config.motor),
          c_(c) {}
    ~MotorSource() override { stop(); }

private:
    void run() override {
        runSessions(500 * kNsPerMs, 5 * kNsPerSec, "motor " + config_.can_interface, " (retrying)",
                    [this] { return session(); });
    }

    // One connection: open, start, spin, stream until a fault or stop().
    Status session() {
        auto link = c_.links.can(config_);
        if (!link.isOk()) return link.status();
        if (Status s = link->bus->open(); !s.isOk()) return s;
        motor::MotorDevice device(*link->bus, motor::motorDeviceConfig(config_), link->now,
                                  c_.taps.motor);
        if (Status s = device.start(); !s.isOk()) return s;
        if (Status s = device.setMotorSpeed(2.0 * std::numbers::pi * config_.target_speed_rev_s);
            !s.isOk()) {
            (void)device.stop();
            return s;
        }
        health_.setConnected();
        health_.markAttempted();
        Status end = Status::ok();
        while (!stopping()) {
            auto r = device.poll(20 * kNsPerMs);
            if (!r.isOk()) {
                end = r.status();
                break;
            }
            if (*r) {
                health_.addSample((*r)->t_host);
                if (!c_.queues.encoder.tryPush(**r))
                    c_.queues.dropped.fetch_add(1, std::memory_order_relaxed);
            }
        }
        (void)device.stop();  // speed 0 and pre-operational, best effort
        link->bus->close();
        return stopping() ? Status::ok() : end;
    }

    MotorConfig config_;
    SourceContext c_;
};

}  // namespace

std::unique_ptr<SensorSource> makeMotorSource(const SourceContext& c) {
    return std::make_unique<MotorSource>(c);
}

}  // namespace handscan::pipeline_daemon
