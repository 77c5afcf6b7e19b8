// The laser's raw observations for self-calibration: every kept Hokuyo step as its point in the
// laser frame {L}, its time, the encoder angle and shaft speed at that time, and the replayed
// trajectory's body pose and velocity at that time, so that the world point can be recomputed
// cheaply for any small change of the spin calibration (SpinCorrection):
//   p_W = T_W_C(t + dt_imu) * T_C_B * Rz(enc(t + dt_enc) - zero) * T_S_L * p_L
// with the trajectory and the encoder angle moved to first order in the time offsets (they are
// milliseconds; the hand turns at most a few rad/s, the shaft at 2 pi rad/s).
#pragma once

#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "handscan/core/config.hpp"
#include "handscan/core/samples.hpp"
#include "handscan/core/status.hpp"
#include "handscan/core/time.hpp"
#include "handscan/tum/tum_file.hpp"

namespace handscan::calibrate {

// Small corrections to a base calibration, the unknowns of the solve (the spin-observable set).
// Rotations of the laser on the shaft are left-multiplied in the shaft frame {S}; a rotation about
// the shaft axis is the encoder zero, so it has no parameter of its own. A shift along the shaft
// axis is a constant offset of the whole sweep in {B}, invisible to the spin, so neither.
struct SpinCorrection {
    enum Index : int {
        kRollShaft = 0,  // rad about {S} x
        kPitchShaft,     // rad about {S} y
        kShiftX,         // m along {S} x
        kShiftY,         // m along {S} y
        kEncoderZero,    // rad, added to encoder_zero_offset
        kEncoderTime,    // s the encoder's stamps are early (added to motor.tpdo_latency)
        kImuTime,        // s the IMU's stamps are early (added to xsens.frame_latency)
        kCount
    };
    using Vector = Eigen::Matrix<double, kCount, 1>;
    static const char* name(int i);
    // Display units: deg for angles, mm for shifts, ms for time offsets.
    static const char* unit(int i);
    static double displayScale(int i);
};

struct SpinObservation {
    TimeNs t = 0;
    float x_laser = 0.0F, y_laser = 0.0F;  // m, in the scan plane of {L}
    double encoder_rad = 0.0;              // interpolated encoder angle at t
    double shaft_speed_radps = 0.0;        // d(encoder)/dt at t
    Eigen::Matrix3d R_world_body = Eigen::Matrix3d::Identity();
    Eigen::Vector3d p_world_body = Eigen::Vector3d::Zero();
    Eigen::Vector3d omega_world = Eigen::Vector3d::Zero();  // rad/s of the body, world frame
    Eigen::Vector3d v_world = Eigen::Vector3d::Zero();      // m/s of the body origin
    std::uint32_t scan = 0;       // running number of the Hokuyo scan (one line of the sweep)
    std::int32_t revolution = 0;  // shaft revolution (angle under the base calibration / 2 pi)
    std::uint8_t half = 0;        // 0: first half revolution, 1: second
};

// A SpinModel at one correction, with the per-correction work done once.
struct PreparedSpin {
    Eigen::Matrix3d R_shaft_laser;
    Eigen::Vector3d t_shaft_laser;
    Eigen::Isometry3d T_body_shaftbase;
    double zero_rad = 0.0, encoder_dt_s = 0.0, imu_dt_s = 0.0;

    Eigen::Vector3d world(const SpinObservation& o) const {
        const Eigen::Vector3d p_shaft =
            R_shaft_laser * Eigen::Vector3d(o.x_laser, o.y_laser, 0.0) + t_shaft_laser;
        // The encoder stamps `encoder_dt_s` early: the angle at t is the one read at t + dt.
        const double shaft = o.encoder_rad + o.shaft_speed_radps * encoder_dt_s - zero_rad;
        const double c = std::cos(shaft), s = std::sin(shaft);
        const Eigen::Vector3d p_base(c * p_shaft.x() - s * p_shaft.y(),
                                     s * p_shaft.x() + c * p_shaft.y(), p_shaft.z());
        const Eigen::Vector3d p_world = o.R_world_body * (T_body_shaftbase * p_base);
        // Likewise the IMU-driven trajectory, to first order (dt is milliseconds).
        return p_world + imu_dt_s * o.omega_world.cross(p_world) + o.p_world_body +
               o.v_world * imu_dt_s;
    }
};

// The base calibration the corrections apply to, with its derived transforms.
struct SpinModel {
    Calibration base;
    // Time offsets already found (s) on top of those the observations were decoded and replayed
    // with: the encoder's and the IMU's stamps are this much early.
    double encoder_time_s = 0.0;
    double imu_time_s = 0.0;
    PreparedSpin prepare(const SpinCorrection::Vector& x) const;
    Eigen::Vector3d world(const SpinObservation& o, const SpinCorrection::Vector& x) const {
        return prepare(x).world(o);
    }
};

struct ObservationOptions {
    int step_stride = 4;            // keep every n-th Hokuyo step (neighbours are 0.25 deg apart)
    double min_range_m = 0.3;       // closer returns hit the operator or the rig
    double max_range_m = 20.0;      // far returns carry more angular noise than information
    double motion_margin_s = 0.05;  // trajectory must cover t +- this
};

// The motion the observations are placed with. The replayed trajectory cannot be used as it is:
// its sweeps are matched half a revolution at a time, so a calibration error that turns with the
// shaft (a shifted or tilted laser) moves each half sweep's matched pose by its own average,
// alternately one way and the other, and that zig-zag hides half of the error the halves would
// show (measured: the solve overshoots 2.2x). So the trajectory is used only at full-revolution
// boundaries, where the shaft, and so the error, is the same every time; in between the rotation
// is the gyro's (its drift spread linearly to meet the next anchor) and the position a cubic
// Hermite curve through the anchors (Catmull-Rom velocities).
tum::Trajectory revolutionMotion(const tum::Trajectory& trajectory,
                                 const std::vector<double>& revolution_starts_s,
                                 const std::vector<ImuSample>& imu,
                                 const Eigen::Matrix3d& R_body_imu);

// Pairs every kept step of `scans` (in time order) with the encoder angle (`encoder` sorted by
// time) and the motion (revolutionMotion of the trajectory and the gyro). Steps in `excluded`
// intervals (tracking not ok) are left out. The streams as the pipeline saw them: from a
// recording (calibrate's loadObservations) or buffered live (the worker's calibration check).
Result<std::vector<SpinObservation>> pairObservations(
    std::span<const LaserScan> scans, std::span<const EncoderSample> encoder,
    const Calibration& base, const tum::Trajectory& trajectory,
    const std::vector<std::pair<double, double>>& excluded_s, const std::vector<ImuSample>& imu,
    const ObservationOptions& options);

}  // namespace handscan::calibrate
