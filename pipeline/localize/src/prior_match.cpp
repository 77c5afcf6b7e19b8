#include "handscan/localize/prior_match.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

#include "handscan/core/time.hpp"
#include "handscan/scan/scan_matcher.hpp"
#include "handscan/scan/voxel_key.hpp"

namespace handscan::localize {
namespace {

struct Candidate {
    Eigen::Isometry3d T;
    double score = 0.0;  // share on the map
};

bool isCancelled(const std::atomic<bool>* cancel) {
    return cancel != nullptr && cancel->load(std::memory_order_relaxed);
}

// The change check at the accepted pose, on the stacked planar points (the ones that carry the
// laser centre that saw them, and a surface normal): a point far from every prior point where
// the earlier session's rays went through empty space into that surface has appeared; one far from
// the prior where the earlier session never looked is new ground, not a change. The stack's rays
// are handed back for the vanished check (Localizer::changes).
void countChanges(const LocalizerConfig& config, const PriorMap& prior,
                  const scan::FeatureCloud& stacked, PriorMatchOutcome& out) {
    if (stacked.planar_origins.size() != stacked.planars.size()) return;
    scan::FeatureMapPoints here;  // the stack in the prior's frame
    for (std::size_t i = 0; i < stacked.planars.size(); ++i) {
        here.planars.push_back((out.T_prior_new * stacked.planars[i]).cast<float>());
        here.planar_origins.push_back((out.T_prior_new * stacked.planar_origins[i]).cast<float>());
    }
    const std::vector<Eigen::Vector3f> normals =
        surfaceNormals(voxelTrees(here, {}), here.planars, here.planar_origins);
    const SeenSpace& seen = prior.seenSpace();
    for (std::size_t i = 0; i < here.planars.size(); ++i) {
        const Eigen::Vector3d q = here.planars[i].cast<double>();
        const Eigen::Vector3d o = here.planar_origins[i].cast<double>();
        if (!o.allFinite()) continue;
        seen.cellsAlong(o, q, out.seen_cells);
        if (!normals[i].allFinite()) continue;  // no surface to judge
        ++out.points_checked;
        if (prior.nearestDistance(q) <= config.change_m) continue;
        if (!seen.seenThrough(q, normals[i].cast<double>())) {
            ++out.new_points;
            continue;
        }
        ++out.changed_points;
        const scan::VoxelKey k = scan::voxelOf(q, config.change_cell_m);
        ++out.change_cells[{k.x(), k.y(), k.z()}];
    }
}

// 1. The grid over x, y and yaw around the guess, scored by the share on the prior map (its
// cells: gridShare), best first.
std::vector<Candidate> scoreGrid(const LocalizerConfig& config, const PriorMap& prior,
                                 const std::vector<Eigen::Vector3d>& sample,
                                 const Eigen::Isometry3d& T_guess, const std::atomic<bool>* cancel,
                                 const std::optional<Eigen::Vector3d>& pivot) {
    std::vector<Candidate> grid;
    const int nr = static_cast<int>(std::floor(config.search_radius_m / config.search_step_m));
    const int ny = static_cast<int>(std::floor(config.search_yaw_deg / config.search_yaw_step_deg));
    for (int iy = -ny; iy <= ny && !isCancelled(cancel); ++iy) {
        const double yaw = iy * config.search_yaw_step_deg * std::numbers::pi / 180.0;
        const Eigen::Matrix3d Rz =
            Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
        const Eigen::Matrix3d R = Rz * T_guess.linear();
        const Eigen::Vector3d centre =
            pivot ? Eigen::Vector3d(*pivot + Rz * (T_guess.translation() - *pivot))
                  : T_guess.translation();
        for (int ix = -nr; ix <= nr; ++ix) {
            for (int jy = -nr; jy <= nr; ++jy) {
                const Eigen::Vector2d d(ix * config.search_step_m, jy * config.search_step_m);
                if (d.norm() > config.search_radius_m + 1e-9) continue;
                Candidate c;
                c.T.linear() = R;
                c.T.translation() = centre + Eigen::Vector3d(d.x(), d.y(), 0.0);
                c.score = gridShare(config, prior, sample, c.T);
                grid.push_back(c);
            }
        }
    }
    std::stable_sort(grid.begin(), grid.end(),
                     [](const Candidate& a, const Candidate& b) { return a.score > b.score; });
    return grid;
}

}  // namespace

std::pair<double, double> separation(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
    const Eigen::Isometry3d d = a.inverse() * b;
    return {(a.translation() - b.translation()).norm(),
            Eigen::AngleAxisd(d.linear()).angle() * 180.0 / std::numbers::pi};
}

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

double shareOnMap(const LocalizerConfig& config, const PriorMap& prior,
                  const std::vector<Eigen::Vector3d>& pts, const Eigen::Isometry3d& T) {
    if (pts.empty()) return 0.0;
    const double n = static_cast<double>(pts.size());
    if (config.score_min_covered > 0.0) {
        std::size_t on = 0, covered = 0;
        for (const Eigen::Vector3d& p : pts) {
            const double d = prior.nearestDistance(T * p);
            on += d <= config.on_map_m ? 1 : 0;
            covered += d <= config.covered_m ? 1 : 0;
        }
        return static_cast<double>(on) /
               std::max(static_cast<double>(covered), config.score_min_covered * n);
    }
    const double r2 = config.on_map_m * config.on_map_m;
    std::size_t on = 0;
    Eigen::Vector3d nb;
    double d2 = 0.0;
    for (const Eigen::Vector3d& p : pts) {
        const Eigen::Vector3d q = T * p;
        for (const auto kind : {scan::FeatureKind::kPlanar, scan::FeatureKind::kEdge}) {
            if (prior.voxels().nearest(kind, q, 1, &nb, &d2) == 1 && d2 <= r2) {
                ++on;
                break;
            }
        }
    }
    return static_cast<double>(on) / n;
}

double gridShare(const LocalizerConfig& config, const PriorMap& prior,
                 const std::vector<Eigen::Vector3d>& pts, const Eigen::Isometry3d& T) {
    const NearCells& near = prior.nearCells();
    if (config.score_min_covered > 0.0 || pts.empty() ||
        std::abs(near.radius() - config.on_map_m) > 1e-9)
        return shareOnMap(config, prior, pts, T);
    std::size_t on = 0;
    for (const Eigen::Vector3d& p : pts) on += near.near(T * p) ? 1 : 0;
    return static_cast<double>(on) / static_cast<double>(pts.size());
}

PriorMatchOutcome searchLock(const LocalizerConfig& config, const PriorMap& prior,
                             const scan::FeatureCloud& stacked, const Eigen::Isometry3d& T_guess,
                             const std::atomic<bool>* cancel,
                             const std::optional<Eigen::Vector3d>& pivot) {
    const double cpu0 = threadCpuMs();
    PriorMatchOutcome out;
    out.kind = MatchKind::kLock;
    const std::vector<Candidate> grid = scoreGrid(
        config, prior, samplePoints(stacked, config.search_points), T_guess, cancel, pivot);
    // 2. The best few distinct seeds, refined by the scan matcher (robust, no prior).
    const scan::ScanMatcher matcher(config.matcher);
    std::vector<Candidate> refined;
    std::vector<Eigen::Isometry3d> seeds;
    const std::vector<Eigen::Vector3d> check = samplePoints(stacked, 4 * config.search_points);
    for (const Candidate& c : grid) {
        if (static_cast<int>(seeds.size()) >= config.refine_candidates || isCancelled(cancel))
            break;
        bool distinct = true;
        for (const Eigen::Isometry3d& s : seeds) {
            const auto [dm, ddeg] = separation(s, c.T);
            distinct = distinct && (dm > config.distinct_m || ddeg > config.distinct_deg);
        }
        if (!distinct) continue;
        seeds.push_back(c.T);
        const scan::MatchResult m = matcher.match(stacked, prior.voxels(), {}, &c.T);
        if (!m.enough_matches) continue;
        if (config.refine_max_steps > 0.0) {
            const auto [dm, ddeg] = separation(c.T, m.T_world_body);
            if (dm > config.refine_max_steps * config.search_step_m ||
                ddeg > config.refine_max_steps * config.search_yaw_step_deg)
                continue;
        }
        refined.push_back({m.T_world_body, shareOnMap(config, prior, check, m.T_world_body)});
    }
    out.cancelled = isCancelled(cancel);
    if (!refined.empty() && !out.cancelled) {
        const auto best = std::max_element(
            refined.begin(), refined.end(),
            [](const Candidate& a, const Candidate& b) { return a.score < b.score; });
        for (const Candidate& c : refined) {
            const auto [dm, ddeg] = separation(best->T, c.T);
            if (dm > config.distinct_m || ddeg > config.distinct_deg)
                out.runner_up = std::max(out.runner_up, c.score);
        }
        out.on_map = best->score;
        out.T_prior_new = best->T;
        out.accepted = best->score >= config.lock_min_on_map &&
                       best->score - out.runner_up >= config.lock_margin;
        if (out.accepted) countChanges(config, prior, stacked, out);
    }
    out.cpu_ms = threadCpuMs() - cpu0;
    return out;
}

PriorMatchOutcome trackPrior(const LocalizerConfig& config, const PriorMap& prior,
                             const scan::FeatureCloud& stacked, const Eigen::Isometry3d& T_init) {
    const double cpu0 = threadCpuMs();
    PriorMatchOutcome out;
    out.kind = MatchKind::kTrack;
    const scan::MatchResult m =
        scan::ScanMatcher(config.matcher).match(stacked, prior.voxels(), {}, &T_init);
    out.on_map = m.enough_matches
                     ? shareOnMap(config, prior, samplePoints(stacked, 4 * config.search_points),
                                  m.T_world_body)
                     : 0.0;
    const auto [dm, ddeg] = separation(T_init, m.T_world_body);
    out.correction_m = dm;
    out.T_prior_new = m.T_world_body;
    out.accepted = m.enough_matches && out.on_map >= config.track_min_on_map &&
                   dm <= config.max_correction_m && ddeg <= config.max_correction_deg;
    if (out.accepted) countChanges(config, prior, stacked, out);
    out.cpu_ms = threadCpuMs() - cpu0;
    return out;
}

}  // namespace handscan::localize
