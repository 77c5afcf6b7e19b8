// SweepStack: the last seconds of registered sweeps' features, stacked into the body frame of the
// newest sweep's start with the odometry's own poses (section 9: "scans are stacked over about
// 2 s while moving"), so one match to the prior map sees the scene all round. Thinned to one
// point per leaf cell, as the maps are, so the match costs the same however many sweeps it holds.
#pragma once

#include <Eigen/Geometry>
#include <deque>
#include <memory>

#include "handscan/core/time.hpp"
#include "handscan/scan/feature_extractor.hpp"

namespace handscan::localize {

struct SweepStackConfig {
    double span_s = 2.0;         // sweeps older than this behind the newest are dropped
    double edge_leaf_m = 0.1;    // one stacked edge point per leaf cell
    double planar_leaf_m = 0.2;  // one stacked planar point per leaf cell
};

class SweepStack {
public:
    explicit SweepStack(const SweepStackConfig& config = {}) : config_(config) {}

    // A sweep matched by the odometry: its features (body frame at its start) and that start's
    // pose in the odometry's world.
    void add(TimeNs t_start, const Eigen::Isometry3d& T_odom_body,
             std::shared_ptr<const scan::FeatureCloud> features);
    bool empty() const { return sweeps_.empty(); }
    std::size_t size() const { return sweeps_.size(); }
    TimeNs newestTime() const { return sweeps_.empty() ? 0 : sweeps_.back().t; }
    TimeNs oldestTime() const { return sweeps_.empty() ? 0 : sweeps_.front().t; }
    // The newest sweep's start in the odometry's world: the frame stack() is in.
    const Eigen::Isometry3d& newestPose() const { return sweeps_.back().T; }
    // Every held sweep's features in the newest sweep's body frame, thinned.
    scan::FeatureCloud stack() const;

private:
    struct Entry {
        TimeNs t;
        Eigen::Isometry3d T;
        std::shared_ptr<const scan::FeatureCloud> features;
    };
    SweepStackConfig config_;
    std::deque<Entry> sweeps_;
};

}  // namespace handscan::localize
