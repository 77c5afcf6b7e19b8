// Emulated CANopen nodes, pure and time-driven, built on the same codec the driver uses: a
// CiA 406 encoder (boot-up, heartbeat, SDO server for 1017h/1800h/6001h-6004h/6200h, TPDO1 with
// the shaft position every cyclic-timer period, NMT) and a CiA 402 drive (controlword state
// machine, modes of operation, target velocity by SDO or RPDO). The simulator generates the
// motor's CAN traffic with them; tests and the fake bus use them as the device on the wire.
// Fault injection: silence (cable cut), heartbeat loss, reboot, emergency.
#pragma once

#include <cstdint>
#include <deque>
#include <limits>
#include <optional>

#include "handscan/motor/canopen.hpp"

namespace handscan::motor {

constexpr TimeNs kNever = std::numeric_limits<TimeNs>::max();

class CanNodeEmulator {
public:
    virtual ~CanNodeEmulator() = default;
    // A frame the master put on the bus at time t.
    virtual void receive(TimeNs t, const CanFrame& frame) = 0;
    // Time of the next frame this node transmits (kNever if none is scheduled).
    virtual TimeNs nextTime() const = 0;
    // Removes and returns the frame due at nextTime().
    virtual TimedCanFrame pop() = 0;
};

struct EncoderEmulatorConfig {
    std::uint8_t node = 1;
    std::uint32_t units_per_revolution = 4096;  // 6001h
    std::uint32_t total_range = 4096u * 4096u;  // 6002h (counter wraps here)
    double initial_angle_rad = 0.0;
    double speed_radps = 0.0;
    TimeNs power_on = 0;  // boot-up is sent at power_on + boot_duration
    TimeNs boot_duration = 20 * kNsPerMs;
    TimeNs response_delay = 500 * kNsPerUs;  // SDO answer latency
};

class Cia406EncoderEmulator final : public CanNodeEmulator {
public:
    explicit Cia406EncoderEmulator(EncoderEmulatorConfig config);

    void receive(TimeNs t, const CanFrame& frame) override;
    TimeNs nextTime() const override;
    TimedCanFrame pop() override;

    // Shaft motion from time t on (the angle is continuous).
    void setSpeed(TimeNs t, double speed_radps);
    double angleAt(TimeNs t) const;
    std::uint32_t positionAt(TimeNs t) const;  // 6004h value at t
    NmtState nmtState() const { return nmt_; }

    // Fault injection.
    void setSilent(bool silent) { silent_ = silent; }             // transmits nothing
    void setHeartbeatLost(bool lost) { heartbeat_lost_ = lost; }  // TPDOs go on, heartbeats stop
    void reboot(TimeNs t);                                        // power cycle at t
    void sendEmergency(TimeNs t, std::uint16_t error_code, std::uint8_t error_register);

private:
    void resetCommunication(TimeNs t, TimeNs boot_at);
    void handleSdo(TimeNs t, const SdoMessage& m);
    void queue(TimeNs t, const CanFrame& f);

    EncoderEmulatorConfig cfg_;
    NmtState nmt_ = NmtState::kBootUp;
    bool booted_ = false;
    TimeNs boot_at_ = 0;
    std::uint16_t heartbeat_ms_ = 0;  // 1017h, 0 after reset (heartbeat off)
    std::uint16_t cyclic_ms_ = 0;     // 6200h
    std::uint8_t transmission_type_ = kTransmissionEventManufacturer;
    TimeNs next_heartbeat_ = kNever;
    TimeNs next_tpdo_ = kNever;
    std::deque<TimedCanFrame> pending_;  // one-shot frames in time order
    TimeNs speed_ref_t_ = 0;
    double speed_ref_angle_ = 0.0;
    double speed_ = 0.0;
    bool silent_ = false;
    bool heartbeat_lost_ = false;
};

struct DriveEmulatorConfig {
    std::uint8_t node = 2;
    TimeNs response_delay = 500 * kNsPerUs;
    TimeNs heartbeat_period = 0;  // 0 = no heartbeat
};

class Cia402DriveEmulator final : public CanNodeEmulator {
public:
    explicit Cia402DriveEmulator(DriveEmulatorConfig config);
    void receive(TimeNs t, const CanFrame& frame) override;
    TimeNs nextTime() const override;
    TimedCanFrame pop() override;

    Cia402State state() const { return state_; }
    std::int8_t mode() const { return mode_; }
    std::int32_t targetVelocity() const { return target_velocity_; }
    std::uint16_t statusword() const;
    void setFault() { state_ = Cia402State::kFault; }

private:
    void applyControlword(std::uint16_t cw);
    void queue(TimeNs t, const CanFrame& f) { pending_.push_back({t, f}); }

    DriveEmulatorConfig cfg_;
    Cia402State state_ = Cia402State::kSwitchOnDisabled;
    std::int8_t mode_ = 0;
    std::int32_t target_velocity_ = 0;
    std::uint16_t last_cw_ = 0;
    std::uint32_t rpdo_mapping_[3] = {0, 0, 0};
    std::deque<TimedCanFrame> pending_;
};

}  // namespace handscan::motor
