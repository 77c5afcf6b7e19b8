// The half-revolution consistency of a spinning laser: in every shaft revolution each half sweeps
// the whole scene, so a point of the second half must lie on the surface the first half saw
// around it. A wrong laser-on-shaft transform, encoder zero or clock offset places the two halves
// differently (the error turns with the shaft), so their point-to-plane distances measure it.
// Each residual keeps its query point and its plane's neighbours by index, with the plane's normal
// frozen at association time, so it can be re-evaluated for any SpinCorrection:
//   r(x) = n . (p_query(x) - mean_j p_neighbour_j(x)).
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "handscan/spin_calibration/spin_observations.hpp"

namespace handscan::calibrate {

inline constexpr int kPlaneNeighbours = 6;

struct HalfPairResidual {
    std::uint32_t query = 0;  // index into the observations (second half)
    std::array<std::uint32_t, kPlaneNeighbours> neighbours{};  // first half
    Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
    std::int32_t revolution = 0;  // the cluster for the covariance (residuals of one turn share
                                  // the trajectory's error there)
};

struct AssociationOptions {
    int query_stride = 3;             // every n-th second-half observation asks for a plane, or
    std::size_t max_queries = 60000;  // fewer when there are more (the solve's cost)
    // A half revolution's scan lines are ~9 deg apart (40 scans per turn), so a plane needs the
    // nearest points of several lines: up to 2 from each of the nearest lines, at least 2 lines.
    double max_neighbour_m = 0.8;
    double max_distance_m = 0.10;    // farther from the plane: another surface (or an outlier)
    double max_thickness_m = 0.015;  // rms distance of the neighbours from their plane
    double min_spread_m = 0.05;      // rms spread across the plane's thinner in-plane direction
};

// Associates every revolution's second half with its first half at correction `x`.
std::vector<HalfPairResidual> associateHalves(std::span<const SpinObservation> observations,
                                              const SpinModel& model,
                                              const SpinCorrection::Vector& x,
                                              const AssociationOptions& options);

// r(x) for every residual, in order.
void evaluateResiduals(std::span<const SpinObservation> observations, const SpinModel& model,
                       std::span<const HalfPairResidual> residuals, const SpinCorrection::Vector& x,
                       std::vector<double>& r);

}  // namespace handscan::calibrate
