#include "handscan/localize/localizer.hpp"

#include <time.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

#include "handscan/core/se3.hpp"

namespace handscan::localize {
namespace {

double threadCpuMs() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) * 1e3 + static_cast<double>(ts.tv_nsec) * 1e-6;
}

// Translation (m) and rotation (deg) between two poses.
std::pair<double, double> separation(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
    const Eigen::Isometry3d d = a.inverse() * b;
    return {(a.translation() - b.translation()).norm(),
            Eigen::AngleAxisd(d.linear()).angle() * 180.0 / std::numbers::pi};
}

}  // namespace

std::vector<Eigen::Vector3d> samplePoints(const scan::FeatureCloud& cloud, int count) {
    const std::size_t n = cloud.edges.size() + cloud.planars.size();
    std::vector<Eigen::Vector3d> out;
    if (n == 0 || count <= 0) return out;
    const double stride = std::max(1.0, static_cast<double>(n) / count);
    for (double i = 0; i < static_cast<double>(n); i += stride) {
        const auto k = static_cast<std::size_t>(i);
        out.push_back(k < cloud.edges.size() ? cloud.edges[k]
                                             : cloud.planars[k - cloud.edges.size()]);
    }
    return out;
}

Localizer::Localizer(const LocalizerConfig& config, std::shared_ptr<const PriorMap> prior,
                     std::optional<Eigen::Isometry3d> hint)
    : config_(config),
      prior_(std::move(prior)),
      hint_(std::move(hint)),
      matcher_(config.matcher),
      stack_(config.stack) {}

double Localizer::onMap(const std::vector<Eigen::Vector3d>& pts, const Eigen::Isometry3d& T) const {
    if (pts.empty()) return 0.0;
    const double r2 = config_.on_map_m * config_.on_map_m;
    std::size_t on = 0;
    Eigen::Vector3d nb;
    double d2 = 0.0;
    for (const Eigen::Vector3d& p : pts) {
        const Eigen::Vector3d q = T * p;
        for (const auto kind : {scan::FeatureKind::kPlanar, scan::FeatureKind::kEdge}) {
            if (prior_->voxels().nearest(kind, q, 1, &nb, &d2) == 1 && d2 <= r2) {
                ++on;
                break;
            }
        }
    }
    return static_cast<double>(on) / static_cast<double>(pts.size());
}

bool Localizer::addSweep(TimeNs t_start, const Eigen::Isometry3d& T_odom_body,
                         std::shared_ptr<const scan::FeatureCloud> features) {
    if (!have_first_) {
        // The hint (or the prior session's start) is where this session's first sweep began.
        have_first_ = true;
        T_prior_odom_ = (hint_ ? *hint_ : prior_->start()) * T_odom_body.inverse();
        last_attempt_t_ = t_start;
    }
    stack_.add(t_start, T_odom_body, std::move(features));
    // A full stack before each match (the first one too: one still sweep sees little).
    if (t_start - last_attempt_t_ < static_cast<TimeNs>(config_.period_s * 1e9)) return false;
    last_attempt_t_ = t_start;
    const double cpu0 = threadCpuMs();
    const scan::FeatureCloud stacked = stack_.stack();
    const Eigen::Isometry3d T_odom_new = stack_.newestPose();
    ++stats_.attempts;
    bool changed = false;
    if (!locked_) {
        ++stats_.lock_attempts;
        tryLock(stacked, T_odom_new);
        changed = locked_;
        if (locked_) stats_.t_lock = t_start;
    } else {
        changed = track(stacked, T_odom_new);
    }
    const double ms = threadCpuMs() - cpu0;
    stats_.cpu_ms += ms;
    stats_.max_attempt_ms = std::max(stats_.max_attempt_ms, ms);
    return changed;
}

void Localizer::tryLock(const scan::FeatureCloud& stacked, const Eigen::Isometry3d& T_odom_new) {
    const Eigen::Isometry3d T_guess = T_prior_odom_ * T_odom_new;
    const std::vector<Eigen::Vector3d> sample = samplePoints(stacked, config_.search_points);
    // 1. Grid over x, y and yaw around the guess, scored by the share on the prior map.
    std::vector<Candidate> grid;
    const int nr = static_cast<int>(std::floor(config_.search_radius_m / config_.search_step_m));
    const int ny =
        static_cast<int>(std::floor(config_.search_yaw_deg / config_.search_yaw_step_deg));
    for (int iy = -ny; iy <= ny; ++iy) {
        const double yaw = iy * config_.search_yaw_step_deg * std::numbers::pi / 180.0;
        const Eigen::Matrix3d R =
            Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix() * T_guess.linear();
        for (int ix = -nr; ix <= nr; ++ix) {
            for (int jy = -nr; jy <= nr; ++jy) {
                const Eigen::Vector2d d(ix * config_.search_step_m, jy * config_.search_step_m);
                if (d.norm() > config_.search_radius_m + 1e-9) continue;
                Candidate c;
                c.T.linear() = R;
                c.T.translation() = T_guess.translation() + Eigen::Vector3d(d.x(), d.y(), 0.0);
                c.score = onMap(sample, c.T);
                grid.push_back(c);
            }
        }
    }
    std::stable_sort(grid.begin(), grid.end(),
                     [](const Candidate& a, const Candidate& b) { return a.score > b.score; });
    // 2. The best few distinct seeds, refined by the scan matcher (robust, no prior).
    std::vector<Candidate> refined;
    std::vector<Eigen::Isometry3d> seeds;
    const std::vector<Eigen::Vector3d> check = samplePoints(stacked, 4 * config_.search_points);
    for (const Candidate& c : grid) {
        if (static_cast<int>(seeds.size()) >= config_.refine_candidates) break;
        bool distinct = true;
        for (const Eigen::Isometry3d& s : seeds) {
            const auto [dm, ddeg] = separation(s, c.T);
            distinct = distinct && (dm > config_.distinct_m || ddeg > config_.distinct_deg);
        }
        if (!distinct) continue;
        seeds.push_back(c.T);
        const scan::MatchResult m = matcher_.match(stacked, prior_->voxels(), {}, &c.T);
        if (!m.enough_matches) continue;
        refined.push_back({m.T_world_body, onMap(check, m.T_world_body)});
    }
    if (refined.empty()) return;
    const auto best =
        std::max_element(refined.begin(), refined.end(),
                         [](const Candidate& a, const Candidate& b) { return a.score < b.score; });
    double runner_up = 0.0;
    for (const Candidate& c : refined) {
        const auto [dm, ddeg] = separation(best->T, c.T);
        if (dm > config_.distinct_m || ddeg > config_.distinct_deg)
            runner_up = std::max(runner_up, c.score);
    }
    stats_.last_on_map = best->score;
    stats_.lock_on_map = best->score;
    stats_.lock_runner_up = runner_up;
    if (best->score < config_.lock_min_on_map || best->score - runner_up < config_.lock_margin)
        return;
    locked_ = true;
    T_prior_odom_ = best->T * T_odom_new.inverse();
    T_prior_odom_.linear() = orthonormalize(T_prior_odom_.linear());
    recordChanges(stacked, best->T);
}

bool Localizer::track(const scan::FeatureCloud& stacked, const Eigen::Isometry3d& T_odom_new) {
    const Eigen::Isometry3d T_init = T_prior_odom_ * T_odom_new;
    const scan::MatchResult m = matcher_.match(stacked, prior_->voxels(), {}, &T_init);
    const double on = m.enough_matches
                          ? onMap(samplePoints(stacked, 4 * config_.search_points), m.T_world_body)
                          : 0.0;
    stats_.last_on_map = on;
    const auto [dm, ddeg] = separation(T_init, m.T_world_body);
    if (!m.enough_matches || on < config_.track_min_on_map || dm > config_.max_correction_m ||
        ddeg > config_.max_correction_deg) {
        ++stats_.rejected_updates;
        return false;
    }
    ++stats_.updates;
    stats_.max_correction_m = std::max(stats_.max_correction_m, dm);
    stats_.sum_correction_m += dm;
    T_prior_odom_ = m.T_world_body * T_odom_new.inverse();
    T_prior_odom_.linear() = orthonormalize(T_prior_odom_.linear());
    recordChanges(stacked, m.T_world_body);
    return true;
}

void Localizer::recordChanges(const scan::FeatureCloud& stacked,
                              const Eigen::Isometry3d& T_prior_new) {
    auto check = [&](const Eigen::Vector3d& p_body) {
        const Eigen::Vector3d q = T_prior_new * p_body;
        const double d = prior_->nearestDistance(q);
        ++stats_.points_checked;
        if (d > config_.covered_m) {
            ++stats_.new_points;
        } else if (d > config_.change_m) {
            ++stats_.changed_points;
            const scan::VoxelKey k = scan::voxelOf(q, config_.change_cell_m);
            ++change_cells_[{k.x(), k.y(), k.z()}];
        }
    };
    for (const Eigen::Vector3d& p : stacked.edges) check(p);
    for (const Eigen::Vector3d& p : stacked.planars) check(p);
}

std::vector<ChangeCell> Localizer::changes() const {
    std::vector<ChangeCell> out;
    for (const auto& [k, n] : change_cells_) {
        if (n < static_cast<std::uint64_t>(config_.change_cell_min_points)) continue;
        const auto [x, y, z] = k;
        out.push_back({(Eigen::Vector3d(x, y, z).array() + 0.5) * config_.change_cell_m, n});
    }
    return out;
}

}  // namespace handscan::localize
