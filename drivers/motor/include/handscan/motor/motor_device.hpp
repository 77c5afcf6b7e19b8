// The spinning motor on its CAN bus: a CiA 406 encoder (shaft angle) and, optionally, a CiA 402
// drive (speed). Single-threaded state machine over an injected transport::CanBus:
//   start(): filters {080, 180, 580, 700}+node -> wait for the encoder's boot-up (or heartbeat;
//            if neither comes, NMT reset-node and wait again) -> SDO configuration in pre-op
//            (optional read of 6001h/6002h, heartbeat 1017h, TPDO1 transmission type 1800h:02,
//            cyclic timer 6200h) -> NMT start -> first TPDO1; the drive (if any): 6060h = 3
//            (profile velocity), controlword steps to `operation enabled`, target velocity 0.
//   poll():  one frame at a time: TPDO1 -> EncoderSample (continuous angle, speed, stamped by
//            EncoderSampleClock as replay stamps the recorded frames); heartbeat and
//            TPDO watchdogs; EMCY. A silent encoder, a reboot or an emergency is a fault: the
//            drive is commanded to stop, the fault is latched and returned on every later poll.
//   setMotorSpeed(): target velocity 60FFh by SDO (acknowledged) or by RPDO (cyclic).
// Time comes from an injected clock so a candump log can be replayed in its own (virtual) time.
#pragma once

#include <cstdint>
#include <deque>
#include <optional>
#include <string>

#include "handscan/core/samples.hpp"
#include "handscan/motor/canopen_master.hpp"
#include "handscan/motor/encoder_sample_clock.hpp"

namespace handscan::motor {

struct DriveConfig {
    std::uint8_t node = 2;
    double velocity_units_per_radps =
        60.0 / (2.0 * 3.141592653589793);  // 60FFh unit: rpm by default
    bool use_rpdo =
        false;  // RPDO1 mapped as controlword(16) + target velocity(32), else SDO writes
    int rpdo = 1;
};

struct MotorConfig {
    std::string interface = "can0";
    std::uint8_t encoder_node = 1;
    UnwrapperConfig unwrap;                   // units per revolution / range, overwritten when read
    bool read_resolution_from_device = true;  // SDO-read 6001h and 6002h at start
    std::uint16_t cyclic_timer_ms = 1;        // 6200h: TPDO1 period
    // Position sampled -> TPDO1 received (calibration). Positions are stamped by the TPDO1
    // cyclic-timer fit (EncoderSampleClock), as a recording of this bus replays them.
    TimeNs tpdo_latency = 0;
    std::uint8_t tpdo1_transmission_type = kTransmissionEventManufacturer;
    std::uint16_t heartbeat_ms = 100;           // 1017h producer heartbeat time
    TimeNs heartbeat_timeout = 350 * kNsPerMs;  // silent encoder after this long without heartbeat
    TimeNs tpdo_timeout = 50 * kNsPerMs;        // no position for this long is a fault too
    TimeNs boot_timeout = 2 * kNsPerSec;
    TimeNs sdo_timeout = 100 * kNsPerMs;
    int sdo_retries = 2;
    std::optional<DriveConfig> drive;
};

enum class MotorState : std::uint8_t {
    kIdle,
    kBooting,
    kConfiguring,
    kStreaming,
    kFault,
    kStopped
};
const char* toString(MotorState s);

struct MotorStats {
    std::uint64_t frames = 0;
    std::uint64_t positions = 0;
    std::uint64_t heartbeats = 0;
    std::uint64_t emergencies = 0;
    std::uint64_t bad_frames = 0;      // frames from our nodes that did not decode
    std::uint64_t late_positions = 0;  // TPDO1 gaps longer than 2.5 cyclic periods (lost frames)
    std::uint64_t wraps = 0;
};

class MotorDevice {
public:
    MotorDevice(transport::CanBus& bus, MotorConfig config, Clock clock, RawTap* tap = nullptr);

    [[nodiscard]] Status start();
    // At most one sample per call; nullopt when the frame carried none or nothing arrived within
    // `timeout`. An error is a latched fault (or a transport failure) naming the cause.
    [[nodiscard]] Result<std::optional<EncoderSample>> poll(TimeNs timeout);
    [[nodiscard]] Status setMotorSpeed(double speed_radps);
    // Speed 0, drive shut down, encoder back to pre-operational (best effort, first error
    // returned).
    [[nodiscard]] Status stop();

    MotorState state() const { return state_; }
    const Status& fault() const { return fault_; }
    const MotorStats& stats() const { return stats_; }
    const UnwrapperConfig& resolution() const { return clock_.unwrapper().config(); }
    std::optional<Cia402State> driveState() const { return drive_state_; }

private:
    void onFrame(const TimedCanFrame& tf);
    void raiseFault(Status cause);
    void checkWatchdogs(TimeNs now);
    Status waitForBoot();
    Status configureEncoder();
    Status enableDrive();
    Result<Cia402State> readDriveState();

    CanOpenMaster master_;
    MotorConfig cfg_;
    EncoderSampleClock clock_;
    MotorState state_ = MotorState::kIdle;
    Status fault_;
    MotorStats stats_;
    std::deque<EncoderSample> ready_;
    std::optional<NmtState> encoder_nmt_;
    bool boot_seen_ = false;
    TimeNs last_heartbeat_ = 0;
    TimeNs last_position_ = 0;
    bool have_position_ = false;
    std::optional<Cia402State> drive_state_;
};

}  // namespace handscan::motor
