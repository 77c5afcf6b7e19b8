#include "handscan/calibrate/gyro_alignment.hpp"

#include <algorithm>
#include <cmath>
#include <variant>

#include "handscan/sources/recorded_source.hpp"

namespace handscan::calibrate {
namespace {

// Sweep pairs this many sweeps apart: 1 (half a turn) and 4 (two turns, more rotation per pair).
constexpr int kGaps[] = {1, 4};
constexpr int kJackknifeBlocks = 8;
constexpr int kP = 5;

}  // namespace

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
                                const std::vector<ImuSample>& gyro,
                                const Eigen::Matrix3d& R_body_imu, const Eigen::Vector3d& axis) {
    imu::HandEyeProblem problem;
    problem.imu = gyro;
    problem.t_s.resize(gyro.size());
    for (std::size_t i = 0; i < gyro.size(); ++i) problem.t_s[i] = toSeconds(gyro[i].t_host);
    problem.R_body_imu = R_body_imu;
    problem.axis_body = axis.normalized();
    const std::vector<double>& t = problem.t_s;
    std::vector<imu::HandEyePair>& pairs = problem.pairs;
    for (std::size_t i = 0; i < sweeps.size(); ++i)
        for (int gap : kGaps)
            for (std::size_t j = i + 1; j < sweeps.size() && j <= i + static_cast<std::size_t>(gap);
                 ++j)
                if (sweeps[j].index == sweeps[i].index + static_cast<std::uint64_t>(gap) &&
                    sweeps[i].t_s > t.front() + 0.05 && sweeps[j].t_s < t.back() - 0.05)
                    pairs.push_back({sweeps[i].t_s, sweeps[j].t_s,
                                     (sweeps[i].q_world_body.conjugate() * sweeps[j].q_world_body)
                                         .toRotationMatrix(),
                                     0.0, 0.0});
    if (pairs.size() < 10)
        return Status{StatusCode::kInvalidArgument,
                      "calibrate: only " + std::to_string(pairs.size()) +
                          " pairs of trusted sweeps; the gyro alignment needs 10 or more (walk "
                          "longer, or start from a calibration closer to the truth)"};
    GyroAlignment out;
    out.pairs = pairs.size();
    Eigen::VectorXd r = imu::handEyeResiduals(problem, imu::HandEyeParams::Zero());
    out.rms_before_rad = std::sqrt(r.squaredNorm() / static_cast<double>(r.size()));
    imu::HandEyeCovariance formal;
    const imu::HandEyeParams x = imu::solveHandEye(problem, imu::HandEyeParams::Zero(), &formal);
    r = imu::handEyeResiduals(problem, x);
    out.rms_after_rad = std::sqrt(r.squaredNorm() / static_cast<double>(r.size()));
    // The formal covariance trusts every pair alike, but overlapping pairs and the matcher's slowly
    // varying errors are not independent (measured: the zero scatters ~3x its formal std over
    // seeds). So also a delete-one-block jackknife over kJackknifeBlocks spans of the walk; the
    // larger variance is reported.
    const double t0 = pairs.front().t0_s, span = pairs.back().t1_s - t0;
    Eigen::Matrix<double, kP, Eigen::Dynamic> leave_out(kP, kJackknifeBlocks);
    for (int b = 0; b < kJackknifeBlocks; ++b) {
        imu::HandEyeProblem kept = problem;
        kept.pairs.clear();
        for (const imu::HandEyePair& p : pairs)
            if (std::min(kJackknifeBlocks - 1,
                         static_cast<int>((p.t0_s - t0) / span * kJackknifeBlocks)) != b)
                kept.pairs.push_back(p);
        leave_out.col(b) = imu::solveHandEye(kept, x);
    }
    const imu::HandEyeParams mean = leave_out.rowwise().mean();
    const double g = static_cast<double>(kJackknifeBlocks);
    const imu::HandEyeParams jackknife =
        (g - 1.0) / g * (leave_out.colwise() - mean).array().square().rowwise().sum();
    out.zero_rad = x[0];
    out.imu_time_s = x[1];
    out.gyro_bias = x.tail<3>();
    out.zero_std_rad = std::sqrt(std::max(formal(0, 0), jackknife[0]));
    out.imu_time_std_s = std::sqrt(std::max(formal(1, 1), jackknife[1]));
    return out;
}

}  // namespace handscan::calibrate
