#include "handscan/spin_calibration/spin_observations.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <variant>

#include "handscan/core/se3.hpp"
#include "handscan/imu/gyro_hand_eye.hpp"
#include "handscan/tum/trajectory_pose.hpp"

namespace handscan::calibrate {

const char* SpinCorrection::name(int i) {
    static const char* const kNames[kCount] = {"laser roll about shaft x",
                                               "laser pitch about shaft y",
                                               "laser shift along shaft x",
                                               "laser shift along shaft y",
                                               "encoder zero",
                                               "encoder time offset",
                                               "IMU time offset"};
    return i >= 0 && i < kCount ? kNames[i] : "?";
}

const char* SpinCorrection::unit(int i) {
    if (i == kShiftX || i == kShiftY) return "mm";
    if (i == kEncoderTime || i == kImuTime) return "ms";
    return "deg";
}

double SpinCorrection::displayScale(int i) {
    if (i == kShiftX || i == kShiftY || i == kEncoderTime || i == kImuTime) return 1e3;
    return 180.0 / std::numbers::pi;
}

PreparedSpin SpinModel::prepare(const SpinCorrection::Vector& x) const {
    using C = SpinCorrection;
    PreparedSpin p;
    p.R_shaft_laser = expSO3(Eigen::Vector3d(x[C::kRollShaft], x[C::kPitchShaft], 0.0)) *
                      base.T_shaft_laser.linear();
    p.t_shaft_laser =
        base.T_shaft_laser.translation() + Eigen::Vector3d(x[C::kShiftX], x[C::kShiftY], 0.0);
    p.T_body_shaftbase = base.T_camera_shaftbase;
    p.zero_rad = base.encoder_zero_offset_rad + x[C::kEncoderZero];
    p.encoder_dt_s = encoder_time_s + x[C::kEncoderTime];
    p.imu_dt_s = imu_time_s + x[C::kImuTime];
    return p;
}

namespace {

bool excluded(double t_s, const std::vector<std::pair<double, double>>& intervals) {
    return std::any_of(intervals.begin(), intervals.end(),
                       [&](const auto& iv) { return t_s >= iv.first && t_s < iv.second; });
}

// Times at which the shaft angle (encoder - zero) crosses a whole turn.
std::vector<double> revolutionStarts(std::span<const EncoderSample> enc, double zero_rad) {
    std::vector<double> out;
    const double turn = 2.0 * std::numbers::pi;
    for (std::size_t i = 1; i < enc.size(); ++i) {
        const double a = (enc[i - 1].angle_rad - zero_rad) / turn;
        const double b = (enc[i].angle_rad - zero_rad) / turn;
        if (std::floor(b) > std::floor(a) && b > a) {
            const double u = (std::floor(b) - a) / (b - a);
            out.push_back(toSeconds(enc[i - 1].t_host) +
                          u * toSeconds(enc[i].t_host - enc[i - 1].t_host));
        }
    }
    return out;
}

}  // namespace

tum::Trajectory revolutionMotion(const tum::Trajectory& trajectory,
                                 const std::vector<double>& starts,
                                 const std::vector<ImuSample>& imu,
                                 const Eigen::Matrix3d& R_body_imu) {
    tum::Trajectory out;
    if (starts.size() < 2 || imu.size() < 2 || trajectory.size() < 2) return out;
    std::vector<double> t_imu(imu.size());
    for (std::size_t i = 0; i < imu.size(); ++i) t_imu[i] = toSeconds(imu[i].t_host);
    std::vector<Eigen::Isometry3d> anchor(starts.size());
    for (std::size_t k = 0; k < starts.size(); ++k) anchor[k] = tum::poseAt(trajectory, starts[k]);
    auto velocity = [&](std::size_t k) {
        const std::size_t a = k == 0 ? 0 : k - 1, b = std::min(k + 1, starts.size() - 1);
        return Eigen::Vector3d((anchor[b].translation() - anchor[a].translation()) /
                               (starts[b] - starts[a]));
    };
    constexpr double kGrid_s = 0.0025;
    for (std::size_t k = 0; k + 1 < starts.size(); ++k) {
        const double t0 = starts[k], t1 = starts[k + 1], h = t1 - t0;
        const Eigen::Matrix3d R0 = anchor[k].linear();
        const Eigen::Matrix3d drift =
            (R0 *
             handscan::imu::integrateGyro(imu, t_imu, t0, t1, R_body_imu, Eigen::Vector3d::Zero()))
                .transpose() *
            anchor[k + 1].linear();
        const Eigen::Vector3d drift_log = logSO3(drift);
        const Eigen::Vector3d p0 = anchor[k].translation(), p1 = anchor[k + 1].translation();
        const Eigen::Vector3d v0 = velocity(k), v1 = velocity(k + 1);
        Eigen::Matrix3d G = Eigen::Matrix3d::Identity();
        double t_prev = t0;
        const int n = std::max(1, static_cast<int>(std::ceil(h / kGrid_s)));
        for (int i = 0; i < n; ++i) {
            const double t = t0 + h * i / n, s = (t - t0) / h;
            G = G * handscan::imu::integrateGyro(imu, t_imu, t_prev, t, R_body_imu,
                                                 Eigen::Vector3d::Zero());
            t_prev = t;
            tum::StampedPose p;
            p.t_s = t;
            p.T.linear() = orthonormalize(R0 * G * expSO3(s * drift_log));
            const double s2 = s * s, s3 = s2 * s;
            p.T.translation() = (2 * s3 - 3 * s2 + 1) * p0 + (s3 - 2 * s2 + s) * h * v0 +
                                (-2 * s3 + 3 * s2) * p1 + (s3 - s2) * h * v1;
            out.push_back(p);
        }
    }
    tum::StampedPose last;
    last.t_s = starts.back();
    last.T = anchor.back();
    out.push_back(last);
    return out;
}

Result<std::vector<SpinObservation>> pairObservations(
    std::span<const LaserScan> scans, std::span<const EncoderSample> enc, const Calibration& base,
    const tum::Trajectory& replayed, const std::vector<std::pair<double, double>>& excluded_s,
    const std::vector<ImuSample>& imu, const ObservationOptions& opt) {
    if (replayed.size() < 2)
        return Status{StatusCode::kInvalidArgument, "calibrate: the replayed trajectory is empty"};
    const tum::Trajectory trajectory =
        revolutionMotion(replayed, revolutionStarts(enc, base.encoder_zero_offset_rad), imu,
                         base.T_camera_imu().linear());
    if (trajectory.size() < 2)
        return Status{StatusCode::kInvalidArgument,
                      "the shaft did not turn twice inside the replayed trajectory"};
    const double t_first = trajectory.front().t_s + opt.motion_margin_s;
    const double t_last = trajectory.back().t_s - opt.motion_margin_s;
    constexpr double kVelocityStep_s = 0.005;  // the trajectory's 200 Hz period
    constexpr TimeNs kMaxEncoderGap = 50 * kNsPerMs;

    std::vector<SpinObservation> out;
    std::uint32_t scan_number = 0;
    for (const LaserScan& scan : scans) {
        ++scan_number;
        for (std::size_t i = 0; i < scan.size(); i += static_cast<std::size_t>(opt.step_stride)) {
            const float r = scan.ranges_m[i];
            if (!std::isfinite(r) || r < opt.min_range_m || r > opt.max_range_m) continue;
            const TimeNs t = scan.stepTime(i);
            const double t_s = toSeconds(t);
            if (t_s < t_first || t_s > t_last || excluded(t_s, excluded_s)) continue;
            auto b =
                std::lower_bound(enc.begin(), enc.end(), t,
                                 [](const EncoderSample& e, TimeNs v) { return e.t_host < v; });
            if (b == enc.begin() || b == enc.end()) continue;
            const auto a = b - 1;
            if (b->t_host - a->t_host > kMaxEncoderGap) continue;
            SpinObservation o;
            o.t = t;
            o.scan = scan_number;
            const double a_rad = scan.stepAngle(i);
            o.x_laser = static_cast<float>(r * std::cos(a_rad));
            o.y_laser = static_cast<float>(r * std::sin(a_rad));
            const double span_s = toSeconds(b->t_host - a->t_host);
            o.shaft_speed_radps = (b->angle_rad - a->angle_rad) / span_s;
            o.encoder_rad = a->angle_rad + o.shaft_speed_radps * toSeconds(t - a->t_host);
            const Eigen::Isometry3d T = tum::poseAt(trajectory, t_s);
            const Eigen::Isometry3d T_minus = tum::poseAt(trajectory, t_s - kVelocityStep_s);
            const Eigen::Isometry3d T_plus = tum::poseAt(trajectory, t_s + kVelocityStep_s);
            o.R_world_body = T.linear();
            o.p_world_body = T.translation();
            o.omega_world =
                logSO3(T_plus.linear() * T_minus.linear().transpose()) / (2.0 * kVelocityStep_s);
            o.v_world = (T_plus.translation() - T_minus.translation()) / (2.0 * kVelocityStep_s);
            const double half_turns =
                std::floor((o.encoder_rad - base.encoder_zero_offset_rad) / std::numbers::pi);
            const auto h = static_cast<std::int64_t>(half_turns);
            o.revolution = static_cast<std::int32_t>(h >= 0 ? h / 2 : (h - 1) / 2);
            o.half = static_cast<std::uint8_t>(h - 2 * static_cast<std::int64_t>(o.revolution));
            out.push_back(o);
        }
    }
    if (out.empty())
        return Status{StatusCode::kInvalidArgument,
                      "no laser step falls inside the replayed trajectory where tracking was ok; "
                      "nothing to calibrate from"};
    return out;
}

}  // namespace handscan::calibrate
