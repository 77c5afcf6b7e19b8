// A small ray-casting stand-in for the spinning Hokuyo, used by the scan tests and benchmarks:
// box rooms, corridors and planes, a trajectory T_world_body(t), the encoder angle stream and
// UTM-30LX scans (1081 steps over 270 deg, 25 ms per scan) with Gaussian range noise.
#pragma once

#include <Eigen/Geometry>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>
#include <random>
#include <vector>

#include "handscan/core/samples.hpp"
#include "handscan/scan/sweep_assembler.hpp"

namespace handscan::scan::testing {

struct Box {
    Eigen::Vector3d lo;
    Eigen::Vector3d hi;
    bool inside = false;  // true: a room seen from within (rays hit its walls from inside)
};

struct Plane {
    Eigen::Vector3d n;  // unit normal
    double d = 0.0;     // n . x = d
};

struct Scene {
    std::vector<Box> boxes;
    std::vector<Plane> planes;

    // Range along the unit ray o + t dir, or NaN when nothing is hit within max_range.
    double cast(const Eigen::Vector3d& o, const Eigen::Vector3d& dir, double max_range) const {
        double best = std::numeric_limits<double>::infinity();
        for (const Box& b : boxes) {
            double t_in = -std::numeric_limits<double>::infinity();
            double t_out = std::numeric_limits<double>::infinity();
            for (int a = 0; a < 3; ++a) {
                if (std::abs(dir[a]) < 1e-12) {
                    if (o[a] < b.lo[a] || o[a] > b.hi[a]) {
                        t_in = std::numeric_limits<double>::infinity();
                    }
                    continue;
                }
                double t1 = (b.lo[a] - o[a]) / dir[a];
                double t2 = (b.hi[a] - o[a]) / dir[a];
                if (t1 > t2) std::swap(t1, t2);
                t_in = std::max(t_in, t1);
                t_out = std::min(t_out, t2);
            }
            if (t_in > t_out) continue;
            const double t = b.inside ? t_out : t_in;
            if (t > 1e-6 && t < best) best = t;
        }
        for (const Plane& p : planes) {
            const double den = p.n.dot(dir);
            if (std::abs(den) < 1e-12) continue;
            const double t = (p.d - p.n.dot(o)) / den;
            if (t > 1e-6 && t < best) best = t;
        }
        return best <= max_range ? best : std::numeric_limits<double>::quiet_NaN();
    }

    // Distance of a point to the nearest surface (for checking assembled clouds).
    double distance(const Eigen::Vector3d& p) const {
        double best = std::numeric_limits<double>::infinity();
        for (const Box& b : boxes) {
            const Eigen::Vector3d q = p.cwiseMax(b.lo).cwiseMin(b.hi);
            if (b.inside) {
                double d = std::numeric_limits<double>::infinity();
                for (int a = 0; a < 3; ++a) {
                    d = std::min({d, std::abs(p[a] - b.lo[a]), std::abs(p[a] - b.hi[a])});
                }
                best = std::min(best, d);
            } else if ((q - p).norm() > 0.0) {
                best = std::min(best, (q - p).norm());
            } else {
                double d = std::numeric_limits<double>::infinity();
                for (int a = 0; a < 3; ++a) d = std::min({d, p[a] - b.lo[a], b.hi[a] - p[a]});
                best = std::min(best, d);
            }
        }
        for (const Plane& pl : planes) best = std::min(best, std::abs(pl.n.dot(p) - pl.d));
        return best;
    }
};

// Body frame = tracking camera: z forward, x right, y down. Rooms below put the floor at +y.
inline Scene officeRoom() {
    Scene s;
    s.boxes.push_back({{-4.0, -1.6, -3.0}, {5.0, 1.2, 6.5}, true});   // the room
    s.boxes.push_back({{1.5, -1.6, 2.0}, {2.1, 1.2, 2.6}, false});    // pillar
    s.boxes.push_back({{-3.0, 0.45, 3.0}, {-1.2, 1.2, 4.0}, false});  // table block
    s.boxes.push_back({{2.5, -0.2, -2.0}, {5.0, 1.2, -1.0}, false});  // cabinet
    s.boxes.push_back({{-1.0, -1.6, 5.5}, {0.2, 1.2, 6.5}, false});   // niche
    return s;
}

// Walls at z = +-1, floor and ceiling: nothing fixes the position along x.
inline Scene corridor() {
    Scene s;
    s.planes.push_back({{0, 0, 1}, 1.0});
    s.planes.push_back({{0, 0, 1}, -1.0});
    s.planes.push_back({{0, 1, 0}, 1.2});
    s.planes.push_back({{0, 1, 0}, -1.4});
    return s;
}

inline Scene floorOnly() {
    Scene s;
    s.planes.push_back({{0, 1, 0}, 1.2});
    return s;
}

// config/calibration.yaml: the Hokuyo's front beam along the shaft, the shaft along the camera's
// z axis 8 cm below it.
inline SpinGeometry deviceGeometry() {
    SpinGeometry g;
    g.T_shaft_laser = Eigen::Isometry3d::Identity();
    g.T_shaft_laser.translation() = Eigen::Vector3d(0, 0, 0.05);
    g.T_shaft_laser.linear() =
        Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitY()).toRotationMatrix();
    g.T_body_shaftbase = Eigen::Isometry3d::Identity();
    g.T_body_shaftbase.translation() = Eigen::Vector3d(0, 0.08, 0);
    return g;
}

using Trajectory = std::function<Eigen::Isometry3d(TimeNs)>;

inline Trajectory staticPose(const Eigen::Isometry3d& T) {
    return [T](TimeNs) { return T; };
}

struct SpinSimConfig {
    double shaft_rev_per_s = 1.0;
    double range_noise_m = 0.005;
    TimeNs encoder_period_ns = 5 * kNsPerMs;
    unsigned seed = 7;
    double max_range_m = 30.0;
};

struct SimStreams {
    std::vector<EncoderSample> encoder;
    std::vector<LaserScan> scans;
};

// UTM-30LX scans from t0 for `duration` (40 scans per second, steps 17.36 us apart).
inline SimStreams simulate(const Scene& scene, const Trajectory& traj, const SpinGeometry& g,
                           TimeNs t0, TimeNs duration, const SpinSimConfig& cfg = {}) {
    SimStreams out;
    std::mt19937 rng(cfg.seed);
    std::normal_distribution<double> noise(0.0, cfg.range_noise_m);
    const auto angleAt = [&](TimeNs t) {
        return 2.0 * M_PI * cfg.shaft_rev_per_s * toSeconds(t - t0) + 1e-3;
    };
    for (TimeNs t = t0 - 50 * kNsPerMs; t <= t0 + duration + 50 * kNsPerMs;
         t += cfg.encoder_period_ns) {
        EncoderSample e;
        e.t_host = t;
        e.angle_rad = angleAt(t);
        e.speed_radps = 2.0 * M_PI * cfg.shaft_rev_per_s;
        out.encoder.push_back(e);
    }
    const TimeNs scan_period = 25 * kNsPerMs;
    for (TimeNs t = t0; t + scan_period <= t0 + duration; t += scan_period) {
        LaserScan s;
        s.t_host = t;
        s.step_period_ns = scan_period / 1440;
        s.first_step = 0;
        s.angle_min_rad = -135.0 * M_PI / 180.0;
        s.angle_increment_rad = 0.25 * M_PI / 180.0;
        s.ranges_m.resize(1081);
        s.intensities.resize(1081);
        for (std::size_t i = 0; i < 1081; ++i) {
            const TimeNs ts = s.stepTime(i);
            const Eigen::Isometry3d T_world_laser = traj(ts) * g.bodyFromLaser(angleAt(ts));
            const double a = s.stepAngle(i);
            const Eigen::Vector3d dir =
                T_world_laser.linear() * Eigen::Vector3d(std::cos(a), std::sin(a), 0.0);
            const double r = scene.cast(T_world_laser.translation(), dir, cfg.max_range_m);
            s.ranges_m[i] = std::isnan(r) ? std::numeric_limits<float>::quiet_NaN()
                                          : static_cast<float>(r + noise(rng));
            s.intensities[i] = static_cast<std::uint16_t>(1000 + i);
        }
        out.scans.push_back(std::move(s));
    }
    return out;
}

// Runs the streams through an assembler (interleaved by time as a live pipeline sees them).
inline std::vector<Sweep> assemble(const SimStreams& streams, const SpinGeometry& g,
                                   const Trajectory& pose_at, const SweepAssemblerConfig& cfg = {},
                                   bool flush = false) {
    SweepAssembler asm_(g, cfg, pose_at);
    std::size_t e = 0;
    for (const LaserScan& s : streams.scans) {
        const TimeNs t_end = s.stepTime(s.size() - 1);
        while (e < streams.encoder.size() && streams.encoder[e].t_host <= t_end + 10 * kNsPerMs) {
            (void)asm_.addEncoder(streams.encoder[e++]);
        }
        (void)asm_.addScan(s);
    }
    while (e < streams.encoder.size()) (void)asm_.addEncoder(streams.encoder[e++]);
    std::vector<Sweep> sweeps = asm_.takeSweeps();
    if (flush) {
        Sweep last = asm_.flush();
        if (!last.empty()) sweeps.push_back(std::move(last));
    }
    return sweeps;
}

inline Eigen::Isometry3d pose(double rx, double ry, double rz, double tx, double ty, double tz) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = (Eigen::AngleAxisd(rz, Eigen::Vector3d::UnitZ()) *
                  Eigen::AngleAxisd(ry, Eigen::Vector3d::UnitY()) *
                  Eigen::AngleAxisd(rx, Eigen::Vector3d::UnitX()))
                     .toRotationMatrix();
    T.translation() = Eigen::Vector3d(tx, ty, tz);
    return T;
}

// The first sweep of a device standing still at T (half or full revolution).
inline Sweep staticSweep(const Scene& scene, const Eigen::Isometry3d& T, unsigned seed,
                         double noise, SweepBoundary boundary) {
    SpinSimConfig sim;
    sim.seed = seed;
    sim.range_noise_m = noise;
    const auto streams =
        simulate(scene, staticPose(T), deviceGeometry(), kNsPerSec, 2 * kNsPerSec, sim);
    SweepAssemblerConfig cfg;
    cfg.boundary = boundary;
    return assemble(streams, deviceGeometry(), staticPose(T), cfg).at(0);
}

inline std::vector<Eigen::Vector3d> toWorld(const Eigen::Isometry3d& T,
                                            const std::vector<Eigen::Vector3d>& p) {
    std::vector<Eigen::Vector3d> out;
    out.reserve(p.size());
    for (const auto& x : p) out.push_back(T * x);
    return out;
}

struct PoseError {
    double rot_deg;
    double trans_m;
};

inline PoseError poseError(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
    const Eigen::Isometry3d d = a.inverse() * b;
    return {Eigen::AngleAxisd(d.linear()).angle() * 180.0 / M_PI, d.translation().norm()};
}

}  // namespace handscan::scan::testing
