// Levenberg-Marquardt on the half-revolution consistency (robust: Huber weights, re-weighted each
// iteration) over the SpinCorrection parameters that are free, with the parameters' covariance and
// the refusal of those the data do not determine. Seven unknowns and tens of thousands of
// residuals: a dense 7x7 normal equation with central-difference Jacobians is exact enough and
// needs no solver library (Ceres' automatic derivatives would buy nothing at this size).
#pragma once

#include <array>
#include <span>
#include <string>
#include <vector>

#include "handscan/spin_calibration/half_revolution_consistency.hpp"

namespace handscan::calibrate {

using SpinMask = std::array<bool, SpinCorrection::kCount>;
using SpinCovariance = Eigen::Matrix<double, SpinCorrection::kCount, SpinCorrection::kCount>;

struct SolverOptions {
    int max_iterations = 20;
    double huber_k = 1.345;  // in robust standard deviations of the residuals
    // How far the starting calibration may be off (the bounds, rounded up): a weak prior
    // on each correction, so a direction the data barely see stays near its start instead of
    // running off with the noise while the trajectory is still poor.
    SpinCorrection::Vector prior_std =
        (SpinCorrection::Vector() << 2.0 * M_PI / 180.0, 2.0 * M_PI / 180.0, 0.02, 0.02,
         1.0 * M_PI / 180.0, 0.005, 0.005)
            .finished();
    // A parameter whose standard deviation is above this fraction of its prior's is not
    // determined by the recording: the data add little to what the start already said.
    double refuse_fraction_of_prior = 0.5;
    // The accuracy an instrument's calibration needs (issue 13: 0.05 deg, 2 mm, 0.05 deg, 0.3 ms):
    // a value determined but less precise than this is written and named in a note.
    SpinCorrection::Vector target_std =
        (SpinCorrection::Vector() << 0.05 * M_PI / 180.0, 0.05 * M_PI / 180.0, 0.002, 0.002,
         0.05 * M_PI / 180.0, 0.3e-3, 0.3e-3)
            .finished();
};

struct SpinSolution {
    SpinCorrection::Vector x = SpinCorrection::Vector::Zero();
    SpinCorrection::Vector std = SpinCorrection::Vector::Constant(INFINITY);  // inf when fixed
    SpinCovariance covariance = SpinCovariance::Zero();
    SpinMask solved{};                   // estimated and determined
    SpinMask refused{};                  // tried, but not determined: left at the base value
    double robust_sigma_before_m = 0.0;  // 1.4826 * median |r| at the start
    double robust_sigma_after_m = 0.0;
    std::size_t residuals = 0;
    int iterations = 0;
    std::vector<std::string> notes;  // why a parameter was refused
};

// LM from x = 0 over the `free` parameters; covariance from the Hessian, made robust to the
// residuals' correlation within a revolution (clustered sandwich estimate; the larger of it and
// the formal one is reported).
SpinSolution solveSpin(std::span<const SpinObservation> observations, const SpinModel& model,
                       std::span<const HalfPairResidual> residuals, const SpinMask& free,
                       const SolverOptions& options);

// solveSpin, then gives up undetermined parameters one at a time and solves again, until every
// free parameter is determined. Time offsets go first when several are undetermined: at a near
// constant shaft speed the encoder's time offset and its zero turn the sweep alike, and the zero
// is the one the pipeline cannot do without.
SpinSolution solveDetermined(std::span<const SpinObservation> observations, const SpinModel& model,
                             std::span<const HalfPairResidual> residuals, SpinMask free,
                             const SolverOptions& options);

}  // namespace handscan::calibrate
