#include "handscan/worker/calibration_check.hpp"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "handscan/spin_calibration/spin_solver.hpp"

namespace handscan::worker {
namespace {

using C = calibrate::SpinCorrection;

// The size of a 2-vector and a conservative std of it: the larger axis of its covariance.
std::pair<double, double> magnitude(double a, double b, const Eigen::Matrix2d& cov) {
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(cov);
    return {std::hypot(a, b), std::sqrt(std::max(0.0, eig.eigenvalues().maxCoeff()))};
}

}  // namespace

const char* calibrationVerdictName(CalibrationVerdict v) {
    switch (v) {
        case CalibrationVerdict::kPending:
            return "pending";
        case CalibrationVerdict::kConsistent:
            return "consistent";
        case CalibrationVerdict::kWrong:
            return "wrong";
        case CalibrationVerdict::kUnchecked:
            return "unchecked";
    }
    return "unknown";
}

CalibrationCheck::CalibrationCheck(const CalibrationCheckConfig& config,
                                   const Calibration& calibration)
    : config_(config), calibration_(calibration), next_check_s_(config.first_check_s) {
    if (!config_.enabled) report_.verdict = CalibrationVerdict::kUnchecked;
}

void CalibrationCheck::addImu(const ImuSample& s) {
    if (report_.verdict == CalibrationVerdict::kPending) imu_.push_back(s);
}

void CalibrationCheck::addEncoder(const EncoderSample& s) {
    if (report_.verdict == CalibrationVerdict::kPending) encoder_.push_back(s);
}

void CalibrationCheck::addScan(const LaserScan& s) {
    if (report_.verdict != CalibrationVerdict::kPending) return;
    if (first_scan_ == 0) first_scan_ = s.t_host;
    last_scan_ = std::max(last_scan_, s.t_host);
    scans_.push_back(s);
}

void CalibrationCheck::addTrajectoryPose(const PoseEstimate& p) {
    if (report_.verdict != CalibrationVerdict::kPending || p.tracking_lost) return;
    const double t = toSeconds(p.t_host);
    if (!trajectory_.empty() && t <= trajectory_.back().t_s) return;
    trajectory_.push_back({t, p.T_world_body});
}

void CalibrationCheck::addSweep(TimeNs t_start, TimeNs t_end, bool trusted, bool lost) {
    if (report_.verdict != CalibrationVerdict::kPending) return;
    if (!trusted) untrusted_s_.emplace_back(toSeconds(t_start), toSeconds(t_end));
    lost_ = lost;
}

CalibrationVerdict CalibrationCheck::update() {
    if (report_.verdict != CalibrationVerdict::kPending || first_scan_ == 0) return report_.verdict;
    const double elapsed_s = toSeconds(last_scan_ - first_scan_);
    // Lost before the check: at once, on what was tracked (once per scan; the trajectory of a
    // lost stretch is a guess and does not grow the check's).
    const bool at_loss = lost_ && !checked_at_loss_;
    if (!at_loss && elapsed_s < next_check_s_) return report_.verdict;
    if (at_loss) checked_at_loss_ = true;
    // Due: the scan waits no longer, even with nothing tracked to check yet.
    first_due_passed_ = true;
    if (trajectory_.size() >= 2) attempt(elapsed_s);
    if (report_.verdict == CalibrationVerdict::kPending) {
        next_check_s_ = std::max(next_check_s_, elapsed_s + config_.retry_period_s);
        if (elapsed_s >= config_.give_up_s) {
            report_.verdict = CalibrationVerdict::kUnchecked;
            report_.message = fmt::format(
                "calibration not checked: the first {:.0f} s did not determine the laser on its "
                "shaft ({} half-to-half planes); walk past walls at a few metres",
                elapsed_s, report_.residuals);
        }
    }
    if (report_.verdict != CalibrationVerdict::kPending) release();
    return report_.verdict;
}

void CalibrationCheck::giveUp() {
    if (report_.verdict != CalibrationVerdict::kPending) return;
    report_.verdict = CalibrationVerdict::kUnchecked;
    report_.message = "calibration not checked: the scan ended before the check could decide";
    release();
}

void CalibrationCheck::attempt(double elapsed_s) {
    const double cpu0 = threadCpuMs();
    ++report_.attempts;
    report_.checked_after_s = elapsed_s;
    // The encoder as the sweep assembler reads it: in time order.
    std::stable_sort(
        encoder_.begin(), encoder_.end(),
        [](const EncoderSample& a, const EncoderSample& b) { return a.t_host < b.t_host; });
    auto obs = calibrate::pairObservations(scans_, encoder_, calibration_, trajectory_,
                                           untrusted_s_, imu_, calibrate::ObservationOptions{});
    report_.residuals = 0;
    if (obs.isOk()) {
        const calibrate::SpinModel model{calibration_};
        const auto residuals = calibrate::associateHalves(*obs, model, C::Vector::Zero(),
                                                          calibrate::AssociationOptions{});
        report_.residuals = residuals.size();
        if (residuals.size() >= config_.min_residuals) {
            calibrate::SpinMask geometry{};
            geometry[C::kRollShaft] = geometry[C::kPitchShaft] = true;
            geometry[C::kShiftX] = geometry[C::kShiftY] = true;
            const calibrate::SpinSolution s =
                calibrate::solveSpin(*obs, model, residuals, geometry, calibrate::SolverOptions{});
            std::tie(report_.rotation_rad, report_.rotation_std_rad) =
                magnitude(s.x[C::kRollShaft], s.x[C::kPitchShaft],
                          s.covariance.block<2, 2>(C::kRollShaft, C::kRollShaft));
            std::tie(report_.shift_m, report_.shift_std_m) = magnitude(
                s.x[C::kShiftX], s.x[C::kShiftY], s.covariance.block<2, 2>(C::kShiftX, C::kShiftX));
            report_.sigma_before_m = s.robust_sigma_before_m;
            report_.sigma_after_m = s.robust_sigma_after_m;
            const double k = config_.significance;
            const bool rotation_off = report_.rotation_rad >= config_.max_rotation_rad &&
                                      report_.rotation_rad >= k * report_.rotation_std_rad;
            const bool shift_off = report_.shift_m >= config_.max_shift_m &&
                                   report_.shift_m >= k * report_.shift_std_m;
            const bool explains =
                report_.sigma_after_m <= (1.0 - config_.min_improvement) * report_.sigma_before_m;
            if ((rotation_off || shift_off) && explains) {
                report_.verdict = CalibrationVerdict::kWrong;
                // Short enough for the status line (shm::kTextChars); the log says more.
                report_.message = fmt::format(
                    "calibration wrong: laser {:.1f} deg, {:.0f} mm off; nothing mapped: stop "
                    "and calibrate",
                    report_.rotation_rad * 180.0 / M_PI, report_.shift_m * 1e3);
            } else if (report_.rotation_std_rad <= config_.max_rotation_rad / 3.0) {
                report_.verdict = CalibrationVerdict::kConsistent;
                report_.message = fmt::format(
                    "calibration consistent: the laser within {:.2f} +- {:.2f} deg of its place",
                    report_.rotation_rad * 180.0 / M_PI, report_.rotation_std_rad * 180.0 / M_PI);
            }
        }
    }
    report_.solve_ms = threadCpuMs() - cpu0;
}

void CalibrationCheck::release() {
    imu_ = {};
    encoder_ = {};
    scans_ = {};
    trajectory_ = {};
    untrusted_s_ = {};
}

}  // namespace handscan::worker
