#include "handscan/spin_calibration/spin_solver.hpp"

#include <fmt/format.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <map>

namespace handscan::calibrate {
namespace {

constexpr int kN = SpinCorrection::kCount;
using Jacobian = Eigen::Matrix<double, Eigen::Dynamic, kN>;

// Central-difference steps: small against the parameters' effect, large against rounding.
const SpinCorrection::Vector kStep =
    (SpinCorrection::Vector() << 1e-4, 1e-4, 1e-4, 1e-4, 1e-4, 1e-5, 1e-5).finished();

double robustSigma(const std::vector<double>& r) {
    if (r.empty()) return 0.0;
    std::vector<double> a(r.size());
    std::transform(r.begin(), r.end(), a.begin(), [](double v) { return std::abs(v); });
    auto mid = a.begin() + static_cast<std::ptrdiff_t>(a.size() / 2);
    std::nth_element(a.begin(), mid, a.end());
    return 1.4826 * *mid;
}

struct Problem {
    std::span<const SpinObservation> obs;
    const SpinModel& model;
    std::span<const HalfPairResidual> res;
    const SpinMask& free;

    void residuals(const SpinCorrection::Vector& x, std::vector<double>& r) const {
        evaluateResiduals(obs, model, res, x, r);
    }
    Jacobian jacobian(const SpinCorrection::Vector& x) const {
        Jacobian J = Jacobian::Zero(static_cast<Eigen::Index>(res.size()), kN);
        std::vector<double> plus, minus;
        for (int j = 0; j < kN; ++j) {
            if (!free[j]) continue;
            SpinCorrection::Vector xp = x, xm = x;
            xp[j] += kStep[j];
            xm[j] -= kStep[j];
            residuals(xp, plus);
            residuals(xm, minus);
            for (std::size_t i = 0; i < res.size(); ++i)
                J(static_cast<Eigen::Index>(i), j) = (plus[i] - minus[i]) / (2.0 * kStep[j]);
        }
        return J;
    }
};

// Huber weights at scale k * sigma.
std::vector<double> huberWeights(const std::vector<double>& r, double threshold) {
    std::vector<double> w(r.size());
    for (std::size_t i = 0; i < r.size(); ++i)
        w[i] = std::abs(r[i]) <= threshold ? 1.0 : threshold / std::abs(r[i]);
    return w;
}

// The prior's weight in the residuals' units: (sigma_r / sigma_prior)^2 per parameter.
SpinCorrection::Vector priorWeights(const SolverOptions& opt, double sigma_r,
                                    const SpinMask& free) {
    SpinCorrection::Vector w;
    for (int j = 0; j < kN; ++j)
        w[j] = free[j] ? (sigma_r * sigma_r) / (opt.prior_std[j] * opt.prior_std[j]) : 0.0;
    return w;
}

double weightedCost(const std::vector<double>& r, double threshold, const SpinCorrection::Vector& x,
                    const SpinCorrection::Vector& prior) {
    double c = 0.5 * (prior.array() * x.array().square()).sum();  // Huber's rho plus the prior
    for (double v : r) {
        const double a = std::abs(v);
        c += a <= threshold ? 0.5 * v * v : threshold * (a - 0.5 * threshold);
    }
    return c;
}

// Normal equations of the free parameters (fixed ones get a unit diagonal and zero gradient).
void normalEquations(const Jacobian& J, const std::vector<double>& r, const std::vector<double>& w,
                     const SpinMask& free, SpinCovariance& H, SpinCorrection::Vector& g) {
    H.setZero();
    g.setZero();
    for (Eigen::Index i = 0; i < J.rows(); ++i) {
        const auto row = J.row(i);
        H.noalias() += w[static_cast<std::size_t>(i)] * row.transpose() * row;
        g.noalias() +=
            w[static_cast<std::size_t>(i)] * r[static_cast<std::size_t>(i)] * row.transpose();
    }
    for (int j = 0; j < kN; ++j) {
        if (free[j]) continue;
        H.row(j).setZero();
        H.col(j).setZero();
        H(j, j) = 1.0;
        g[j] = 0.0;
    }
}

// Inverse of the free block (scaled to unit diagonal first, so units do not matter); a direction
// the data do not see comes out with a huge variance rather than a failure.
SpinCovariance inverseFree(const SpinCovariance& H, const SpinMask& free) {
    SpinCorrection::Vector d;
    for (int j = 0; j < kN; ++j) d[j] = free[j] && H(j, j) > 0.0 ? 1.0 / std::sqrt(H(j, j)) : 1.0;
    SpinCovariance Hs = d.asDiagonal() * H * d.asDiagonal();
    Hs.diagonal().array() += 1e-12;
    SpinCovariance inv =
        d.asDiagonal() * Hs.ldlt().solve(SpinCovariance::Identity()) * d.asDiagonal();
    for (int j = 0; j < kN; ++j)
        if (!free[j]) {
            inv.row(j).setZero();
            inv.col(j).setZero();
        }
    return inv;
}

}  // namespace

SpinSolution solveSpin(std::span<const SpinObservation> obs, const SpinModel& model,
                       std::span<const HalfPairResidual> res, const SpinMask& free,
                       const SolverOptions& opt) {
    const Problem problem{obs, model, res, free};
    SpinSolution s;
    s.residuals = res.size();
    std::vector<double> r;
    problem.residuals(s.x, r);
    s.robust_sigma_before_m = robustSigma(r);
    const double threshold = opt.huber_k * std::max(s.robust_sigma_before_m, 1e-4);
    const SpinCorrection::Vector prior =
        priorWeights(opt, std::max(s.robust_sigma_before_m, 1e-4), free);
    double cost = weightedCost(r, threshold, s.x, prior);
    double lambda = 1e-3;
    SpinCovariance H;
    SpinCorrection::Vector g;
    for (s.iterations = 0; s.iterations < opt.max_iterations; ++s.iterations) {
        const Jacobian J = problem.jacobian(s.x);
        normalEquations(J, r, huberWeights(r, threshold), free, H, g);
        H.diagonal() += prior;
        g += prior.cwiseProduct(s.x);
        bool improved = false;
        while (lambda < 1e8) {
            SpinCovariance A = H;
            A.diagonal() += lambda * H.diagonal();
            const SpinCorrection::Vector dx = A.ldlt().solve(-g);
            const SpinCorrection::Vector x_new = s.x + dx;
            std::vector<double> r_new;
            problem.residuals(x_new, r_new);
            const double cost_new = weightedCost(r_new, threshold, x_new, prior);
            if (cost_new < cost) {
                const bool converged = cost - cost_new < 1e-6 * cost;
                s.x = x_new;
                r.swap(r_new);
                cost = cost_new;
                lambda = std::max(lambda / 10.0, 1e-9);
                improved = !converged;
                break;
            }
            lambda *= 10.0;
        }
        if (!improved) break;
    }
    s.robust_sigma_after_m = robustSigma(r);

    // Covariance at the solution: the formal one, sigma^2 H^-1, and the sandwich
    // H^-1 (sum over revolutions of g_c g_c^T) H^-1, which does not assume independent residuals
    // (the trajectory's error within a revolution moves all its residuals alike).
    const Jacobian J = problem.jacobian(s.x);
    const std::vector<double> w = huberWeights(r, threshold);
    normalEquations(J, r, w, free, H, g);
    H.diagonal() += prior;
    const SpinCovariance Hinv = inverseFree(H, free);
    int free_count = 0;
    for (bool f : free) free_count += f ? 1 : 0;
    double wrss = 0.0;
    for (std::size_t i = 0; i < r.size(); ++i) wrss += w[i] * r[i] * r[i];
    const double dof = std::max(1.0, static_cast<double>(r.size()) - free_count);
    const SpinCovariance formal = (wrss / dof) * Hinv;
    std::map<std::int32_t, SpinCorrection::Vector> clusters;
    for (std::size_t i = 0; i < r.size(); ++i) {
        auto [it, inserted] =
            clusters.try_emplace(res[i].revolution, SpinCorrection::Vector::Zero());
        it->second += w[i] * r[i] * J.row(static_cast<Eigen::Index>(i)).transpose();
    }
    SpinCovariance meat = SpinCovariance::Zero();
    for (const auto& [rev, gc] : clusters) meat += gc * gc.transpose();
    const double small_sample = clusters.size() > 1 ? static_cast<double>(clusters.size()) /
                                                          static_cast<double>(clusters.size() - 1)
                                                    : 1.0;
    const SpinCovariance sandwich = small_sample * Hinv * meat * Hinv;
    s.covariance = sandwich;
    for (int j = 0; j < kN; ++j) {
        if (!free[j]) continue;
        s.std[j] = std::sqrt(std::max(formal(j, j), sandwich(j, j)));
        s.covariance(j, j) = s.std[j] * s.std[j];
        s.solved[j] = true;
    }
    return s;
}

SpinSolution solveDetermined(std::span<const SpinObservation> obs, const SpinModel& model,
                             std::span<const HalfPairResidual> res, SpinMask free,
                             const SolverOptions& opt) {
    SpinMask refused{};
    std::vector<std::string> notes;
    for (;;) {
        SpinSolution s = solveSpin(obs, model, res, free, opt);
        int worst = -1;
        double worst_ratio = 1.0;
        for (int j = 0; j < kN; ++j) {
            if (!free[j]) continue;
            double ratio = s.std[j] / (opt.refuse_fraction_of_prior * opt.prior_std[j]);
            if (!std::isfinite(ratio)) ratio = 1e300;
            // Time offsets first (see the header): they rank above any geometric parameter.
            const bool time = j == SpinCorrection::kEncoderTime || j == SpinCorrection::kImuTime;
            if (ratio > 1.0 && time) ratio *= 1e6;
            if (ratio > worst_ratio) {
                worst_ratio = ratio;
                worst = j;
            }
        }
        if (worst < 0) {
            s.refused = refused;
            s.notes = std::move(notes);
            return s;
        }
        const double scale = SpinCorrection::displayScale(worst);
        notes.push_back(fmt::format(
            "{}: not determined by this recording (std {:.3g} {} > {:.3g}, half the start's "
            "uncertainty); kept as given",
            SpinCorrection::name(worst), s.std[worst] * scale, SpinCorrection::unit(worst),
            opt.refuse_fraction_of_prior * opt.prior_std[worst] * scale));
        free[worst] = false;
        refused[worst] = true;
        bool any = false;
        for (bool f : free) any = any || f;
        if (!any) {
            SpinSolution none;
            none.refused = refused;
            none.notes = std::move(notes);
            none.residuals = res.size();
            return none;
        }
    }
}

}  // namespace handscan::calibrate
