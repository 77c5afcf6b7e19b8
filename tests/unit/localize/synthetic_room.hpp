// A synthetic room of boxes as edge and planar feature points (what a spinning laser's feature
// extraction keeps of it): the walls, floor and ceiling of a 10 x 7 x 3 m room and a few pieces
// of furniture placed without symmetry, surfaces sampled on a grid, edges along the boxes' edges.
#pragma once

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <vector>

#include "handscan/scan/feature_extractor.hpp"
#include "handscan/scan/voxel_map.hpp"

namespace handscan::localize::test {

struct Box {
    Eigen::Vector3d lo, hi;
};

inline std::vector<Box> furniture() {
    return {{{1.0, 0.3, 0.0}, {2.6, 1.1, 0.75}},  // desk
            {{0.2, 4.5, 0.0}, {0.6, 6.5, 1.9}},   // shelf
            {{7.5, 5.8, 0.0}, {9.6, 6.7, 1.1}},   // cabinet
            {{5.0, 2.5, 0.0}, {5.8, 3.1, 1.2}}};  // a column-like crate
}

// Surface points of a box's faces (grid `step`, offset `phase`) and points along its 12 edges.
inline void sampleBox(const Box& b, double step, double phase, bool inside,
                      std::vector<Eigen::Vector3d>& planars, std::vector<Eigen::Vector3d>& edges) {
    for (int axis = 0; axis < 3; ++axis) {
        const int u = (axis + 1) % 3, v = (axis + 2) % 3;
        for (const double w : {b.lo[axis], b.hi[axis]}) {
            for (double a = b.lo[u] + phase; a < b.hi[u]; a += step)
                for (double c = b.lo[v] + phase; c < b.hi[v]; c += step) {
                    Eigen::Vector3d p;
                    p[axis] = w;
                    p[u] = a;
                    p[v] = c;
                    // A room's floor and ceiling are seen from inside; a box's bottom never.
                    if (!inside && axis == 2 && w == b.lo[2]) continue;
                    planars.push_back(p);
                }
        }
    }
    for (int axis = 0; axis < 3; ++axis) {
        const int u = (axis + 1) % 3, v = (axis + 2) % 3;
        for (const double cu : {b.lo[u], b.hi[u]})
            for (const double cv : {b.lo[v], b.hi[v]})
                for (double a = b.lo[axis] + phase / 2; a < b.hi[axis]; a += step / 2) {
                    Eigen::Vector3d p;
                    p[axis] = a;
                    p[u] = cu;
                    p[v] = cv;
                    edges.push_back(p);
                }
    }
}

// Whether the segment from `from` to `p` passes through one of the boxes (each shrunk by a
// millimetre, so that a point on a box's face seen from outside is not hidden by its own box).
inline bool hidden(const Eigen::Vector3d& from, const Eigen::Vector3d& p,
                   const std::vector<Box>& boxes) {
    const Eigen::Vector3d d = p - from;
    for (const Box& b : boxes) {
        double t0 = 0.0, t1 = 1.0;
        for (int a = 0; a < 3 && t0 <= t1; ++a) {
            const double lo = b.lo[a] + 1e-3, hi = b.hi[a] - 1e-3;
            if (std::abs(d[a]) < 1e-12) {
                if (from[a] < lo || from[a] > hi) t0 = 2.0;
                continue;
            }
            double ta = (lo - from[a]) / d[a], tb = (hi - from[a]) / d[a];
            if (ta > tb) std::swap(ta, tb);
            t0 = std::max(t0, ta);
            t1 = std::min(t1, tb);
        }
        if (t0 <= t1) return true;
    }
    return false;
}

inline std::vector<Box> furnitureMoved(const Eigen::Vector3d& moved) {
    std::vector<Box> f = furniture();
    f[2].lo += moved;
    f[2].hi += moved;
    return f;
}

// The room in world coordinates; `moved`: the cabinet shifted by this much (a changed scene).
// `viewpoints` empty: every surface point, its laser centre unknown (NaN); else only the planar
// points one of them sees past the furniture, each with the first that does as its laser centre
// (what a feature map of a session standing there keeps).
inline scan::FeatureMapPoints roomWorld(double step, double phase,
                                        const Eigen::Vector3d& moved = Eigen::Vector3d::Zero(),
                                        const std::vector<Eigen::Vector3d>& viewpoints = {}) {
    scan::FeatureMapPoints m;
    std::vector<Eigen::Vector3d> planars, edges;
    sampleBox({{0, 0, 0}, {10, 7, 3}}, step, phase, true, planars, edges);
    const std::vector<Box> f = furnitureMoved(moved);
    for (const Box& b : f) sampleBox(b, step, phase, false, planars, edges);
    for (const auto& p : edges) m.edges.push_back(p.cast<float>());
    for (const auto& p : planars) {
        Eigen::Vector3f origin = Eigen::Vector3f::Constant(std::nanf(""));
        if (!viewpoints.empty()) {
            const auto seen = std::find_if(viewpoints.begin(), viewpoints.end(),
                                           [&](const auto& v) { return !hidden(v, p, f); });
            if (seen == viewpoints.end()) continue;
            origin = seen->template cast<float>();
        }
        m.planars.push_back(p.cast<float>());
        m.planar_origins.push_back(origin);
    }
    return m;
}

// What a sensor at T_world_body sees of the room (within `range`, past the furniture), in its
// body frame, the planar points with the laser centre (the body's origin).
inline scan::FeatureCloud sweepAt(const Eigen::Isometry3d& T_world_body,
                                  const Eigen::Vector3d& moved = Eigen::Vector3d::Zero(),
                                  double range = 8.0) {
    const scan::FeatureMapPoints w = roomWorld(0.2, 0.07, moved);
    const std::vector<Box> f = furnitureMoved(moved);
    const Eigen::Vector3d o = T_world_body.translation();
    const Eigen::Isometry3d T = T_world_body.inverse();
    scan::FeatureCloud c;
    auto keep = [&](const Eigen::Vector3f& p) {
        return (p.cast<double>() - o).norm() < range && !hidden(o, p.cast<double>(), f);
    };
    for (const auto& p : w.edges)
        if (keep(p)) c.edges.push_back(T * p.cast<double>());
    for (const auto& p : w.planars) {
        if (!keep(p)) continue;
        c.planars.push_back(T * p.cast<double>());
        c.planar_origins.push_back(Eigen::Vector3d::Zero());
    }
    return c;
}

inline Eigen::Isometry3d pose(double x, double y, double z, double yaw_deg) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() =
        Eigen::AngleAxisd(yaw_deg * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    T.translation() = Eigen::Vector3d(x, y, z);
    return T;
}

}  // namespace handscan::localize::test
