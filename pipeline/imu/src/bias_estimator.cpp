#include "handscan/imu/bias_estimator.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "handscan/imu/dof_projector.hpp"

namespace handscan::imu {
namespace {

// The first of the three unknowns of velocity i in the least-squares state (v_0 .. v_n first).
Eigen::Index velocityIndex(int i) { return Eigen::Index{3} * i; }

}  // namespace

Result<BiasUpdate> BiasEstimator::add(const FeedbackPose& f, const ImuHistory& history,
                                      const ImuBiases& current, const Eigen::Vector3d& gravity) {
    BiasUpdate out;
    out.biases = current;
    out.gravity_world = gravity;
    out.v_world_imu_latest = f.v_predicted;
    if (!window_.empty() && toSeconds(f.t - window_.back().t) < config_.min_spacing_s) {
        if (f.t <= window_.back().t) {
            return Status(StatusCode::kInvalidArgument,
                          "IMU bias feedback: pose at t=" + std::to_string(f.t) +
                              " ns is not newer than the previous one; feed poses in time order");
        }
        window_.back() = f;  // too close for a meaningful interval: keep the newest only
        if (window_.size() < 2) return out;
    } else {
        window_.push_back(f);
    }
    while (!window_.empty() && (toSeconds(f.t - window_.front().t) > config_.window_s ||
                                window_.front().t < history.front())) {
        window_.pop_front();
    }
    const int n = static_cast<int>(window_.size()) - 1;  // intervals
    out.intervals = std::max(n, 0);
    if (n < 1) return out;

    std::vector<Preintegrated> pre;
    pre.reserve(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
        auto p = history.preintegrate(window_[i].t, window_[i + 1].t, current);
        if (!p) return p.status();
        pre.push_back(std::move(*p));
    }

    // Tukey biweight of a whitened residual norm: an interval whose feedback jumps by many
    // sigmas (a matcher slip, or the snap back after one) carries no weight at all - a bounded
    // influence (Huber) still let a 19 cm snap-back bend the velocity by 0.1 m/s.
    const double k = config_.robust_c;
    auto huber = [k](double e) {
        if (e >= k) return 0.0;
        const double u = 1.0 - (e / k) * (e / k);
        return u * u;
    };
    const int iterations = std::max(1, config_.robust_iterations);

    // 1. Gyro bias from the rotation residuals, rows projected on the world rotation DOFs solved
    //    at both ends of the interval, whitened by the feedback's rotation noise (both ends).
    const double sr = std::sqrt(2.0) * config_.feedback_sigma_rad;
    std::vector<Eigen::Matrix3d> Ar(static_cast<std::size_t>(n));
    std::vector<Eigen::Vector3d> rr(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
        const FeedbackPose& a = window_[i];
        const FeedbackPose& b = window_[i + 1];
        const Eigen::Matrix3d Q = a.solved.topLeftCorner<3, 3>() * b.solved.topLeftCorner<3, 3>();
        const Eigen::Vector3d r =
            logSO3(pre[i].dR.transpose() * a.R_world_imu.transpose() * b.R_world_imu);
        Ar[i] = Q * b.R_world_imu * pre[i].dR_dbg / sr;  // world-frame rows
        rr[i] = Q * b.R_world_imu * r / sr;
    }
    const double pg = 1.0 / config_.gyro_bias_step_sigma_radps;
    Eigen::Vector3d dbg = Eigen::Vector3d::Zero();
    for (int iter = 0; iter < iterations; ++iter) {
        Eigen::Matrix3d H = pg * pg * Eigen::Matrix3d::Identity();
        Eigen::Vector3d g = Eigen::Vector3d::Zero();
        for (int i = 0; i < n; ++i) {
            const double w = iter == 0 ? 1.0 : huber((rr[i] - Ar[i] * dbg).norm());
            H += w * Ar[i].transpose() * Ar[i];
            g += w * Ar[i].transpose() * rr[i];
        }
        dbg = H.ldlt().solve(g);
    }
    ImuBiases b1 = current;
    b1.gyro_radps += dbg;
    out.gyro_updated = dbg.squaredNorm() > 0.0;

    // 2. Velocities v_0..v_n and the accel bias change; the accel bias only with >= 2 intervals
    //    (with one, it cannot be told from the initial velocity). Position rows compare the
    //    feedback positions (noise of both ends), velocity rows chain the IMU's velocity
    //    increments; both are whitened, the position rows robustly weighted per interval.
    //    The horizontal gravity correction dg (world x, y) is solved along with the accel bias.
    const bool solve_ba = n >= 2;
    const int nv = 3 * (n + 1);
    const int ng = nv + 3;  // index of dg
    const int nx = nv + (solve_ba ? 5 : 0);
    Eigen::Matrix<double, 3, 2> E = Eigen::Matrix<double, 3, 2>::Zero();
    E(0, 0) = E(1, 1) = 1.0;
    const double sp = std::sqrt(2.0) * config_.feedback_sigma_m;
    std::vector<Eigen::MatrixXd> Ap(static_cast<std::size_t>(n)), Av(static_cast<std::size_t>(n));
    std::vector<Eigen::Vector3d> rp(static_cast<std::size_t>(n)), rv(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
        const FeedbackPose& a = window_[i];
        const FeedbackPose& b = window_[i + 1];
        const double dt = pre[i].dt_s;
        const Eigen::Matrix3d Q =
            a.solved.bottomRightCorner<3, 3>() * b.solved.bottomRightCorner<3, 3>();
        // Position: p_j - p_i - g dt^2/2 - R_i dp(b1) = v_i dt + R_i dp_dba dba
        Ap[i] = Eigen::MatrixXd::Zero(3, nx);
        Ap[i].block<3, 3>(0, velocityIndex(i)) = Q * dt / sp;
        if (solve_ba) {
            Ap[i].block<3, 3>(0, nv) = Q * a.R_world_imu * pre[i].dp_dba / sp;
            Ap[i].block<3, 2>(0, ng) = Q * E * (0.5 * dt * dt / sp);
        }
        rp[i] = Q *
                (b.p_world_imu - a.p_world_imu - 0.5 * gravity * dt * dt -
                 a.R_world_imu * pre[i].position(b1)) /
                sp;
        // Velocity continuity: v_j - v_i - R_i dv_dba dba = g dt + R_i dv(b1)
        const double sv = config_.velocity_sigma_mps + config_.velocity_sigma_mps2 * dt;
        Av[i] = Eigen::MatrixXd::Zero(3, nx);
        Av[i].block<3, 3>(0, velocityIndex(i + 1)) = Eigen::Matrix3d::Identity() / sv;
        Av[i].block<3, 3>(0, velocityIndex(i)) = -Eigen::Matrix3d::Identity() / sv;
        if (solve_ba) {
            Av[i].block<3, 3>(0, nv) = -a.R_world_imu * pre[i].dv_dba / sv;
            Av[i].block<3, 2>(0, ng) = -E * (dt / sv);
        }
        rv[i] = (gravity * dt + a.R_world_imu * pre[i].velocity(b1)) / sv;
    }
    Eigen::MatrixXd H0 = Eigen::MatrixXd::Zero(nx, nx);
    Eigen::VectorXd g0 = Eigen::VectorXd::Zero(nx);
    const double wv = 1.0 / config_.velocity_prior_sigma_mps;
    for (int i = 0; i <= n; ++i) {  // velocity priors
        H0.block<3, 3>(velocityIndex(i), velocityIndex(i)) += wv * wv * Eigen::Matrix3d::Identity();
        g0.segment<3>(velocityIndex(i)) += wv * wv * window_[i].v_predicted;
    }
    if (solve_ba) {
        const double wa = 1.0 / config_.accel_bias_step_sigma_mps2;
        H0.block<3, 3>(nv, nv) += wa * wa * Eigen::Matrix3d::Identity();
        const double wg = 1.0 / config_.gravity_step_sigma_mps2;
        H0.block<2, 2>(ng, ng) += wg * wg * Eigen::Matrix2d::Identity();
    }
    for (int i = 0; i < n; ++i) {
        H0.noalias() += Av[i].transpose() * Av[i];
        g0.noalias() += Av[i].transpose() * rv[i];
    }
    Eigen::VectorXd x = Eigen::VectorXd::Zero(nx);
    for (int iter = 0; iter < iterations; ++iter) {
        Eigen::MatrixXd Hx = H0;
        Eigen::VectorXd gx = g0;
        for (int i = 0; i < n; ++i) {
            const double w = iter == 0 ? 1.0 : huber((Ap[i] * x - rp[i]).norm());
            Hx.noalias() += w * Ap[i].transpose() * Ap[i];
            gx.noalias() += w * Ap[i].transpose() * rp[i];
        }
        x = Hx.ldlt().solve(gx);
    }
    if (!x.allFinite()) {
        return Status(StatusCode::kInvalidArgument,
                      "IMU bias feedback: singular velocity/bias system; ignored");
    }
    ImuBiases b2 = b1;
    Eigen::Vector3d g2 = gravity;
    if (solve_ba) {
        // Nothing is fed from unsolved translation directions (section 8): the changes of the
        // accel bias and of gravity are kept only where they act along directions the newest
        // feedback solved. Along an unsolved axis they were set by the weak velocity priors
        // alone, i.e. by the IMU's own runaway velocity.
        const Eigen::Matrix3d keep =
            Eigen::Matrix3d::Identity() - unsolvedTranslation(window_.back().solved);
        const Eigen::Matrix3d& Rn = window_.back().R_world_imu;
        b2.accel_mps2 += Rn.transpose() * keep * Rn * x.segment<3>(nv);
        // The correction turns gravity; its magnitude stays (the vertical is the accel bias's).
        g2 = (gravity + keep * E * x.segment<2>(ng)).normalized() * gravity.norm();
        out.accel_updated = true;
    }
    const double tilt = std::acos(std::clamp(-g2.z() / g2.norm(), -1.0, 1.0));
    if (b2.gyro_radps.norm() > config_.max_gyro_bias_radps ||
        b2.accel_mps2.norm() > config_.max_accel_bias_mps2 || tilt > config_.max_gravity_tilt_rad) {
        window_.clear();  // the window holds an inconsistent pose; start over from the next one
        return Status(
            StatusCode::kInvalidArgument,
            "IMU bias feedback: implausible biases (gyro " + std::to_string(b2.gyro_radps.norm()) +
                " rad/s, accel " + std::to_string(b2.accel_mps2.norm()) + " m/s^2, gravity tilt " +
                std::to_string(tilt) + " rad) from the feedback window; kept the previous biases");
    }
    out.biases = b2;
    out.gravity_world = g2;
    // Velocity at the newest pose only in the solved translation DOFs (eq. (26)).
    const Eigen::Matrix3d Qn = window_.back().solved.bottomRightCorner<3, 3>();
    out.v_world_imu_latest = f.v_predicted + Qn * (x.segment<3>(velocityIndex(n)) - f.v_predicted);
    return out;
}

}  // namespace handscan::imu
