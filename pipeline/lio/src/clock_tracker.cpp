#include "handscan/lio/clock_tracker.hpp"

#include <algorithm>
#include <cmath>

namespace handscan::lio {
namespace {

// Pairs of trusted sweeps this many sweeps apart: 1 (half a turn) and 4 (two turns, more rotation
// per pair), as calibrate's alignment.
constexpr std::uint64_t kGaps[] = {1, 4};
// Beyond these a solution is a solver running off, not a clock (see update()).
constexpr double kPlausibleTimeS = 0.05;
constexpr double kPlausibleTurnRad = 5.0 * M_PI / 180.0;

double clampToward(double current, double target, double max_step) {
    return current + std::clamp(target - current, -max_step, max_step);
}

}  // namespace

ClockTracker::ClockTracker(const ClockTrackerConfig& config, const Eigen::Matrix3d& R_body_imu,
                           const Eigen::Vector3d& axis_body)
    : config_(config), R_body_imu_(R_body_imu), axis_(axis_body.normalized()) {
    stats_.imu_offset_s = config_.configured_imu_offset_s;
    stats_.encoder_offset_s = config_.configured_encoder_offset_s;
    if (!config_.enabled) return;
    stats_.imu_offset_s = clampImu(config_.start_imu_offset_s);
    stats_.encoder_offset_s = clampEncoder(config_.start_encoder_offset_s);
}

double ClockTracker::clampImu(double offset_s) const {
    return std::clamp(offset_s, config_.configured_imu_offset_s - config_.imu_bound_s,
                      config_.configured_imu_offset_s + config_.imu_bound_s);
}

double ClockTracker::clampEncoder(double offset_s) const {
    return std::clamp(offset_s, config_.configured_encoder_offset_s - config_.encoder_bound_s,
                      config_.configured_encoder_offset_s + config_.encoder_bound_s);
}

void ClockTracker::addImu(const ImuSample& raw) {
    if (!config_.enabled) return;
    if (!imu_.empty() && raw.t_host <= imu_.back().t_host) return;
    if (!raw.gyro_radps_imu.allFinite()) return;
    imu_.push_back(raw);
    // The window's pairs reach back window_s from the newest sweep, plus a pair's span.
    const TimeNs keep = fromSeconds(config_.window_s + 5.0);
    while (!imu_.empty() && imu_.front().t_host < raw.t_host - keep) imu_.pop_front();
}

void ClockTracker::addEncoder(const EncoderSample& raw) {
    if (!config_.enabled || !std::isfinite(raw.speed_radps)) return;
    // A few seconds' mean: the drive holds the speed within ~2 %.
    shaft_speed_radps_ += 0.01 * (raw.speed_radps - shaft_speed_radps_);
    stats_.shaft_speed_radps = shaft_speed_radps_;
}

void ClockTracker::addSweep(std::uint64_t ordinal, TimeNs t_start,
                            const Eigen::Quaterniond& q_world_body, bool trusted) {
    if (!config_.enabled || !trusted || !q_world_body.coeffs().allFinite()) return;
    // The turn the encoder offset applied at the time amounts to (see update()).
    const double applied_turn = -shaft_speed_radps_ * stats_.encoder_offset_s;
    sweeps_.push_back({ordinal, toSeconds(t_start), q_world_body.normalized(), applied_turn});
    while (!sweeps_.empty() && sweeps_.front().t_s < sweeps_.back().t_s - config_.window_s)
        sweeps_.pop_front();
}

imu::HandEyeProblem ClockTracker::problem(double t_from_s) const {
    imu::HandEyeProblem p;
    // Priors a few times the bounds: they decide nothing the data determine, and hold what the
    // data do not (see HandEyeProblem::prior_sigma).
    p.prior_sigma[imu::kHandEyeTurn] = kPlausibleTurnRad;
    p.prior_sigma[imu::kHandEyeImuTime] = kPlausibleTimeS;
    p.R_body_imu = R_body_imu_;
    p.axis_body = axis_;
    for (const ImuSample& s : imu_) {
        if (toSeconds(s.t_host) < t_from_s - 1.0) continue;
        p.imu.push_back(s);
        p.t_s.push_back(toSeconds(s.t_host));
    }
    if (p.t_s.size() < 2) return p;
    // Only pairs the gyro covers with a margin for the time offset being solved.
    const double lo = p.t_s.front() + 0.05, hi = p.t_s.back() - 0.05;
    for (std::size_t i = 0; i < sweeps_.size(); ++i)
        for (std::uint64_t gap : kGaps)
            for (std::size_t j = i + 1; j < sweeps_.size() && j <= i + gap; ++j)
                if (sweeps_[j].ordinal == sweeps_[i].ordinal + gap && sweeps_[i].t_s > lo &&
                    sweeps_[j].t_s < hi)
                    p.pairs.push_back({sweeps_[i].t_s, sweeps_[j].t_s,
                                       (sweeps_[i].q.conjugate() * sweeps_[j].q).toRotationMatrix(),
                                       sweeps_[i].applied_turn_rad, sweeps_[j].applied_turn_rad});
    return p;
}

bool ClockTracker::update(TimeNs now) {
    const double t = toSeconds(now);
    if (!config_.enabled || sweeps_.empty() || t - last_solve_s_ < config_.update_period_s ||
        sweeps_.back().t_s <= last_solved_sweep_s_)
        return false;
    const imu::HandEyeProblem p = problem(sweeps_.front().t_s);
    if (p.pairs.size() < config_.min_pairs) return false;
    last_solve_s_ = t;
    last_solved_sweep_s_ = sweeps_.back().t_s;
    ++stats_.solves;
    imu::HandEyeCovariance covariance;
    const imu::HandEyeParams x = imu::solveHandEye(p, x_, &covariance);
    stats_.pairs = p.pairs.size();
    const auto rms = [](const Eigen::VectorXd& r) {
        return std::sqrt(r.squaredNorm() /
                         static_cast<double>(std::max<Eigen::Index>(1, r.size())));
    };
    stats_.rms_before_rad = rms(imu::handEyeResiduals(p, x_));
    stats_.rms_after_rad = rms(imu::handEyeResiduals(p, x));
    // A solve without information (a still scanner: no rotation, no clock to see) can run off on
    // a flat residual to any value with a small formal std (seen in a daemon test: an IMU offset
    // of 1e10 s). No latency is ever tens of milliseconds or turns a sweep by degrees, and a
    // solution must fit better than where it started: otherwise the clocks hold and the next
    // solve starts afresh.
    const bool plausible = x.allFinite() && covariance.allFinite() &&
                           std::abs(x[imu::kHandEyeImuTime]) <= kPlausibleTimeS &&
                           std::abs(x[imu::kHandEyeTurn]) <= kPlausibleTurnRad &&
                           covariance(imu::kHandEyeImuTime, imu::kHandEyeImuTime) > 0.0 &&
                           covariance(imu::kHandEyeTurn, imu::kHandEyeTurn) > 0.0 &&
                           stats_.rms_after_rad <= 1.05 * stats_.rms_before_rad + 1e-9;
    if (!plausible) {
        x_.setZero();
        ++stats_.rejected_solves;
        stats_.imu_std_s = stats_.turn_std_rad = std::numeric_limits<double>::infinity();
        return false;
    }
    x_ = x;
    stats_.imu_std_s =
        config_.std_inflation * std::sqrt(covariance(imu::kHandEyeImuTime, imu::kHandEyeImuTime));
    stats_.turn_std_rad =
        config_.std_inflation * std::sqrt(covariance(imu::kHandEyeTurn, imu::kHandEyeTurn));
    const double before_imu = stats_.imu_offset_s, before_enc = stats_.encoder_offset_s;
    bool determined = false;
    if (stats_.imu_std_s <= config_.max_imu_std_s) {
        determined = true;
        const double want = x[imu::kHandEyeImuTime];
        stats_.imu_target_s = want;
        stats_.imu_at_bound = clampImu(want) != want;
        stats_.imu_offset_s = clampToward(stats_.imu_offset_s, clampImu(want), config_.max_step_s);
    }
    // A turn eps added to the encoder zero equals stamps moved by -eps / speed (angle(t) + w s
    // = angle(t) - eps): the offset to subtract from the encoder's stamps.
    if (stats_.turn_std_rad <= config_.max_turn_std_rad &&
        std::abs(shaft_speed_radps_) >= config_.min_shaft_speed_radps) {
        determined = true;
        const double want = -x[imu::kHandEyeTurn] / shaft_speed_radps_;
        stats_.encoder_target_s = want;
        stats_.encoder_at_bound = clampEncoder(want) != want;
        stats_.encoder_offset_s =
            clampToward(stats_.encoder_offset_s, clampEncoder(want), config_.max_step_s);
    }
    if (determined) ++stats_.determined;
    return stats_.imu_offset_s != before_imu || stats_.encoder_offset_s != before_enc;
}

}  // namespace handscan::lio
