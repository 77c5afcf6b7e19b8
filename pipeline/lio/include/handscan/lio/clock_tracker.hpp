// ClockTracker: the IMU's and the encoder's time offsets against the laser, tracked online
// (issue 13: "time offsets tracked online within a bounded range"; the paper assumes synchronised
// sensors, ours are not). The clocks come from device.yaml's latencies or calibration.yaml's
// time_offsets; USB-serial buffering, bus load or a firmware update move them by milliseconds,
// and 1.5 ms on the encoder alone turns every sweep by 0.54 deg about the shaft at 1 rev/s
// (house 60 s: drift 0.05 -> 0.43 %).
//
// The model is `handscan calibrate`'s gyro alignment (imu/gyro_hand_eye.hpp) over a sliding
// window of the sweeps the tracking monitor trusted: the rotation increments the scan matcher
// reports against the gyro's. It solves the IMU's time offset dt and a turn eps of the sweeps
// about the shaft axis; at the near constant shaft speed of a scan a late encoder and a wrong
// encoder zero turn the sweep alike (the speed ripple, ~2 %, leaves them inseparable), so eps is
// applied as an encoder time offset, eps / shaft speed. Both are absolute (from the raw stamps),
// held within `*_bound_s` of the configured values, applied only once determined (std under
// `max_*_std`) and in steps small enough that the shifted stamps keep their order.
// Pure computation, in sample-time order.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <deque>
#include <limits>
#include <optional>

#include "handscan/core/samples.hpp"
#include "handscan/imu/gyro_hand_eye.hpp"

namespace handscan::lio {

struct ClockTrackerConfig {
    bool enabled = true;
    double window_s = 30.0;        // trusted sweeps this far back form the pairs
    double update_period_s = 2.0;  // a solve this often (~1 % of a core: see clock_tracker_bench)
    std::size_t min_pairs = 20;    // ~5 s of trusted sweeps at 2 sweeps/s
    // The bounded range about the configured clocks: a latency beyond it is a fault (a wrong
    // device.yaml, a USB hub in the way) that `handscan calibrate` should measure, not something
    // to follow blindly. Reaching it is reported.
    double imu_bound_s = 0.005;
    double encoder_bound_s = 0.005;
    // Determined: the formal std times `std_inflation` (overlapping pairs and the matcher's slowly
    // varying errors are not independent: calibrate measured ~3x over seeds) under these.
    double std_inflation = 3.0;
    double max_imu_std_s = 0.001;
    double max_turn_std_rad = 0.00175;  // 0.1 deg: 0.28 ms at 1 rev/s
    // The applied offsets move at most this much per solve: under half the 5 ms sample period of
    // the IMU and the encoder's TPDOs, so shifted stamps never reorder, and a sweep under
    // assembly sees at most a 0.09 deg step of its encoder angle.
    double max_step_s = 0.002;
    // The shaft must turn at least this fast for eps to be a time (a stopped shaft has no clock
    // to show).
    double min_shaft_speed_radps = 1.0;
    // The configured clocks as offsets from the stamps (the centre of the bounds; applied even
    // when tracking is off): zero when the drivers stamp with the configured latencies; in a
    // daemon that installed a new calibration since its drivers started, the new latencies
    // minus those the drivers stamp with (PipelineWorker::recalibrate).
    double configured_imu_offset_s = 0.0;
    double configured_encoder_offset_s = 0.0;
    // The offsets applied from the first sample (held within the bounds): what the previous scan
    // of the session tracked (PipelineWorker::reset), so a new scan does not start from the
    // configured clocks again.
    double start_imu_offset_s = 0.0;
    double start_encoder_offset_s = 0.0;
};

struct ClockTrackerStats {
    std::uint64_t solves = 0;           // solves run
    std::uint64_t determined = 0;       // solves whose offsets were determined (and applied)
    std::uint64_t rejected_solves = 0;  // ran off or fit worse: no measurement
    double imu_offset_s = 0.0;          // applied: subtracted from the IMU's stamps
    double encoder_offset_s = 0.0;      // applied: subtracted from the encoder's stamps
    double imu_target_s = 0.0;          // what the last determined solve wants (unclamped)
    double encoder_target_s = 0.0;
    double imu_std_s = std::numeric_limits<double>::infinity();  // the last solve's (inflated) std
    double turn_std_rad = std::numeric_limits<double>::infinity();
    double shaft_speed_radps = 0.0;
    bool imu_at_bound = false;  // the last determined solve wanted more than the bound
    bool encoder_at_bound = false;
    std::size_t pairs = 0;                             // in the last solve
    double rms_before_rad = 0.0, rms_after_rad = 0.0;  // the last solve's residuals
};

class ClockTracker {
public:
    // `R_body_imu`: the IMU's orientation in the body frame; `axis_body`: the shaft axis there.
    ClockTracker(const ClockTrackerConfig& config, const Eigen::Matrix3d& R_body_imu,
                 const Eigen::Vector3d& axis_body);

    // The streams as stamped (before this tracker's offsets): the solve is absolute.
    void addImu(const ImuSample& raw);
    void addEncoder(const EncoderSample& raw);
    // A sweep the scan matcher placed: `ordinal` counts every assembled sweep (consecutive
    // ordinals are consecutive sweeps), `trusted` the tracking monitor's verdict.
    void addSweep(std::uint64_t ordinal, TimeNs t_start, const Eigen::Quaterniond& q_world_body,
                  bool trusted);
    // Solves when due; true when the applied offsets changed.
    bool update(TimeNs now);

    TimeNs imuOffset() const { return fromSeconds(stats_.imu_offset_s); }
    TimeNs encoderOffset() const { return fromSeconds(stats_.encoder_offset_s); }
    const ClockTrackerStats& stats() const { return stats_; }

private:
    struct Sweep {
        std::uint64_t ordinal;
        double t_s;
        Eigen::Quaterniond q;
        double applied_turn_rad;  // the encoder offset applied then, as a turn
    };
    imu::HandEyeProblem problem(double t_from_s) const;
    // Within the bounds about the configured clocks.
    double clampImu(double offset_s) const;
    double clampEncoder(double offset_s) const;

    ClockTrackerConfig config_;
    Eigen::Matrix3d R_body_imu_;
    Eigen::Vector3d axis_;
    std::deque<ImuSample> imu_;
    std::deque<Sweep> sweeps_;
    double shaft_speed_radps_ = 0.0;  // smoothed, signed
    double last_solve_s_ = -std::numeric_limits<double>::infinity();
    double last_solved_sweep_s_ =
        -std::numeric_limits<double>::infinity();        // the newest sweep in the last solve
    imu::HandEyeParams x_ = imu::HandEyeParams::Zero();  // the last solution (warm start)
    ClockTrackerStats stats_;
};

}  // namespace handscan::lio
