// ScanMatcher: refines the body pose at a sweep's start by matching its edge and planar features
// to the map (sections 6.1-6.2): point-to-line (eq. 14) and point-to-plane (eq. 15) distances to
// neighbour clusters that pass an eigenvalue test, robust weights, Gauss-Newton on SE(3) with the
// pose prior of eqs. (17)-(18), and the degeneracy remapping of eq. (21) so that directions the
// scene cannot constrain stay at the prior; directions it constrains weakly are solved when a
// re-association probe shows that the constraint is real (degeneracy_probe_max_std_m).
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <vector>

#include "handscan/core/se3.hpp"
#include "handscan/scan/degeneracy.hpp"
#include "handscan/scan/feature_extractor.hpp"
#include "handscan/scan/local_map.hpp"

namespace handscan::scan {

enum class RobustKernel : std::uint8_t { kNone = 0, kHuber = 1, kBisquare = 2 };

struct ScanMatcherConfig {
    int max_associations = 6;  // outer loop: nearest-neighbour search + cluster test
    int max_iterations = 4;    // inner Gauss-Newton steps per association
    // Edge cluster size. The map keeps one edge point per 10 cm leaf, so 5 neighbours reach 40 cm
    // and more along an edge and, on cluttered real scans, take in points of a neighbouring edge
    // that still pass the eigenvalue test. 4 instead of 5: the 3DTK tilting scans
    // (tests/unit/scan/laser3d_real_test) land 1.08 instead of 1.50 deg (scan001) and 3.2
    // instead of 4.3 cm (scan001 -> scan002) from the published registration; the simulated
    // office and courtyard keep their accuracy (ATE 6.4 -> 6.1 mm, 4.5 -> 4.5 mm; drift 0.105 ->
    // 0.104 %, 0.095 -> 0.096 %), and so do the degenerate tunnel and field (tests/e2e/lio, ATE
    // 1.64 -> 1.69 m, 3.47 -> 2.98 m). 3 is too few to tell a line: the tunnel diverges (13.7 m).
    int neighbours = 4;
    // Planar cluster size. With 5, clusters of few scan lines give plane normals a few degrees
    // off, which invent ~7 units of information along a corridor's axis and pull the pose there;
    // 8 brings that under 3, and the office's per-sweep error (ground-truth dewarped sweeps,
    // prior 20 cm / 3 deg off) from 1.3 cm to 0.4 cm mean.
    int plane_neighbours = 8;
    // Curved surfaces (eq. 15): up to this many map points (closest first, within
    // max_neighbour_dist_m) fit a quadric under each planar match, whose height at the query moves
    // the plane onto the surface; 0 or <= plane_neighbours: the cluster's plane as it is. Without
    // it the simulated tunnel's vault biased every match the same way: with ground-truth motion
    // the map pitched 1.74 deg over 55 m (replay --reference-motion, 90 s seed 1; 0.34 deg with
    // 16).
    int curvature_neighbours = 16;
    // rms of those points about their quadric above which they are no smooth surface (a corner,
    // clutter) and the plane stands: the laser's noise, ~1 cm.
    double curvature_max_rms_m = 0.01;
    double max_neighbour_dist_m = 1.0;  // farthest cluster point from the query
    double edge_eigen_ratio = 10.0;  // edge: lambda_max > ratio * lambda_mid (one large eigenvalue)
    double edge_max_thickness_m = 0.05;  // sqrt(lambda_mid): the cluster must be a thin segment
    double plane_eigen_ratio =
        0.1;  // plane: lambda_min < ratio * lambda_mid (one small eigenvalue)
    double plane_max_thickness_m = 0.05;  // every cluster point this close to the fitted plane
    // sqrt(lambda_mid) at least this: a cluster from a single scan line is a segment, whose
    // "normal" is any direction around it (far from the sensor, lines are wider apart than the
    // neighbour search, and such clusters would pull the pose sideways).
    double plane_min_extent_m = 0.03;
    // A planar match whose map points were mostly seen from the other side of the plane than the
    // query point (the far face of a thin wall) is rejected; sensors closer to the plane than
    // this tell no side.
    double view_side_margin_m = 0.1;
    RobustKernel kernel = RobustKernel::kBisquare;
    double kernel_scale_m = 0.1;  // bisquare zero-weight distance / Huber corner
    // Coarse to fine: the first association uses this scale, each later one half the previous,
    // down to kernel_scale_m, so a prior decimetres off still pulls in the far correspondences.
    double kernel_scale_initial_m = 0.5;
    double laser_sigma_m = 0.03;  // feature-to-map distance noise (weights the prior against)
    // Section 8: a direction of the laser constraints alone is degraded when the standard
    // deviation they give it, laser_sigma_m / sqrt(lambda) for an eigenvalue lambda of
    // sum(w J^T J), exceeds this (rotations count as their displacement at 1 m). Stated as a
    // standard deviation, the threshold does not depend on how many features a sweep has: on the
    // simulated scenes a tunnel's axis gives lambda <= 4 (std >= 15 mm) and the weakest office
    // direction lambda >= 28 (std <= 6 mm).
    double degeneracy_max_std_m = 0.01;
    // Weak but real directions (an extension of section 8): a corridor's axis is held only by a
    // few door recesses, lambda ~2-9, as weak as the information that noisy cluster normals
    // invent along a smooth tunnel's axis - lowering the threshold to 2-3 cm solves the
    // corridor but lets the tunnel "solve" its axis from noise and diverge. What tells them
    // apart is whether the information survives re-association. From the laser's own minimum
    // along the direction (found by Gauss-Newton restricted to it, on fresh correspondences at
    // every step), moved `offset` and 2 `offset` off along it (both ways), the same descent
    // must come back by a fraction in [min_return, 2 - min_return] of the offset. A recess's
    // faces pull back; noise-tilted clusters, found anew at the moved pose, pull anywhere.
    // Measured on the simulated scenes with the map built at the true poses (replay
    // --reference-motion, seed 2): corridor directions with lambda 4-9 come back in 50 % of the
    // sweeps, lambda >= 9 in 100 %; tunnel axes (lambda 0.3-9) in 0 of 178. Directions whose
    // laser standard deviation exceeds `degeneracy_probe_max_std_m` are not probed. A confirmed
    // direction joins the solved subspace of eq. (21) for a last round from that minimum.
    // Whole pipeline, corridor 60 s seeds 1-6: ATE 0.08 / 0.68 / 9.5 / 4.4 / 0.19 / 3.7 m ->
    // 0.10 / 0.18 / 0.08 / 0.35 / 0.03 / 0.02 m (with lio's unsolved_prior_sigma_trans_m and
    // the IMU trust of imu::UnsolvedMotionPrior earned by solved time); office, house,
    // courtyard byte-identical; tunnel 90 s seeds 1-4 9.4 / 5.1 / 3.4 / 8.1 -> 7.6 / 4.6 / 2.9 /
    // 8.0 m, field 90 s seeds 1-2 22.5 / 16.6 -> 16.5 / 13.4 m. Two descent steps per probe
    // (three: corridor seed 3 0.57 m, tunnel 8.9 / 4.1 / 2.3 / 7.6 m, and slower). Cost
    // (loaded machine, noisy): mean matching time tunnel 37 -> 47 ms, corridor 20 -> 32 ms.
    double degeneracy_probe_max_std_m = 0.02;
    double degeneracy_probe_offset_m = 0.05;
    double degeneracy_probe_min_return = 0.5;
    int degeneracy_probe_iterations = 2;
    int min_correspondences = 20;  // fewer: the sweep constrains nothing
    double converged_rot_rad = 1e-5;
    double converged_trans_m = 1e-5;
};

// A pose prior of eqs. (17)/(18): the predicted body pose and the information (inverse
// covariance) of its error log(T_prior^{-1} T) in the body tangent (rot, trans). Several priors
// add up, e.g. eq. (22): VIO information projected on its solved directions plus IMU
// information on the others.
struct PosePrior {
    Eigen::Isometry3d T_world_body = Eigen::Isometry3d::Identity();
    Matrix6d information = Matrix6d::Identity();
};

struct MatchResult {
    Eigen::Isometry3d T_world_body = Eigen::Isometry3d::Identity();
    DegeneracyAnalysis degeneracy;  // of the last association; the solved mask is in here
    Matrix6d covariance = Matrix6d::Identity();  // (rot, trans), from the final normal equations
    int associations = 0;
    int iterations = 0;
    int edge_matches = 0;
    int plane_matches = 0;
    double rms_m = 0.0;  // weighted rms feature-to-map distance, last iteration
    bool converged = false;
    bool enough_matches = false;   // false: pose = prior, mask 0
    int probed_directions = 0;     // weak directions tested by re-association
    int confirmed_directions = 0;  // of those, solved because they came back
};

class ScanMatcher {
public:
    explicit ScanMatcher(const ScanMatcherConfig& config = {}) : config_(config) {}

    // `features` in the body frame at the sweep's start; the search starts at priors[0]'s pose
    // (or `initial` when given).
    MatchResult match(const FeatureCloud& features, const LocalMap& map,
                      const std::vector<PosePrior>& priors,
                      const Eigen::Isometry3d* initial = nullptr) const;

    const ScanMatcherConfig& config() const { return config_; }

private:
    // When the pose moved off the laser's minimum along unit direction v (rot, trans) comes back
    // under fresh associations (see ScanMatcherConfig::degeneracy_probe_max_std_m): how far
    // that minimum lies from T along v; nullopt when it does not come back.
    std::optional<double> comesBack(const FeatureCloud& features, const LocalMap& map,
                                    const Eigen::Isometry3d& T, const Vector6d& v) const;

    ScanMatcherConfig config_;
};

// The eigenvalue threshold of section 8 that `config` implies: (laser_sigma / max_std)^2.
double degeneracyEigenvalueThreshold(const ScanMatcherConfig& config);
// The eigenvalue above which a weak direction is probed: (laser_sigma / probe_max_std)^2.
double degeneracyProbeEigenvalueThreshold(const ScanMatcherConfig& config);

}  // namespace handscan::scan
