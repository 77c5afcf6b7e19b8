#include "handscan/calibrate/gyro_alignment.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <map>
#include <variant>

#include "handscan/core/se3.hpp"
#include "handscan/sources/recorded_source.hpp"

namespace handscan::calibrate {
namespace {

constexpr int kP = 5;  // eps, dt, bias x y z
using Params = Eigen::Matrix<double, kP, 1>;

// Sweep pairs this many sweeps apart: 1 (half a turn) and 4 (two turns, more rotation per pair).
constexpr int kGaps[] = {1, 4};
constexpr int kJackknifeBlocks = 8;

struct Pair {
    double t0 = 0.0, t1 = 0.0;
    Eigen::Matrix3d A;  // the laser's rotation increment, body frame at t0
};

void residuals(const std::vector<Pair>& pairs, const std::vector<ImuSample>& imu,
               const std::vector<double>& t, const Eigen::Matrix3d& R_body_imu,
               const Eigen::Vector3d& axis, const Params& x, Eigen::VectorXd& r) {
    r.resize(static_cast<Eigen::Index>(3 * pairs.size()));
    const Eigen::Matrix3d R = Eigen::AngleAxisd(x[0], axis).toRotationMatrix();
    for (std::size_t k = 0; k < pairs.size(); ++k) {
        const Eigen::Matrix3d B =
            integrateGyro(imu, t, pairs[k].t0 + x[1], pairs[k].t1 + x[1], R_body_imu, x.tail<3>());
        r.segment<3>(static_cast<Eigen::Index>(3 * k)) =
            logSO3(R.transpose() * pairs[k].A * R * B.transpose());
    }
}

// Gauss-Newton with Huber weights per residual (a bad match must not steer the clock), from x0;
// the formal covariance at the solution when asked.
Params gaussNewton(const std::vector<Pair>& pairs, const std::vector<ImuSample>& imu,
                   const std::vector<double>& t, const Eigen::Matrix3d& R_body_imu,
                   const Eigen::Vector3d& axis, Params x,
                   Eigen::Matrix<double, kP, kP>* covariance) {
    const Params step = (Params() << 1e-5, 1e-5, 1e-6, 1e-6, 1e-6).finished();
    Eigen::VectorXd r, rp, rm;
    residuals(pairs, imu, t, R_body_imu, axis, x, r);
    Eigen::Matrix<double, Eigen::Dynamic, kP> J(r.size(), kP);
    for (int it = 0; it < 8; ++it) {
        for (int j = 0; j < kP; ++j) {
            Params xp = x, xm = x;
            xp[j] += step[j];
            xm[j] -= step[j];
            residuals(pairs, imu, t, R_body_imu, axis, xp, rp);
            residuals(pairs, imu, t, R_body_imu, axis, xm, rm);
            J.col(j) = (rp - rm) / (2.0 * step[j]);
        }
        std::vector<double> mag(static_cast<std::size_t>(r.size()));
        for (Eigen::Index i = 0; i < r.size(); ++i)
            mag[static_cast<std::size_t>(i)] = std::abs(r[i]);
        std::nth_element(mag.begin(), mag.begin() + static_cast<std::ptrdiff_t>(mag.size() / 2),
                         mag.end());
        const double scale = 1.345 * 1.4826 * std::max(1e-6, mag[mag.size() / 2]);
        Eigen::Matrix<double, kP, kP> H = Eigen::Matrix<double, kP, kP>::Zero();
        Params grad = Params::Zero();
        double wrss = 0.0;
        for (Eigen::Index i = 0; i < r.size(); ++i) {
            const double w = std::abs(r[i]) <= scale ? 1.0 : scale / std::abs(r[i]);
            H.noalias() += w * J.row(i).transpose() * J.row(i);
            grad.noalias() += w * r[i] * J.row(i).transpose();
            wrss += w * r[i] * r[i];
        }
        const Params dx = H.ldlt().solve(-grad);
        x += dx;
        residuals(pairs, imu, t, R_body_imu, axis, x, r);
        if (covariance != nullptr)
            *covariance = (wrss / std::max(1.0, static_cast<double>(r.size()) - kP)) *
                          H.ldlt().solve(Eigen::Matrix<double, kP, kP>::Identity());
        if (std::abs(dx[0]) < 1e-7 && std::abs(dx[1]) < 1e-8) break;
    }
    return x;
}

}  // namespace

Eigen::Matrix3d integrateGyro(const std::vector<ImuSample>& imu, const std::vector<double>& t,
                              double a, double b, const Eigen::Matrix3d& R_body_imu,
                              const Eigen::Vector3d& bias) {
    auto rate = [&](double s) {
        auto it = std::upper_bound(t.begin(), t.end(), s);
        if (it == t.begin()) return imu.front().gyro_radps_imu;
        if (it == t.end()) return imu.back().gyro_radps_imu;
        const auto i = static_cast<std::size_t>(it - t.begin());
        const double u = (s - t[i - 1]) / (t[i] - t[i - 1]);
        return Eigen::Vector3d((1.0 - u) * imu[i - 1].gyro_radps_imu + u * imu[i].gyro_radps_imu);
    };
    Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
    double s = a;
    auto it = std::upper_bound(t.begin(), t.end(), a);
    while (s < b) {
        const double e = (it != t.end() && *it < b) ? *it : b;
        if (e > s) R = R * expSO3(R_body_imu * (rate(0.5 * (s + e)) - bias) * (e - s));
        s = e;
        if (it != t.end()) ++it;
    }
    return R;
}

Result<std::vector<ImuSample>> loadImu(const std::string& recording, const DeviceConfig& device) {
    sources::RecordedSourceOptions options;
    options.laser = false;
    options.colour = false;
    options.fast = true;
    auto opened = sources::RecordedSource::open(recording, device, options);
    if (!opened.isOk()) return opened.status();
    std::vector<ImuSample> imu;
    std::vector<sources::Sample> samples;
    for (;;) {
        samples.clear();
        auto clock = (*opened)->next(samples);
        if (!clock.isOk()) return clock.status();
        for (auto& s : samples)
            if (auto* i = std::get_if<ImuSample>(&s)) imu.push_back(*i);
        if (!clock->has_value()) break;
    }
    std::stable_sort(imu.begin(), imu.end(),
                     [](const ImuSample& a, const ImuSample& b) { return a.t_host < b.t_host; });
    if (imu.size() < 2)
        return Status{StatusCode::kInvalidArgument,
                      recording +
                          ": no /xsens/raw samples decoded; the IMU's time offset and the "
                          "encoder zero need the gyro"};
    return imu;
}

Result<GyroAlignment> alignGyro(const std::vector<MatchedSweepPose>& sweeps,
                                const std::vector<ImuSample>& imu,
                                const Eigen::Matrix3d& R_body_imu, const Eigen::Vector3d& axis) {
    std::vector<double> t(imu.size());
    for (std::size_t i = 0; i < imu.size(); ++i) t[i] = toSeconds(imu[i].t_host);
    std::vector<Pair> pairs;
    for (std::size_t i = 0; i < sweeps.size(); ++i)
        for (int gap : kGaps)
            for (std::size_t j = i + 1; j < sweeps.size() && j <= i + static_cast<std::size_t>(gap);
                 ++j)
                if (sweeps[j].index == sweeps[i].index + static_cast<std::uint64_t>(gap) &&
                    sweeps[i].t_s > t.front() + 0.05 && sweeps[j].t_s < t.back() - 0.05)
                    pairs.push_back({sweeps[i].t_s, sweeps[j].t_s,
                                     (sweeps[i].q_world_body.conjugate() * sweeps[j].q_world_body)
                                         .toRotationMatrix()});
    if (pairs.size() < 10)
        return Status{StatusCode::kInvalidArgument,
                      "calibrate: only " + std::to_string(pairs.size()) +
                          " pairs of trusted sweeps; the gyro alignment needs 10 or more (walk "
                          "longer, or start from a calibration closer to the truth)"};
    const Eigen::Vector3d a = axis.normalized();
    GyroAlignment out;
    out.pairs = pairs.size();
    Eigen::VectorXd r;
    residuals(pairs, imu, t, R_body_imu, a, Params::Zero(), r);
    out.rms_before_rad = std::sqrt(r.squaredNorm() / static_cast<double>(r.size()));
    Eigen::Matrix<double, kP, kP> formal;
    const Params x = gaussNewton(pairs, imu, t, R_body_imu, a, Params::Zero(), &formal);
    residuals(pairs, imu, t, R_body_imu, a, x, r);
    out.rms_after_rad = std::sqrt(r.squaredNorm() / static_cast<double>(r.size()));
    // The formal covariance trusts every pair alike, but overlapping pairs and the matcher's slowly
    // varying errors are not independent (measured: the zero scatters ~3x its formal std over
    // seeds). So also a delete-one-block jackknife over kJackknifeBlocks spans of the walk; the
    // larger variance is reported.
    const double t0 = pairs.front().t0, span = pairs.back().t1 - t0;
    Eigen::Matrix<double, kP, Eigen::Dynamic> leave_out(kP, kJackknifeBlocks);
    for (int b = 0; b < kJackknifeBlocks; ++b) {
        std::vector<Pair> kept;
        for (const Pair& p : pairs)
            if (std::min(kJackknifeBlocks - 1,
                         static_cast<int>((p.t0 - t0) / span * kJackknifeBlocks)) != b)
                kept.push_back(p);
        leave_out.col(b) = gaussNewton(kept, imu, t, R_body_imu, a, x, nullptr);
    }
    const Params mean = leave_out.rowwise().mean();
    const double g = static_cast<double>(kJackknifeBlocks);
    const Params jackknife =
        (g - 1.0) / g * (leave_out.colwise() - mean).array().square().rowwise().sum();
    out.zero_rad = x[0];
    out.imu_time_s = x[1];
    out.gyro_bias = x.tail<3>();
    out.zero_std_rad = std::sqrt(std::max(formal(0, 0), jackknife[0]));
    out.imu_time_std_s = std::sqrt(std::max(formal(1, 1), jackknife[1]));
    return out;
}

}  // namespace handscan::calibrate
