// SweepAssembler: turns the 2D Hokuyo scans and the motor-encoder angle stream into 3D sweeps.
// Each step becomes a point at its own time: the encoder angle is interpolated at that time, the
// laser -> shaft -> body calibration places the beam, and the motion estimate (PoseAtFn) at that
// time moves it into the body frame at the sweep's start, so the device may move during the 1 s
// sweep (no rigid-sweep assumption). Sweeps end at half or full shaft revolutions.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <deque>
#include <optional>
#include <vector>

#include "handscan/core/config.hpp"
#include "handscan/core/samples.hpp"
#include "handscan/core/status.hpp"
#include "handscan/scan/sweep.hpp"

namespace handscan::scan {

enum class SweepBoundary : std::uint8_t { kHalfRevolution = 0, kFullRevolution = 1 };

struct SweepAssemblerConfig {
    SweepBoundary boundary = SweepBoundary::kHalfRevolution;
    double min_range_m = 0.1;  // UTM-30LX guaranteed range 0.1-30 m
    double max_range_m = 30.0;
    // Encoder samples further apart than this do not bracket a step: its angle is unknown, the
    // point is dropped and counted (a CAN dropout must not smear the cloud).
    TimeNs max_encoder_gap_ns = 50 * kNsPerMs;
    // The motion estimate is sampled this often inside a scan and interpolated per step.
    TimeNs pose_sample_period_ns = 2 * kNsPerMs;
    // A scan waits at most this long for the encoder to cover it before it is dropped.
    TimeNs max_encoder_latency_ns = 500 * kNsPerMs;
};

// The geometry the assembler needs from calibration.yaml.
struct SpinGeometry {
    Eigen::Isometry3d T_shaft_laser = Eigen::Isometry3d::Identity();
    Eigen::Isometry3d T_body_shaftbase = Eigen::Isometry3d::Identity();
    double encoder_zero_offset_rad = 0.0;  // encoder angle at which {S} coincides with {B}

    static SpinGeometry fromCalibration(const Calibration& c) {
        return {c.T_shaft_laser, c.T_camera_shaftbase, c.encoder_zero_offset_rad};
    }
    // {L} -> {C} at encoder angle `encoder_angle_rad`: T_C_B * Rz(angle - zero) * T_S_L.
    Eigen::Isometry3d bodyFromLaser(double encoder_angle_rad) const;
};

struct SweepAssemblerStats {
    std::uint64_t scans = 0;
    std::uint64_t points = 0;
    std::uint64_t dropped_invalid_range = 0;  // NaN / out of [min, max]
    std::uint64_t dropped_no_encoder = 0;     // step not bracketed by encoder samples
    std::uint64_t dropped_scans_late = 0;     // encoder never caught up
    std::uint64_t sweeps = 0;
    std::uint64_t encoder_out_of_order = 0;
};

class SweepAssembler {
public:
    SweepAssembler(const SpinGeometry& geometry, const SweepAssemblerConfig& config,
                   PoseAtFn pose_at);

    // Encoder samples must come in time order; an older one is rejected.
    [[nodiscard]] Status addEncoder(const EncoderSample& sample);
    // Scans are held until the encoder stream covers their last step.
    [[nodiscard]] Status addScan(const LaserScan& scan);
    // Completed sweeps, oldest first.
    std::vector<Sweep> takeSweeps();
    // The sweep under construction (end of a recording); empty if none.
    Sweep flush();

    const SweepAssemblerStats& stats() const { return stats_; }
    const SweepAssemblerConfig& config() const { return config_; }

private:
    void processReadyScans(bool force);
    void processScan(const LaserScan& scan);
    std::optional<double> encoderAngleAt(TimeNs t) const;
    std::int64_t boundaryIndex(double encoder_angle_rad) const;
    void startSweep(TimeNs t);
    void closeSweep();

    SpinGeometry geometry_;
    SweepAssemblerConfig config_;
    PoseAtFn pose_at_;
    std::deque<EncoderSample> encoder_;
    std::deque<LaserScan> pending_;
    std::vector<Sweep> done_;
    std::optional<Sweep> current_;
    std::int64_t current_boundary_ = 0;
    Eigen::Isometry3d T_start_world_ = Eigen::Isometry3d::Identity();
    std::uint64_t next_index_ = 0;
    SweepAssemblerStats stats_;
};

}  // namespace handscan::scan
