#include "handscan/imu/bias_estimator.hpp"

#include <Eigen/Dense>
#include <string>
#include <vector>

namespace handscan::imu {

Result<BiasUpdate> BiasEstimator::add(const FeedbackPose& f, const ImuHistory& history,
                                      const ImuBiases& current, const Eigen::Vector3d& gravity) {
    BiasUpdate out;
    out.biases = current;
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
    while (!window_.empty() &&
           (toSeconds(f.t - window_.front().t) > config_.window_s || window_.front().t < history.front())) {
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

    // 1. Gyro bias from the rotation residuals, rows projected on the world rotation DOFs solved
    //    at both ends of the interval.
    Eigen::Matrix3d H = config_.gyro_prior_weight * Eigen::Matrix3d::Identity();
    Eigen::Vector3d g = Eigen::Vector3d::Zero();
    for (int i = 0; i < n; ++i) {
        const FeedbackPose& a = window_[i];
        const FeedbackPose& b = window_[i + 1];
        const Eigen::Matrix3d Q = a.solved.topLeftCorner<3, 3>() * b.solved.topLeftCorner<3, 3>();
        const Eigen::Vector3d r = logSO3(pre[i].dR.transpose() * a.R_world_imu.transpose() * b.R_world_imu);
        const Eigen::Matrix3d A = Q * b.R_world_imu * pre[i].dR_dbg;  // world-frame rows
        H += A.transpose() * A;
        g += A.transpose() * (Q * b.R_world_imu * r);
    }
    const Eigen::Vector3d dbg = H.ldlt().solve(g);
    ImuBiases b1 = current;
    b1.gyro_radps += dbg;
    out.gyro_updated = dbg.squaredNorm() > 0.0;

    // 2. Velocities v_0..v_n and the accel bias change; the accel bias only with >= 2 intervals
    //    (with one, it cannot be told from the initial velocity).
    const bool solve_ba = n >= 2;
    const int nv = 3 * (n + 1);
    const int nx = nv + (solve_ba ? 3 : 0);
    Eigen::MatrixXd Hx = Eigen::MatrixXd::Zero(nx, nx);
    Eigen::VectorXd gx = Eigen::VectorXd::Zero(nx);
    auto addRows = [&](const Eigen::MatrixXd& A, const Eigen::VectorXd& r) {
        Hx.noalias() += A.transpose() * A;
        gx.noalias() += A.transpose() * r;
    };
    for (int i = 0; i <= n; ++i) {  // velocity priors
        Eigen::MatrixXd A = Eigen::MatrixXd::Zero(3, nx);
        A.block<3, 3>(0, 3 * i).setIdentity();
        addRows(config_.velocity_prior_weight * A, config_.velocity_prior_weight * window_[i].v_predicted);
    }
    if (solve_ba) {
        Eigen::MatrixXd A = Eigen::MatrixXd::Zero(3, nx);
        A.block<3, 3>(0, nv).setIdentity();
        addRows(config_.accel_prior_weight * A, Eigen::VectorXd::Zero(3));
    }
    for (int i = 0; i < n; ++i) {
        const FeedbackPose& a = window_[i];
        const FeedbackPose& b = window_[i + 1];
        const double dt = pre[i].dt_s;
        const Eigen::Matrix3d Q = a.solved.bottomRightCorner<3, 3>() * b.solved.bottomRightCorner<3, 3>();
        // Position: p_j - p_i - g dt^2/2 - R_i dp(b1) = v_i dt + R_i dp_dba dba
        Eigen::MatrixXd A = Eigen::MatrixXd::Zero(3, nx);
        A.block<3, 3>(0, 3 * i) = Q * dt;
        if (solve_ba) A.block<3, 3>(0, nv) = Q * a.R_world_imu * pre[i].dp_dba;
        const Eigen::Vector3d rp = Q * (b.p_world_imu - a.p_world_imu - 0.5 * gravity * dt * dt -
                                        a.R_world_imu * pre[i].position(b1));
        addRows(A, rp);
        // Velocity continuity: v_j - v_i - R_i dv_dba dba = g dt + R_i dv(b1)
        const double w = config_.velocity_row_weight;
        Eigen::MatrixXd B = Eigen::MatrixXd::Zero(3, nx);
        B.block<3, 3>(0, 3 * (i + 1)) = w * Eigen::Matrix3d::Identity();
        B.block<3, 3>(0, 3 * i) = -w * Eigen::Matrix3d::Identity();
        if (solve_ba) B.block<3, 3>(0, nv) = -w * a.R_world_imu * pre[i].dv_dba;
        addRows(B, w * (gravity * dt + a.R_world_imu * pre[i].velocity(b1)));
    }
    const Eigen::VectorXd x = Hx.ldlt().solve(gx);
    if (!x.allFinite()) {
        return Status(StatusCode::kInvalidArgument, "IMU bias feedback: singular velocity/bias system; ignored");
    }
    ImuBiases b2 = b1;
    if (solve_ba) {
        b2.accel_mps2 += x.segment<3>(nv);
        out.accel_updated = true;
    }
    if (b2.gyro_radps.norm() > config_.max_gyro_bias_radps ||
        b2.accel_mps2.norm() > config_.max_accel_bias_mps2) {
        window_.clear();  // the window holds an inconsistent pose; start over from the next one
        return Status(StatusCode::kInvalidArgument,
                      "IMU bias feedback: implausible biases (gyro " + std::to_string(b2.gyro_radps.norm()) +
                          " rad/s, accel " + std::to_string(b2.accel_mps2.norm()) +
                          " m/s^2) from the feedback window; kept the previous biases");
    }
    out.biases = b2;
    // Velocity at the newest pose only in the solved translation DOFs (eq. (26)).
    const Eigen::Matrix3d Qn = window_.back().solved.bottomRightCorner<3, 3>();
    out.v_world_imu_latest = f.v_predicted + Qn * (x.segment<3>(3 * n) - f.v_predicted);
    return out;
}

}  // namespace handscan::imu
