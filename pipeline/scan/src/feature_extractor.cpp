#include "handscan/scan/feature_extractor.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <unordered_set>

namespace handscan::scan {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Consecutive SCIP steps: a gap (error codes, dropped steps) breaks the neighbourhood.
bool contiguous(const Sweep& s, std::size_t a, std::size_t b) {
    return static_cast<int>(s.points[b].step) - static_cast<int>(s.points[a].step) ==
           static_cast<int>(b - a);
}

std::uint64_t leafKey(const Eigen::Vector3d& p, double leaf) {
    const auto q = [leaf](double v) {
        return static_cast<std::uint64_t>(static_cast<std::int64_t>(std::floor(v / leaf)) +
                                          (1 << 20)) &
               0x1FFFFF;
    };
    return (q(p.x()) << 42) | (q(p.y()) << 21) | q(p.z());
}

}  // namespace

std::vector<double> lineSmoothness(const Sweep& sweep, const ScanLine& line, int half_window) {
    const std::size_t n = line.end - line.begin;
    std::vector<double> c(n, kNaN);
    const auto hw = static_cast<std::size_t>(half_window);
    if (n < 2 * hw + 1) {
        return c;
    }
    for (std::size_t k = hw; k + hw < n; ++k) {
        const std::size_t i = line.begin + k;
        if (!contiguous(sweep, i - hw, i + hw)) {
            continue;
        }
        // eq. (12): c = |sum_j (X_i - X_j)| / (|C| * |X_i|), with |X_i| the measured range.
        Eigen::Vector3d sum = Eigen::Vector3d::Zero();
        for (std::size_t j = i - hw; j <= i + hw; ++j) {
            sum += sweep.points[i].p_start - sweep.points[j].p_start;
        }
        c[k] = sum.norm() / (2.0 * static_cast<double>(hw) * sweep.points[i].range_m);
    }
    return c;
}

FeatureCloud extractFeatures(const Sweep& sweep, const FeatureConfig& config) {
    FeatureCloud out;
    std::unordered_set<std::uint64_t> planar_leaves;
    const int hw = config.half_window;
    const double tan_incidence = std::tan(config.max_incidence_deg * M_PI / 180.0);
    for (const ScanLine& line : sweep.lines) {
        const std::size_t n = line.end - line.begin;
        const std::vector<double> c = lineSmoothness(sweep, line, hw);
        // 0 = pickable, 1 = excluded (occlusion, grazing, near), 2 = neighbour of a picked point.
        std::vector<std::uint8_t> state(n, 0);
        const double step = std::abs(line.angle_increment_rad);
        for (std::size_t k = 0; k < n; ++k) {
            const SweepPoint& p = sweep.points[line.begin + k];
            if (std::isnan(c[k]) || p.range_m < config.min_range_m) {
                state[k] = 1;
            }
        }
        for (std::size_t k = 0; k + 1 < n; ++k) {
            const std::size_t i = line.begin + k;
            if (!contiguous(sweep, i, i + 1)) {
                continue;
            }
            const double ra = sweep.points[i].range_m;
            const double rb = sweep.points[i + 1].range_m;
            // Figure 8, point B: across a depth jump the far side is the boundary of a region the
            // near object occludes; it moves as the sensor moves. Exclude the far side's window.
            if (std::abs(ra - rb) > config.occlusion_ratio * std::min(ra, rb)) {
                if (ra > rb) {
                    for (int d = 0; d <= hw && k >= static_cast<std::size_t>(d); ++d) {
                        state[k - static_cast<std::size_t>(d)] = 1;
                    }
                } else {
                    for (int d = 1; d <= hw + 1 && k + static_cast<std::size_t>(d) < n; ++d) {
                        state[k + static_cast<std::size_t>(d)] = 1;
                    }
                }
            }
        }
        for (std::size_t k = 1; k + 1 < n; ++k) {
            const std::size_t i = line.begin + k;
            if (!contiguous(sweep, i - 1, i + 1)) {
                continue;
            }
            // Figure 8, point D: the range changes fast along the line on both sides when the
            // surface is nearly parallel to the beam: |dr| / (r * dphi) = tan(incidence).
            const double r = sweep.points[i].range_m;
            const double limit = tan_incidence * r * step;
            if (std::abs(r - sweep.points[i - 1].range_m) > limit &&
                std::abs(sweep.points[i + 1].range_m - r) > limit) {
                state[k] = 1;
            }
        }

        const double edge_thr = config.edge_threshold_steps * step;
        const double planar_thr = config.planar_threshold_steps * step;
        const auto regions = static_cast<std::size_t>(std::max(1, config.regions_per_line));
        std::vector<std::size_t> order;
        for (std::size_t r = 0; r < regions; ++r) {
            const std::size_t b = n * r / regions;
            const std::size_t e = n * (r + 1) / regions;
            order.clear();
            for (std::size_t k = b; k < e; ++k) {
                if (state[k] == 0) {
                    order.push_back(k);
                }
            }
            std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t bb) {
                return c[a] > c[bb] || (c[a] == c[bb] && a < bb);
            });
            auto markNeighbours = [&](std::size_t k, int radius) {
                const std::size_t lo = k >= static_cast<std::size_t>(radius)
                                           ? k - static_cast<std::size_t>(radius)
                                           : 0;
                const std::size_t hi = std::min(n - 1, k + static_cast<std::size_t>(radius));
                for (std::size_t j = lo; j <= hi; ++j) {
                    if (state[j] == 0) {
                        state[j] = 2;
                    }
                }
            };
            int edges = 0;
            for (std::size_t k : order) {
                if (edges >= config.max_edges_per_region || c[k] <= edge_thr) {
                    break;
                }
                const double noise_c = config.edge_noise_factor * config.range_noise_m /
                                       sweep.points[line.begin + k].range_m;
                if (state[k] != 0 || c[k] <= noise_c) {
                    continue;
                }
                out.edges.push_back(sweep.points[line.begin + k].p_start);
                ++edges;
                markNeighbours(k, hw);  // no features whose neighbours are already selected
            }
            int planars = 0;
            for (auto it = order.rbegin(); it != order.rend(); ++it) {
                const std::size_t k = *it;
                if (planars >= config.max_planars_per_region || c[k] >= planar_thr) {
                    break;
                }
                if (state[k] != 0) {
                    continue;
                }
                const Eigen::Vector3d& p = sweep.points[line.begin + k].p_start;
                markNeighbours(k, 1);
                if (config.planar_leaf_m > 0.0 &&
                    !planar_leaves.insert(leafKey(p, config.planar_leaf_m)).second) {
                    continue;
                }
                out.planars.push_back(p);
                out.planar_origins.push_back(sweep.points[line.begin + k].origin_start);
                ++planars;
            }
        }
    }
    return out;
}

}  // namespace handscan::scan
