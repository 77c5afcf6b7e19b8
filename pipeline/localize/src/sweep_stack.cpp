#include "handscan/localize/sweep_stack.hpp"

#include <unordered_set>

#include "handscan/scan/voxel_key.hpp"

namespace handscan::localize {

void SweepStack::add(TimeNs t_start, const Eigen::Isometry3d& T_odom_body,
                     std::shared_ptr<const scan::FeatureCloud> features) {
    if (!features) return;
    sweeps_.push_back({t_start, T_odom_body, std::move(features)});
    const auto span = static_cast<TimeNs>(config_.span_s * 1e9);
    while (sweeps_.size() > 1 && sweeps_.front().t < t_start - span) sweeps_.pop_front();
}

scan::FeatureCloud SweepStack::stack() const {
    scan::FeatureCloud out;
    if (sweeps_.empty()) return out;
    const Eigen::Isometry3d T_new_odom = sweeps_.back().T.inverse();
    std::unordered_set<scan::VoxelKey, scan::VoxelKeyHash> edge_cells, planar_cells;
    // Newest first: where sweeps overlap, the one closest to the matched pose is kept.
    for (auto it = sweeps_.rbegin(); it != sweeps_.rend(); ++it) {
        const Eigen::Isometry3d T = T_new_odom * it->T;
        const scan::FeatureCloud& f = *it->features;
        for (const Eigen::Vector3d& p : f.edges) {
            const Eigen::Vector3d q = T * p;
            if (edge_cells.insert(scan::voxelOf(q, config_.edge_leaf_m)).second)
                out.edges.push_back(q);
        }
        const bool origins = f.planar_origins.size() == f.planars.size();
        for (std::size_t i = 0; i < f.planars.size(); ++i) {
            const Eigen::Vector3d q = T * f.planars[i];
            if (!planar_cells.insert(scan::voxelOf(q, config_.planar_leaf_m)).second) continue;
            out.planars.push_back(q);
            if (origins) out.planar_origins.push_back(T * f.planar_origins[i]);
        }
    }
    if (out.planar_origins.size() != out.planars.size()) out.planar_origins.clear();
    return out;
}

}  // namespace handscan::localize
