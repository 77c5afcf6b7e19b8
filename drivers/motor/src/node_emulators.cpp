#include "handscan/motor/node_emulators.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace handscan::motor {

// ---- CiA 406 encoder -------------------------------------------------------------------------

Cia406EncoderEmulator::Cia406EncoderEmulator(EncoderEmulatorConfig config) : cfg_(config) {
    speed_ref_t_ = cfg_.power_on;
    speed_ref_angle_ = cfg_.initial_angle_rad;
    speed_ = cfg_.speed_radps;
    resetCommunication(cfg_.power_on, cfg_.power_on + cfg_.boot_duration);
}

void Cia406EncoderEmulator::resetCommunication(TimeNs /*t*/, TimeNs boot_at) {
    nmt_ = NmtState::kBootUp;
    booted_ = false;
    boot_at_ = boot_at;
    heartbeat_ms_ = 0;
    cyclic_ms_ = 0;
    transmission_type_ = kTransmissionEventManufacturer;
    next_heartbeat_ = kNever;
    next_tpdo_ = kNever;
    pending_.clear();
    queue(boot_at, encodeHeartbeat(cfg_.node, NmtState::kBootUp));
}

void Cia406EncoderEmulator::queue(TimeNs t, const CanFrame& f) {
    auto it = std::upper_bound(pending_.begin(), pending_.end(), t,
                               [](TimeNs a, const TimedCanFrame& b) { return a < b.t_host; });
    pending_.insert(it, {t, f});
}

void Cia406EncoderEmulator::setSpeed(TimeNs t, double speed_radps) {
    speed_ref_angle_ = angleAt(t);
    speed_ref_t_ = t;
    speed_ = speed_radps;
}

double Cia406EncoderEmulator::angleAt(TimeNs t) const {
    return speed_ref_angle_ + speed_ * toSeconds(t - speed_ref_t_);
}

std::uint32_t Cia406EncoderEmulator::positionAt(TimeNs t) const {
    const double counts =
        std::floor(angleAt(t) * cfg_.units_per_revolution / (2.0 * std::numbers::pi));
    const double range =
        cfg_.total_range == 0 ? 4294967296.0 : static_cast<double>(cfg_.total_range);
    double m = std::fmod(counts, range);
    if (m < 0) m += range;
    return static_cast<std::uint32_t>(m);
}

void Cia406EncoderEmulator::reboot(TimeNs t) { resetCommunication(t, t + cfg_.boot_duration); }

void Cia406EncoderEmulator::sendEmergency(TimeNs t, std::uint16_t error_code,
                                          std::uint8_t error_register) {
    Emergency e;
    e.node = cfg_.node;
    e.error_code = error_code;
    e.error_register = error_register;
    queue(t, encodeEmergency(e));
}

void Cia406EncoderEmulator::receive(TimeNs t, const CanFrame& f) {
    if (silent_ || !booted_) return;
    const CobIdInfo info = classifyCobId(f);
    if (info.function == CanOpenFunction::kNmt) {
        auto m = decodeNmt(f);
        if (!m || (m->node != 0 && m->node != cfg_.node)) return;
        switch (m->command) {
            case NmtCommand::kStart:
                nmt_ = NmtState::kOperational;
                if (cyclic_ms_ > 0 && transmission_type_ >= kTransmissionEventManufacturer)
                    next_tpdo_ = t + cyclic_ms_ * kNsPerMs;
                break;
            case NmtCommand::kStop:
                nmt_ = NmtState::kStopped;
                next_tpdo_ = kNever;
                break;
            case NmtCommand::kEnterPreOperational:
                nmt_ = NmtState::kPreOperational;
                next_tpdo_ = kNever;
                break;
            case NmtCommand::kResetNode:
            case NmtCommand::kResetCommunication:
                resetCommunication(t, t + cfg_.boot_duration);
                break;
        }
        return;
    }
    if (info.function == CanOpenFunction::kSdoRequest && info.node == cfg_.node &&
        nmt_ != NmtState::kStopped) {
        auto m = decodeSdo(f);
        if (m) handleSdo(t, *m);
    }
}

void Cia406EncoderEmulator::handleSdo(TimeNs t, const SdoMessage& m) {
    const TimeNs at = t + cfg_.response_delay;
    const auto abort = [&](std::uint32_t code) {
        queue(at, encodeSdoAbort(cfg_.node, m.index, m.subindex, code, true));
    };
    const auto ack = [&] { queue(at, encodeSdoWriteAck(cfg_.node, m.index, m.subindex)); };
    const auto answer = [&](std::uint32_t v, std::uint8_t size) {
        queue(at, encodeSdoReadResponse(cfg_.node, m.index, m.subindex, v, size));
    };
    if (m.kind == SdoKind::kUploadRequest) {
        switch (m.index) {
            case od::kDeviceType:
                return answer(0x00010196u, 4);  // profile 406 (0x196), single/multi-turn
            case od::kProducerHeartbeatTime:
                return answer(heartbeat_ms_, 2);
            case od::kEncoderUnitsPerRevolution:
                return answer(cfg_.units_per_revolution, 4);
            case od::kEncoderTotalRange:
                return answer(cfg_.total_range, 4);
            case od::kEncoderPosition:
                return answer(positionAt(t), 4);
            case od::kEncoderCyclicTimer:
                return answer(cyclic_ms_, 2);
            case od::kTpdo1Communication:
                if (m.subindex == 2) return answer(transmission_type_, 1);
                return abort(0x06090011);
            default:
                return abort(0x06020000);
        }
    }
    if (m.kind != SdoKind::kDownloadRequest) return abort(0x05040001);
    switch (m.index) {
        case od::kProducerHeartbeatTime:
            heartbeat_ms_ = static_cast<std::uint16_t>(m.value);
            next_heartbeat_ = heartbeat_ms_ > 0 ? at + heartbeat_ms_ * kNsPerMs : kNever;
            return ack();
        case od::kEncoderCyclicTimer:
            cyclic_ms_ = static_cast<std::uint16_t>(m.value);
            if (nmt_ == NmtState::kOperational)
                next_tpdo_ = cyclic_ms_ > 0 ? at + cyclic_ms_ * kNsPerMs : kNever;
            return ack();
        case od::kTpdo1Communication:
            if (m.subindex != 2) return abort(0x06090011);
            if (m.value == 0 || (m.value > 240 && m.value < 0xFE)) return abort(0x06090030);
            transmission_type_ = static_cast<std::uint8_t>(m.value);
            return ack();
        case od::kEncoderPosition:
            return abort(0x06010002);
        case od::kEncoderUnitsPerRevolution:
        case od::kEncoderTotalRange:
            return abort(0x08000022);  // fixed in this emulated model
        default:
            return abort(0x06020000);
    }
}

TimeNs Cia406EncoderEmulator::nextTime() const {
    if (silent_) return kNever;
    TimeNs t = pending_.empty() ? kNever : pending_.front().t_host;
    if (booted_ && !heartbeat_lost_) t = std::min(t, next_heartbeat_);
    if (booted_ && nmt_ == NmtState::kOperational) t = std::min(t, next_tpdo_);
    return t;
}

TimedCanFrame Cia406EncoderEmulator::pop() {
    const TimeNs t = nextTime();
    if (!pending_.empty() && pending_.front().t_host == t) {
        TimedCanFrame f = pending_.front();
        pending_.pop_front();
        if (!booted_ && f.t_host >= boot_at_ &&
            classifyCobId(f.frame).function == CanOpenFunction::kHeartbeat) {
            booted_ = true;  // boot-up sent: pre-operational now
            nmt_ = NmtState::kPreOperational;
        }
        return f;
    }
    if (booted_ && nmt_ == NmtState::kOperational && next_tpdo_ == t) {
        next_tpdo_ += cyclic_ms_ * kNsPerMs;
        return {t, encodeEncoderPositionTpdo(cfg_.node, positionAt(t))};
    }
    next_heartbeat_ += heartbeat_ms_ * kNsPerMs;
    return {t, encodeHeartbeat(cfg_.node, nmt_)};
}

// ---- CiA 402 drive ---------------------------------------------------------------------------

Cia402DriveEmulator::Cia402DriveEmulator(DriveEmulatorConfig config) : cfg_(config) {}

std::uint16_t Cia402DriveEmulator::statusword() const {
    switch (state_) {
        case Cia402State::kNotReadyToSwitchOn:
            return 0x0200;
        case Cia402State::kSwitchOnDisabled:
            return 0x0250;
        case Cia402State::kReadyToSwitchOn:
            return 0x0231;
        case Cia402State::kSwitchedOn:
            return 0x0233;
        case Cia402State::kOperationEnabled:
            return 0x0237;
        case Cia402State::kQuickStopActive:
            return 0x0217;
        case Cia402State::kFaultReactionActive:
            return 0x021F;
        case Cia402State::kFault:
            return 0x0218;
    }
    return 0;
}

// Device-control transitions of CiA 402 (command coding of the controlword, bits 0..3 and 7).
void Cia402DriveEmulator::applyControlword(std::uint16_t cw) {
    const bool fault_reset_edge = (cw & 0x80) && !(last_cw_ & 0x80);
    last_cw_ = cw;
    if (state_ == Cia402State::kFault) {
        if (fault_reset_edge) state_ = Cia402State::kSwitchOnDisabled;
        return;
    }
    if ((cw & 0x02) == 0) {  // disable voltage
        state_ = Cia402State::kSwitchOnDisabled;
        return;
    }
    if ((cw & 0x04) == 0) {  // quick stop
        state_ = state_ == Cia402State::kOperationEnabled ? Cia402State::kQuickStopActive
                                                          : Cia402State::kSwitchOnDisabled;
        return;
    }
    if ((cw & 0x0F) == 0x06) {
        state_ = Cia402State::kReadyToSwitchOn;
    } else if ((cw & 0x0F) == 0x07 && state_ == Cia402State::kReadyToSwitchOn) {
        state_ = Cia402State::kSwitchedOn;
    } else if ((cw & 0x0F) == 0x0F &&
               (state_ == Cia402State::kSwitchedOn || state_ == Cia402State::kOperationEnabled ||
                state_ == Cia402State::kQuickStopActive)) {
        state_ = Cia402State::kOperationEnabled;
    }
}

void Cia402DriveEmulator::receive(TimeNs t, const CanFrame& f) {
    const CobIdInfo info = classifyCobId(f);
    if (info.node != cfg_.node) return;
    const TimeNs at = t + cfg_.response_delay;
    if (info.function == CanOpenFunction::kRpdo && info.pdo == 1 && rpdo_mapping_[0] == 2 &&
        f.len >= 6) {
        applyControlword(static_cast<std::uint16_t>(f.data[0] | (f.data[1] << 8)));
        target_velocity_ = static_cast<std::int32_t>(static_cast<std::uint32_t>(f.data[2]) |
                                                     (static_cast<std::uint32_t>(f.data[3]) << 8) |
                                                     (static_cast<std::uint32_t>(f.data[4]) << 16) |
                                                     (static_cast<std::uint32_t>(f.data[5]) << 24));
        return;
    }
    if (info.function != CanOpenFunction::kSdoRequest) return;
    auto m = decodeSdo(f);
    if (!m) return;
    if (m->kind == SdoKind::kUploadRequest) {
        switch (m->index) {
            case od::kStatusword:
                return queue(at, encodeSdoReadResponse(cfg_.node, m->index, 0, statusword(), 2));
            case od::kModesOfOperationDisplay:
                return queue(at, encodeSdoReadResponse(cfg_.node, m->index, 0,
                                                       static_cast<std::uint8_t>(mode_), 1));
            case od::kTargetVelocity:
                return queue(
                    at, encodeSdoReadResponse(cfg_.node, m->index, 0,
                                              static_cast<std::uint32_t>(target_velocity_), 4));
            default:
                return queue(at,
                             encodeSdoAbort(cfg_.node, m->index, m->subindex, 0x06020000, true));
        }
    }
    if (m->kind != SdoKind::kDownloadRequest) return;
    switch (m->index) {
        case od::kControlword:
            applyControlword(static_cast<std::uint16_t>(m->value));
            break;
        case od::kModesOfOperation:
            mode_ = static_cast<std::int8_t>(m->value);
            break;
        case od::kTargetVelocity:
            target_velocity_ = static_cast<std::int32_t>(m->value);
            break;
        case od::kRpdo1Mapping:
            if (m->subindex <= 2) rpdo_mapping_[m->subindex] = m->value;
            break;
        case od::kRpdo1Communication:
            break;
        default:
            return queue(at, encodeSdoAbort(cfg_.node, m->index, m->subindex, 0x06020000, true));
    }
    queue(at, encodeSdoWriteAck(cfg_.node, m->index, m->subindex));
}

TimeNs Cia402DriveEmulator::nextTime() const {
    return pending_.empty() ? kNever : pending_.front().t_host;
}

TimedCanFrame Cia402DriveEmulator::pop() {
    TimedCanFrame f = pending_.front();
    pending_.pop_front();
    return f;
}

}  // namespace handscan::motor
