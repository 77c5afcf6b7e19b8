#include "handscan/imu/gyro_hand_eye.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

#include "handscan/core/se3.hpp"

namespace handscan::imu {
namespace {

constexpr int kP = 5;

// The gyro's piecewise-linear rate at s (clamped to the ends).
Eigen::Vector3d rateAt(const std::vector<ImuSample>& imu, const std::vector<double>& t, double s) {
    auto it = std::upper_bound(t.begin(), t.end(), s);
    if (it == t.begin()) return imu.front().gyro_radps_imu;
    if (it == t.end()) return imu.back().gyro_radps_imu;
    const auto i = static_cast<std::size_t>(it - t.begin());
    const double u = (s - t[i - 1]) / (t[i] - t[i - 1]);
    return (1.0 - u) * imu[i - 1].gyro_radps_imu + u * imu[i].gyro_radps_imu;
}

// The rotation from the first sample to every sample, for one bias: any interval's rotation is
// then two partial pieces and one product (integrateGyro's sums, without walking the samples
// again for every pair and every Jacobian column).
class GyroPrefix {
public:
    GyroPrefix(const HandEyeProblem& p, const Eigen::Vector3d& bias)
        : p_(p), bias_(bias), P_(p.imu.size(), Eigen::Matrix3d::Identity()) {
        for (std::size_t k = 0; k + 1 < p.imu.size(); ++k)
            P_[k + 1] = P_[k] * piece(0.5 * (p.imu[k].gyro_radps_imu + p.imu[k + 1].gyro_radps_imu),
                                      p.t_s[k + 1] - p.t_s[k]);
    }

    Eigen::Matrix3d between(double a, double b) const {
        const std::vector<double>& t = p_.t_s;
        if (t.empty() || a < t.front() || b > t.back())
            return integrateGyro(p_.imu, t, a, b, p_.R_body_imu, bias_);
        // First sample after a, last sample before b: the pieces integrateGyro makes.
        const auto i =
            static_cast<std::size_t>(std::upper_bound(t.begin(), t.end(), a) - t.begin());
        const auto j_end =
            static_cast<std::size_t>(std::lower_bound(t.begin(), t.end(), b) - t.begin());
        if (i >= j_end || j_end == 0) return piece(rateAt(p_.imu, t, 0.5 * (a + b)), b - a);
        const std::size_t j = j_end - 1;
        return piece(rateAt(p_.imu, t, 0.5 * (a + t[i])), t[i] - a) * P_[i].transpose() * P_[j] *
               piece(rateAt(p_.imu, t, 0.5 * (t[j] + b)), b - t[j]);
    }

private:
    Eigen::Matrix3d piece(const Eigen::Vector3d& rate, double dt) const {
        return expSO3(p_.R_body_imu * (rate - bias_) * dt);
    }

    const HandEyeProblem& p_;
    Eigen::Vector3d bias_;
    std::vector<Eigen::Matrix3d> P_;
};

void residuals(const HandEyeProblem& p, const GyroPrefix& gyro, const HandEyeParams& x,
               Eigen::VectorXd& r) {
    r.resize(static_cast<Eigen::Index>(3 * p.pairs.size()));
    for (std::size_t k = 0; k < p.pairs.size(); ++k) {
        const HandEyePair& q = p.pairs[k];
        auto turn = [&](double applied) {
            return Eigen::AngleAxisd(x[kHandEyeTurn] - applied, p.axis_body).toRotationMatrix();
        };
        const Eigen::Matrix3d R0 = turn(q.applied_turn0_rad), R1 = turn(q.applied_turn1_rad);
        const Eigen::Matrix3d B =
            gyro.between(q.t0_s + x[kHandEyeImuTime], q.t1_s + x[kHandEyeImuTime]);
        r.segment<3>(static_cast<Eigen::Index>(3 * k)) =
            logSO3(R0.transpose() * q.A * R1 * B.transpose());
    }
}

}  // namespace

Eigen::Matrix3d integrateGyro(const std::vector<ImuSample>& imu, const std::vector<double>& t,
                              double a, double b, const Eigen::Matrix3d& R_body_imu,
                              const Eigen::Vector3d& bias) {
    Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
    double s = a;
    auto it = std::upper_bound(t.begin(), t.end(), a);
    while (s < b) {
        const double e = (it != t.end() && *it < b) ? *it : b;
        if (e > s) R = R * expSO3(R_body_imu * (rateAt(imu, t, 0.5 * (s + e)) - bias) * (e - s));
        s = e;
        if (it != t.end()) ++it;
    }
    return R;
}

Eigen::VectorXd handEyeResiduals(const HandEyeProblem& p, const HandEyeParams& x) {
    Eigen::VectorXd r;
    residuals(p, GyroPrefix(p, x.tail<3>()), x, r);
    return r;
}

HandEyeParams solveHandEye(const HandEyeProblem& p, HandEyeParams x,
                           HandEyeCovariance* covariance) {
    const HandEyeParams step = (HandEyeParams() << 1e-5, 1e-5, 1e-6, 1e-6, 1e-6).finished();
    Eigen::VectorXd r, rp, rm;
    auto eval = [&](const HandEyeParams& at, Eigen::VectorXd& out, const GyroPrefix* same_bias) {
        if (same_bias != nullptr)
            residuals(p, *same_bias, at, out);
        else
            residuals(p, GyroPrefix(p, at.tail<3>()), at, out);
    };
    eval(x, r, nullptr);
    Eigen::Matrix<double, Eigen::Dynamic, kP> J(r.size(), kP);
    for (int it = 0; it < 8; ++it) {
        const GyroPrefix gyro(p, x.tail<3>());
        for (int j = 0; j < kP; ++j) {
            HandEyeParams xp = x, xm = x;
            xp[j] += step[j];
            xm[j] -= step[j];
            // The turn and the time move no bias: the prefix at x serves them.
            const GyroPrefix* same = j < 2 ? &gyro : nullptr;
            eval(xp, rp, same);
            eval(xm, rm, same);
            J.col(j) = (rp - rm) / (2.0 * step[j]);
        }
        std::vector<double> mag(static_cast<std::size_t>(r.size()));
        for (Eigen::Index i = 0; i < r.size(); ++i)
            mag[static_cast<std::size_t>(i)] = std::abs(r[i]);
        std::nth_element(mag.begin(), mag.begin() + static_cast<std::ptrdiff_t>(mag.size() / 2),
                         mag.end());
        const double scale = 1.345 * 1.4826 * std::max(1e-6, mag[mag.size() / 2]);
        HandEyeCovariance H = HandEyeCovariance::Zero();
        HandEyeParams grad = HandEyeParams::Zero();
        double wrss = 0.0;
        for (Eigen::Index i = 0; i < r.size(); ++i) {
            const double w = std::abs(r[i]) <= scale ? 1.0 : scale / std::abs(r[i]);
            H.noalias() += w * J.row(i).transpose() * J.row(i);
            grad.noalias() += w * r[i] * J.row(i).transpose();
            wrss += w * r[i] * r[i];
        }
        // The residuals' variance: the normal equations are in its units, so the prior's
        // information is that over its own variance.
        const double s2 = std::max(1e-18, wrss / std::max(1.0, static_cast<double>(r.size()) - kP));
        for (int j = 0; j < kP; ++j) {
            if (!std::isfinite(p.prior_sigma[j])) continue;
            const double w = s2 / (p.prior_sigma[j] * p.prior_sigma[j]);
            H(j, j) += w;
            grad[j] += w * x[j];
        }
        const HandEyeParams dx = H.ldlt().solve(-grad);
        x += dx;
        eval(x, r, nullptr);
        if (covariance != nullptr)
            *covariance = (wrss / std::max(1.0, static_cast<double>(r.size()) - kP)) *
                          H.ldlt().solve(HandEyeCovariance::Identity());
        if (std::abs(dx[0]) < 1e-7 && std::abs(dx[1]) < 1e-8) break;
    }
    return x;
}

}  // namespace handscan::imu
