#include "handscan/fusion/tracking_monitor.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace handscan::fusion {
namespace {

std::string format(const char* fmt, double a, double b) {
    char buf[160];
    std::snprintf(buf, sizeof buf, fmt, a, b);
    return buf;
}

double rotationAngle(const Eigen::Matrix3d& R) { return Eigen::AngleAxisd(R).angle(); }

}  // namespace

const char* lostReasonName(LostReason r) {
    switch (r) {
        case LostReason::kNone:
            return "none";
        case LostReason::kNoMatch:
            return "no_match";
        case LostReason::kMapDisagrees:
            return "map_disagrees";
        case LostReason::kPoorFit:
            return "poor_fit";
        case LostReason::kPredictionDisagrees:
            return "prediction_disagrees";
        case LostReason::kImplausibleMotion:
            return "implausible_motion";
        case LostReason::kLaserBlind:
            return "laser_blind";
        case LostReason::kImuSilent:
            return "imu_silent";
        case LostReason::kDropped:
            return "dropped";
        case LostReason::kCalibrationWrong:
            return "calibration_wrong";
    }
    return "unknown";
}

LostReason TrackingMonitor::checkMotion(const SweepEvidence& e, std::string& detail) const {
    // Speeds and accelerations across a failure (a fall, a gap) say nothing about the motion.
    if (!last_ || e.t <= last_->t || last_failure_t_ >= last_->t) return LostReason::kNone;
    const double dt = toSeconds(e.t - last_->t);
    const Eigen::Vector3d v = (e.T_world_match.translation() - last_->T.translation()) / dt;
    if (v.norm() > config_.max_speed_mps) {
        detail = format("speed %.1f m/s over %.2f s", v.norm(), dt);
        return LostReason::kImplausibleMotion;
    }
    const double rate =
        rotationAngle(last_->T.linear().transpose() * e.T_world_match.linear()) / dt;
    if (rate > config_.max_rate_radps) {
        detail = format("turn rate %.0f deg/s over %.2f s", rate * 180.0 / M_PI, dt);
        return LostReason::kImplausibleMotion;
    }
    // Acceleration only between adjacent sweeps: across a gap the mean velocities say little.
    if (before_last_ && dt < 2.0 && last_->t > before_last_->t &&
        before_last_->t > last_failure_t_) {
        const double dt0 = toSeconds(last_->t - before_last_->t);
        if (dt0 < 2.0) {
            const Eigen::Vector3d v0 =
                (last_->T.translation() - before_last_->T.translation()) / dt0;
            const double a = (v - v0).norm() / (0.5 * (dt + dt0));
            if (a > config_.max_accel_mps2) {
                detail = format("acceleration %.0f m/s^2 over %.2f s", a, 0.5 * (dt + dt0));
                return LostReason::kImplausibleMotion;
            }
        }
    }
    return LostReason::kNone;
}

LostReason TrackingMonitor::check(const SweepEvidence& e, std::string& detail) const {
    if (!e.enough_matches) {
        detail = format("%.0f correspondences for %.0f features", static_cast<double>(e.matches),
                        static_cast<double>(e.features));
        return LostReason::kNoMatch;
    }
    const double fraction =
        e.features > 0 ? static_cast<double>(e.matches) / static_cast<double>(e.features) : 0.0;
    if (fraction < config_.min_match_fraction) {
        detail = format("%.0f %% of the features found the map (at least %.0f %%)",
                        100.0 * fraction, 100.0 * config_.min_match_fraction);
        return LostReason::kMapDisagrees;
    }
    if (e.rms_m > config_.max_rms_m) {
        detail = format("rms %.1f cm from the map's surfaces (at most %.1f cm)", 100.0 * e.rms_m,
                        100.0 * config_.max_rms_m);
        return LostReason::kPoorFit;
    }
    // Without feedback since the last consistent sweep the prediction runs on the IMU and the
    // walker's prior alone: its error grows with that time, and so does the jump allowed.
    const double unfed_s = last_ ? toSeconds(e.t - last_->t) : 0.0;
    const double scale = std::max(1.0, unfed_s / 0.5);
    const Eigen::Isometry3d d = e.T_world_prior.inverse() * e.T_world_match;
    const Vector6d err = logSE3(d);
    const double sigmas = std::sqrt(std::max(0.0, err.dot(e.prior_information * err)));
    if (sigmas > scale * config_.max_prediction_sigmas) {
        char buf[160];
        std::snprintf(buf, sizeof buf,
                      "the match is %.2f m / %.1f deg (%.0f sigma) from the IMU prediction",
                      d.translation().norm(), rotationAngle(d.linear()) * 180.0 / M_PI, sigmas);
        detail = buf;
        return LostReason::kPredictionDisagrees;
    }
    return checkMotion(e, detail);
}

TrackingVerdict TrackingMonitor::assess(const SweepEvidence& e) {
    TrackingVerdict v;
    if (config_.enabled && e.founds_map && awaiting_relocalisation_) {
        // The lost sweeps' own map (LaserInertialOdometry while relocalising) is founded: still
        // lost, and nothing of it enters the scan's map.
        v.consistent = false;
        v.enters_map = false;
        v.lost = lost_;
        if (!intervals_.empty()) v.reason = intervals_.back().reason;
        if (lost_) ++intervals_.back().sweeps;
        return v;
    }
    if (!config_.enabled || e.founds_map) {
        if (e.founds_map) {
            before_last_ = last_;
            last_ = Stamped{e.t, e.T_world_match};
        }
        return v;
    }
    v.reason = check(e, v.detail);
    v.consistent = v.reason == LostReason::kNone;
    recent_.push_back(!v.consistent);
    while (static_cast<int>(recent_.size()) > config_.trip_window) recent_.pop_front();
    v.fits_map = v.consistent || v.reason == LostReason::kPredictionDisagrees;
    if (v.consistent && awaiting_relocalisation_) {
        good_run_ = 0;  // consistent with an unknown pose proves nothing yet
    } else if (v.consistent) {
        bad_run_ = 0;
        ++good_run_;
        before_last_ = last_;
        last_ = Stamped{e.t, e.T_world_match};
        if (lost_ && good_run_ >= config_.recover_after) {
            lost_ = false;
            intervals_.back().t_end = e.t;
        }
    } else {
        good_run_ = 0;
        ++bad_run_;
        ++rejected_;
        const bool trips =
            bad_run_ >= config_.trip_after ||
            std::count(recent_.begin(), recent_.end(), true) >= config_.trip_in_window ||
            v.reason == LostReason::kImplausibleMotion;
        if (!lost_ && trips) {
            lost_ = true;
            intervals_.push_back({e.t, 0, v.reason, v.detail, 0, e.t});
        }
    }
    if (lost_) ++intervals_.back().sweeps;
    // Sweeps the matcher could try on (it found correspondences) count towards giving it up,
    // sweeps that see nothing do not; it is given up at a failed one, so that a run of
    // consistent sweeps under way may still complete the recovery.
    unrecovered_ = !lost_ ? 0 : e.enough_matches ? unrecovered_ + 1 : unrecovered_;
    if (lost_ && !awaiting_relocalisation_ && config_.relocalise_after > 0 && !v.consistent &&
        unrecovered_ >= config_.relocalise_after) {
        awaiting_relocalisation_ = true;
        good_run_ = 0;
        intervals_.back().detail += "; not recovered by " +
                                    std::to_string(config_.relocalise_after) +
                                    " sweeps' matches: relocalising";
    }
    v.lost = lost_;
    // While lost, consistent sweeps only count towards recovery: the one that completes it is
    // the first to enter the map again.
    v.enters_map = v.consistent && !lost_;
    if (lost_ && v.reason == LostReason::kNone) v.reason = intervals_.back().reason;
    return v;
}

TrackingVerdict TrackingMonitor::fail(TimeNs t, TimeNs t_seen, LostReason reason,
                                      std::string detail, bool pose_unknown) {
    TrackingVerdict v;
    if (!config_.enabled) return v;
    v.consistent = false;
    v.fits_map = false;
    v.enters_map = false;
    v.reason = reason;
    v.detail = std::move(detail);
    good_run_ = 0;
    bad_run_ = std::max(bad_run_, config_.trip_after);
    last_failure_t_ = std::max(last_failure_t_, t);
    awaiting_relocalisation_ = awaiting_relocalisation_ || pose_unknown;
    if (!lost_) {
        lost_ = true;
        intervals_.push_back({t, 0, reason, v.detail, 0, t_seen});
    }
    v.lost = true;
    return v;
}

void TrackingMonitor::relocalised(TimeNs t, const std::string& detail) {
    if (!awaiting_relocalisation_) return;
    awaiting_relocalisation_ = false;
    good_run_ = 0;
    unrecovered_ = 0;
    last_failure_t_ = std::max(last_failure_t_, t);  // no motion judged across the jump
    if (!intervals_.empty()) intervals_.back().detail += "; " + detail;
}

}  // namespace handscan::fusion
