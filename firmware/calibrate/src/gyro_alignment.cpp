#include "handscan/calibrate/gyro_alignment.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <variant>

#include "handscan/core/se3.hpp"
#include "handscan/sources/recorded_source.hpp"

namespace handscan::calibrate {
namespace {

constexpr int kP = 5;  // eps, dt, bias x y z
using Params = Eigen::Matrix<double, kP, 1>;

// Sweep pairs this many sweeps apart: 1 (half a turn) and 4 (two turns, more rotation per pair).
constexpr int kGaps[] = {1, 4};

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
    Params x = Params::Zero();
    Eigen::VectorXd r;
    residuals(pairs, imu, t, R_body_imu, a, x, r);
    const auto n = static_cast<double>(pairs.size());
    out.rms_before_rad = std::sqrt(r.squaredNorm() / (3.0 * n));
    const Params step = (Params() << 1e-5, 1e-5, 1e-6, 1e-6, 1e-6).finished();
    Eigen::Matrix<double, Eigen::Dynamic, kP> J;
    for (int it = 0; it < 10; ++it) {
        J.resize(r.size(), kP);
        Eigen::VectorXd rp, rm;
        for (int j = 0; j < kP; ++j) {
            Params xp = x, xm = x;
            xp[j] += step[j];
            xm[j] -= step[j];
            residuals(pairs, imu, t, R_body_imu, a, xp, rp);
            residuals(pairs, imu, t, R_body_imu, a, xm, rm);
            J.col(j) = (rp - rm) / (2.0 * step[j]);
        }
        // Gauss-Newton with a Huber weight per pair (a bad match must not steer the clock).
        const double scale =
            1.345 * 1.4826 * std::max(1e-6, [&] {
                std::vector<double> v(static_cast<std::size_t>(r.size()));
                for (Eigen::Index i = 0; i < r.size(); ++i)
                    v[static_cast<std::size_t>(i)] = std::abs(r[i]);
                std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2),
                                 v.end());
                return v[v.size() / 2];
            }());
        Eigen::Matrix<double, kP, kP> H = Eigen::Matrix<double, kP, kP>::Zero();
        Params g = Params::Zero();
        double wrss = 0.0;
        for (Eigen::Index i = 0; i < r.size(); ++i) {
            const double w = std::abs(r[i]) <= scale ? 1.0 : scale / std::abs(r[i]);
            H.noalias() += w * J.row(i).transpose() * J.row(i);
            g.noalias() += w * r[i] * J.row(i).transpose();
            wrss += w * r[i] * r[i];
        }
        const Params dx = H.ldlt().solve(-g);
        x += dx;
        residuals(pairs, imu, t, R_body_imu, a, x, r);
        const Eigen::Matrix<double, kP, kP> cov =
            (wrss / std::max(1.0, 3.0 * n - kP)) *
            H.ldlt().solve(Eigen::Matrix<double, kP, kP>::Identity());
        out.zero_std_rad = std::sqrt(cov(0, 0));
        out.imu_time_std_s = std::sqrt(cov(1, 1));
        if (std::abs(dx[0]) < 1e-3 * out.zero_std_rad &&
            std::abs(dx[1]) < 1e-3 * out.imu_time_std_s)
            break;
    }
    out.zero_rad = x[0];
    out.imu_time_s = x[1];
    out.gyro_bias = x.tail<3>();
    out.rms_after_rad = std::sqrt(r.squaredNorm() / (3.0 * n));
    return out;
}

}  // namespace handscan::calibrate
