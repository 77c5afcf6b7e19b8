#include "handscan/motor/motor_device.hpp"

#include <cmath>
#include <cstdio>
#include <vector>

#include "handscan/core/log.hpp"

namespace handscan::motor {
namespace {

constexpr std::size_t kMaxQueuedSamples = 8192;  // ~8 s at 1 kHz: start() and SDOs never queue more

std::string hex(unsigned v, int digits) {
    char buf[16];
    std::snprintf(buf, sizeof buf, "%0*X", digits, v);
    return buf;
}

std::string ms(TimeNs t) { return std::to_string(t / kNsPerMs) + " ms"; }

void addNodeFilters(std::vector<CanFilter>& f, std::uint8_t node) {
    for (std::uint32_t base : {0x080u, 0x180u, 0x580u, 0x700u})
        f.push_back(exactSffFilter(base + node));
}

EncoderTiming timing(const MotorConfig& c) {
    const bool cyclic = c.tpdo1_transmission_type >= kTransmissionEventManufacturer;
    return {cyclic ? static_cast<TimeNs>(c.cyclic_timer_ms) * kNsPerMs : 0, c.tpdo_latency};
}

}  // namespace

const char* toString(MotorState s) {
    switch (s) {
        case MotorState::kIdle:
            return "idle";
        case MotorState::kBooting:
            return "booting";
        case MotorState::kConfiguring:
            return "configuring";
        case MotorState::kStreaming:
            return "streaming";
        case MotorState::kFault:
            return "fault";
        case MotorState::kStopped:
            return "stopped";
    }
    return "?";
}

MotorDevice::MotorDevice(transport::CanBus& bus, MotorConfig config, Clock clock, RawTap* tap)
    : master_(bus, std::move(clock), tap, config.interface),
      cfg_(std::move(config)),
      clock_(cfg_.unwrap, timing(cfg_)) {
    master_.setFrameHandler([this](const TimedCanFrame& tf) { onFrame(tf); });
}

void MotorDevice::raiseFault(Status cause) {
    if (state_ == MotorState::kFault) return;
    state_ = MotorState::kFault;
    fault_ = std::move(cause);
    log().error("motor: {}", fault_.message());
    // Stop the spinning laser without waiting for anything: quick stop (fire and forget; we may be
    // inside another transfer, and the bus may be the thing that failed).
    if (cfg_.drive) {
        const DriveConfig& d = *cfg_.drive;
        const CanFrame stop =
            d.use_rpdo ? encodeDriveVelocityRpdo(d.rpdo, d.node, controlword::kQuickStop, 0)
                       : encodeSdoWrite(d.node, od::kControlword, 0, controlword::kQuickStop, 2);
        if (Status s = master_.send(stop); !s)
            log().error("motor: quick stop of drive node {} not sent: {}", d.node, s.message());
    }
}

void MotorDevice::onFrame(const TimedCanFrame& tf) {
    ++stats_.frames;
    const CobIdInfo info = classifyCobId(tf.frame);
    const bool from_encoder = info.node == cfg_.encoder_node;
    const bool from_drive = cfg_.drive && info.node == cfg_.drive->node;
    if (!from_encoder && !from_drive) return;
    const std::string who =
        std::string(from_encoder ? "encoder" : "drive") + " node " + std::to_string(info.node);

    switch (info.function) {
        case CanOpenFunction::kHeartbeat: {
            auto hb = decodeHeartbeat(tf.frame);
            if (!hb) {
                ++stats_.bad_frames;
                return;
            }
            if (!from_encoder) {
                if (state_ == MotorState::kStreaming && hb->state == NmtState::kBootUp) {
                    raiseFault({StatusCode::kDeviceError,
                                who + " rebooted (boot-up " + hex(tf.frame.id, 3) +
                                    "#00) during the scan; its configuration is lost"});
                }
                return;
            }
            ++stats_.heartbeats;
            last_heartbeat_ = tf.t_host;
            encoder_nmt_ = hb->state;
            if (hb->state == NmtState::kBootUp) boot_seen_ = true;
            if (state_ == MotorState::kStreaming && hb->state != NmtState::kOperational) {
                raiseFault(
                    {StatusCode::kDeviceError,
                     hb->state == NmtState::kBootUp
                         ? who + " rebooted (boot-up " + hex(tf.frame.id, 3) +
                               "#00) during the scan; restart the scan"
                         : who + " left operational state: heartbeat says " + toString(hb->state)});
            }
            return;
        }
        case CanOpenFunction::kTpdo: {
            if (info.pdo != 1) return;
            if (from_drive) {
                if (tf.frame.len >= 2)
                    drive_state_ = cia402StateFromStatusword(
                        static_cast<std::uint16_t>(tf.frame.data[0] | (tf.frame.data[1] << 8)));
                return;
            }
            auto pos = decodeEncoderPositionTpdo(tf.frame);
            if (!pos) {
                ++stats_.bad_frames;
                log().warn("motor: {}", pos.status().message());
                return;
            }
            if (state_ != MotorState::kStreaming) return;  // stale frames before NMT start
            const bool event_driven =
                cfg_.tpdo1_transmission_type >= kTransmissionEventManufacturer;
            if (have_position_ && event_driven && cfg_.cyclic_timer_ms > 0 &&
                tf.t_host - last_position_ >
                    static_cast<TimeNs>(2.5 * cfg_.cyclic_timer_ms * kNsPerMs)) {
                ++stats_.late_positions;
            }
            auto sample = clock_.update(tf.t_host, *pos);
            if (!sample) {
                ++stats_.bad_frames;
                log().warn("motor: {} ({} at {} ns)", sample.status().message(), who, tf.t_host);
                return;
            }
            have_position_ = true;
            last_position_ = tf.t_host;
            ++stats_.positions;
            stats_.wraps = clock_.unwrapper().wraps();
            if (ready_.size() < kMaxQueuedSamples) ready_.push_back(*sample);
            return;
        }
        case CanOpenFunction::kEmcy: {
            auto e = decodeEmergency(tf.frame);
            if (!e) {
                ++stats_.bad_frames;
                return;
            }
            ++stats_.emergencies;
            if (e->error_code != 0) {
                raiseFault({StatusCode::kDeviceError,
                            who + " sent an emergency: error code 0x" + hex(e->error_code, 4) +
                                ", error register 0x" + hex(e->error_register, 2) +
                                " (see the device manual's EMCY table)"});
            }
            return;
        }
        default:
            return;  // SDO responses outside a transfer (late answers) are dropped
    }
}

void MotorDevice::checkWatchdogs(TimeNs now) {
    if (state_ != MotorState::kStreaming) return;
    if (cfg_.heartbeat_ms > 0 && now - last_heartbeat_ > cfg_.heartbeat_timeout) {
        raiseFault({StatusCode::kTimeout,
                    "encoder node " + std::to_string(cfg_.encoder_node) +
                        " silent: no heartbeat (" + hex(cobHeartbeat(cfg_.encoder_node), 3) +
                        ") for " + ms(now - last_heartbeat_) + " (limit " +
                        ms(cfg_.heartbeat_timeout) + ") on " + master_.bus().describe() +
                        "; scan stopped. Check the encoder's cable and power"});
        return;
    }
    if (cfg_.tpdo_timeout > 0 && now - last_position_ > cfg_.tpdo_timeout) {
        raiseFault({StatusCode::kTimeout, "encoder node " + std::to_string(cfg_.encoder_node) +
                                              " sends no position (TPDO1 " +
                                              hex(cobTpdo(1, cfg_.encoder_node), 3) + ") for " +
                                              ms(now - last_position_) + " (limit " +
                                              ms(cfg_.tpdo_timeout) + "); scan stopped"});
    }
}

Status MotorDevice::waitForBoot() {
    const std::uint8_t n = cfg_.encoder_node;
    const std::string what =
        "encoder node " + std::to_string(n) + " boot-up (" + hex(cobHeartbeat(n), 3) + "#00)";
    Status s = master_.pumpUntil([&] { return boot_seen_ || encoder_nmt_.has_value(); },
                                 cfg_.boot_timeout, what);
    if (!s && s.code() == StatusCode::kTimeout) {
        // Already running with heartbeats disabled, or booted before we listened: reset it.
        log().info("motor: no boot-up from encoder node {} within {}; sending NMT reset node", n,
                   ms(cfg_.boot_timeout));
        if (Status sent = master_.send(encodeNmt(NmtCommand::kResetNode, n)); !sent) return sent;
        s = master_.pumpUntil([&] { return boot_seen_; }, cfg_.boot_timeout,
                              what + " after NMT reset node");
        if (!s) return {s.code(), s.message() + "; check power, wiring, node id and bitrate"};
    }
    if (!s) return s;
    if (encoder_nmt_ && *encoder_nmt_ != NmtState::kBootUp &&
        *encoder_nmt_ != NmtState::kPreOperational) {
        // Running already: back to pre-operational so the configuration applies before PDOs flow.
        if (Status sent = master_.send(encodeNmt(NmtCommand::kEnterPreOperational, n)); !sent)
            return sent;
    }
    return Status::ok();
}

Status MotorDevice::configureEncoder() {
    const std::uint8_t n = cfg_.encoder_node;
    UnwrapperConfig u = cfg_.unwrap;
    if (cfg_.read_resolution_from_device) {
        auto upr = master_.sdoRead(n, od::kEncoderUnitsPerRevolution, 0, cfg_.sdo_timeout,
                                   cfg_.sdo_retries);
        if (!upr) return upr.status();
        auto range =
            master_.sdoRead(n, od::kEncoderTotalRange, 0, cfg_.sdo_timeout, cfg_.sdo_retries);
        if (!range) return range.status();
        if (*upr == 0)
            return {StatusCode::kDeviceError, "encoder node " + std::to_string(n) +
                                                  " reports 0 units per revolution (6001h)"};
        u.units_per_revolution = *upr;
        u.total_range = *range;
    }
    clock_ = EncoderSampleClock(u, timing(cfg_));
    if (Status s = master_.sdoWrite(n, od::kProducerHeartbeatTime, 0, cfg_.heartbeat_ms, 2,
                                    cfg_.sdo_timeout, cfg_.sdo_retries);
        !s)
        return s;
    if (Status s = master_.sdoWrite(n, od::kTpdo1Communication, 2, cfg_.tpdo1_transmission_type, 1,
                                    cfg_.sdo_timeout, cfg_.sdo_retries);
        !s)
        return s;
    if (Status s = master_.sdoWrite(n, od::kEncoderCyclicTimer, 0, cfg_.cyclic_timer_ms, 2,
                                    cfg_.sdo_timeout, cfg_.sdo_retries);
        !s)
        return s;
    return Status::ok();
}

Result<Cia402State> MotorDevice::readDriveState() {
    auto sw =
        master_.sdoRead(cfg_.drive->node, od::kStatusword, 0, cfg_.sdo_timeout, cfg_.sdo_retries);
    if (!sw) return sw.status();
    drive_state_ = cia402StateFromStatusword(static_cast<std::uint16_t>(*sw));
    return *drive_state_;
}

Status MotorDevice::enableDrive() {
    const DriveConfig& d = *cfg_.drive;
    const auto write = [&](std::uint16_t index, std::uint8_t sub, std::uint32_t v,
                           std::uint8_t size) {
        return master_.sdoWrite(d.node, index, sub, v, size, cfg_.sdo_timeout, cfg_.sdo_retries);
    };
    if (Status s = master_.send(encodeNmt(NmtCommand::kStart, d.node)); !s) return s;
    if (Status s =
            write(od::kModesOfOperation, 0, static_cast<std::uint32_t>(kModeProfileVelocity), 1);
        !s)
        return s;
    if (d.use_rpdo) {
        // RPDO mapping: controlword (6040h, 16 bit) + target velocity (60FFh, 32 bit),
        // event-driven.
        const std::uint32_t cob = cobRpdo(d.rpdo, d.node);
        const auto comm = static_cast<std::uint16_t>(od::kRpdo1Communication + d.rpdo - 1);
        const auto map = static_cast<std::uint16_t>(od::kRpdo1Mapping + d.rpdo - 1);
        for (const auto& [index, sub, value, size] :
             std::vector<std::tuple<std::uint16_t, std::uint8_t, std::uint32_t, std::uint8_t>>{
                 {comm, 1, 0x80000000u | cob, 4},
                 {map, 0, 0, 1},
                 {map, 1, 0x60400010u, 4},
                 {map, 2, 0x60FF0020u, 4},
                 {map, 0, 2, 1},
                 {comm, 2, 0xFF, 1},
                 {comm, 1, cob, 4}}) {
            if (Status s = write(index, sub, value, size); !s) return s;
        }
    }
    if (Status s = write(od::kTargetVelocity, 0, 0, 4); !s) return s;
    for (int step = 0; step < 8; ++step) {
        auto st = readDriveState();
        if (!st) return st.status();
        if (*st == Cia402State::kOperationEnabled) return Status::ok();
        const auto cw = controlwordTowardsOperationEnabled(*st);
        if (!cw) {
            // The drive moves on by itself (not ready to switch on / fault reaction): give it time.
            if (Status s = master_.pumpUntil([] { return false; }, 10 * kNsPerMs, "drive settling");
                s.code() != StatusCode::kTimeout)
                return s;
            continue;
        }
        if (Status s = write(od::kControlword, 0, *cw, 2); !s) return s;
    }
    return {StatusCode::kDeviceError,
            "drive node " + std::to_string(d.node) +
                " did not reach 'operation enabled' (stuck in " +
                toString(drive_state_.value_or(Cia402State::kNotReadyToSwitchOn)) +
                "); check the drive's enable input and fault log"};
}

Status MotorDevice::start() {
    state_ = MotorState::kBooting;
    fault_ = Status::ok();
    stats_ = {};
    ready_.clear();
    encoder_nmt_.reset();
    boot_seen_ = false;
    have_position_ = false;
    drive_state_.reset();

    std::vector<CanFilter> filters;
    addNodeFilters(filters, cfg_.encoder_node);
    if (cfg_.drive) addNodeFilters(filters, cfg_.drive->node);
    if (Status s = master_.bus().setFilters(filters); !s) return s;

    const auto failed = [&](const Status& s) {
        if (state_ != MotorState::kFault) {
            state_ = MotorState::kFault;
            fault_ = s;
        }
        return fault_;
    };
    if (Status s = waitForBoot(); !s) return failed(s);
    state_ = MotorState::kConfiguring;
    if (Status s = configureEncoder(); !s) return failed(s);
    if (state_ == MotorState::kFault) return fault_;

    // Streaming from here: the watchdogs count from the NMT start.
    state_ = MotorState::kStreaming;
    last_heartbeat_ = master_.now();
    last_position_ = last_heartbeat_;
    if (Status s = master_.send(encodeNmt(NmtCommand::kStart, cfg_.encoder_node)); !s)
        return failed(s);
    const TimeNs first_wait = cfg_.tpdo_timeout > 0 ? cfg_.tpdo_timeout : cfg_.heartbeat_timeout;
    if (Status s = master_.pumpUntil(
            [&] { return have_position_ || state_ == MotorState::kFault; }, first_wait,
            "first position (TPDO1) from encoder node " + std::to_string(cfg_.encoder_node));
        !s) {
        return failed(s);
    }
    if (state_ == MotorState::kFault) return fault_;
    if (cfg_.drive) {
        if (Status s = enableDrive(); !s) return failed(s);
    }
    if (state_ == MotorState::kFault) return fault_;
    log().info("motor: encoder node {} streaming ({} units/rev, range {}, every {} ms){}",
               cfg_.encoder_node, resolution().units_per_revolution, resolution().total_range,
               cfg_.cyclic_timer_ms,
               cfg_.drive ? ", drive node " + std::to_string(cfg_.drive->node) + " enabled"
                          : std::string());
    return Status::ok();
}

Result<std::optional<EncoderSample>> MotorDevice::poll(TimeNs timeout) {
    const auto pop = [&]() -> std::optional<EncoderSample> {
        EncoderSample s = ready_.front();
        ready_.pop_front();
        return s;
    };
    if (!ready_.empty()) return pop();  // samples taken before a fault are still delivered
    if (state_ == MotorState::kFault) return fault_;
    if (state_ != MotorState::kStreaming) {
        return Status(StatusCode::kInvalidArgument, std::string("motor: poll() in state ") +
                                                        toString(state_) + "; call start() first");
    }
    auto r = master_.receive(timeout);
    if (r) {
        onFrame(*r);
    } else if (r.status().code() != StatusCode::kTimeout) {
        raiseFault({r.status().code(), "CAN bus " + master_.bus().describe() +
                                           " failed: " + r.status().message() + "; scan stopped"});
    }
    checkWatchdogs(master_.now());
    if (!ready_.empty()) return pop();
    if (state_ == MotorState::kFault) return fault_;
    return std::optional<EncoderSample>();
}

Status MotorDevice::setMotorSpeed(double speed_radps) {
    if (!cfg_.drive)
        return {StatusCode::kUnsupported,
                "motor: no drive configured (motor.drive in device.yaml)"};
    if (state_ == MotorState::kFault) return fault_;
    const DriveConfig& d = *cfg_.drive;
    const double units = std::round(speed_radps * d.velocity_units_per_radps);
    if (!std::isfinite(units) || units > 2147483647.0 || units < -2147483648.0) {
        return {StatusCode::kInvalidArgument, "motor: speed " + std::to_string(speed_radps) +
                                                  " rad/s is outside the drive's 32-bit range"};
    }
    const auto v = static_cast<std::int32_t>(units);
    if (d.use_rpdo)
        return master_.send(
            encodeDriveVelocityRpdo(d.rpdo, d.node, controlword::kEnableOperation, v));
    return master_.sdoWrite(d.node, od::kTargetVelocity, 0, static_cast<std::uint32_t>(v), 4,
                            cfg_.sdo_timeout, cfg_.sdo_retries);
}

Status MotorDevice::stop() {
    Status first;
    const auto keep = [&](Status s) {
        if (first.isOk() && !s.isOk()) first = std::move(s);
    };
    if (cfg_.drive && state_ != MotorState::kFault) {
        keep(setMotorSpeed(0.0));
        keep(master_.sdoWrite(cfg_.drive->node, od::kControlword, 0, controlword::kShutdown, 2,
                              cfg_.sdo_timeout, cfg_.sdo_retries));
    }
    keep(master_.send(encodeNmt(NmtCommand::kEnterPreOperational, cfg_.encoder_node)));
    if (state_ != MotorState::kFault) state_ = MotorState::kStopped;
    return first;
}

}  // namespace handscan::motor
