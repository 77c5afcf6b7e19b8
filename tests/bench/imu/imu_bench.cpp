// Cost of the IMU prediction per sample (target <= 5 us on one core), of a feedback correction
// (bias window solve + re-integration), of poseAt() queries (one per laser step), and of the
// evaluation tools (ATE/drift on a 30 min trajectory, point-to-mesh distance).
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>

#include "handscan/core/se3.hpp"
#include "handscan/eval/mesh_distance.hpp"
#include "handscan/eval/trajectory_metrics.hpp"
#include "handscan/imu/imu_predictor.hpp"

namespace {

using namespace handscan;

ImuSample sampleAt(int k) {
    const double t = k * 0.005;
    ImuSample s;
    s.t_host = static_cast<TimeNs>(k) * 5 * kNsPerMs;
    s.gyro_radps_imu =
        Eigen::Vector3d(0.3 * std::sin(1.3 * t), 0.2 * std::cos(0.9 * t), 0.5 * std::sin(0.5 * t));
    s.accel_mps2_imu = Eigen::Vector3d(0.5 * std::sin(0.6 * t), 0.4 * std::cos(1.1 * t), 9.81);
    return s;
}

Eigen::Isometry3d camchainLike() {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() << 0, -1, 0, 0, 0, -1, 1, 0, 0;
    T.translation() = Eigen::Vector3d(0.02, 0.03, -0.04);
    return T;
}

// One addImu(): validation, midpoint SO(3) step, history push and trim (15 s horizon, full).
void BM_ImuPredictionPerSample(benchmark::State& state) {
    imu::ImuPredictor p({}, camchainLike());
    p.initialize(imu::NavState{}, {});
    int k = 0;
    for (; k < 200 * 16; ++k) (void)p.addImu(sampleAt(k));  // fill the history
    for (auto _ : state) {
        benchmark::DoNotOptimize(p.addImu(sampleAt(k++)));
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_ImuPredictionPerSample);

// poseAt() at an arbitrary time inside the last sweep (the assembler calls it per laser step).
void BM_PoseAtLaserStep(benchmark::State& state) {
    imu::ImuPredictor p({}, camchainLike());
    p.initialize(imu::NavState{}, {});
    for (int k = 0; k < 200 * 16; ++k) (void)p.addImu(sampleAt(k));
    const TimeNs newest = p.newestTime();
    TimeNs t = newest - kNsPerSec;
    for (auto _ : state) {
        benchmark::DoNotOptimize(p.poseAt(t));
        t += 17'361;  // a Hokuyo step (25 ms / 1440)
        if (t > newest) t = newest - kNsPerSec;
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_PoseAtLaserStep);

// correct(): the 8 s window of 1 Hz feedbacks (robust bias, gravity and velocity solve) +
// re-integration of the 0.3 s after the feedback time.
void BM_FeedbackCorrection(benchmark::State& state) {
    imu::ImuPredictor p({}, camchainLike());
    p.initialize(imu::NavState{}, {});
    int k = 0;
    for (; k < 200 * 10; ++k) (void)p.addImu(sampleAt(k));
    for (auto _ : state) {
        state.PauseTiming();
        for (int j = 0; j < 200; ++j) (void)p.addImu(sampleAt(k++));
        const TimeNs t = p.newestTime() - 300 * kNsPerMs;
        const Eigen::Isometry3d T = *p.poseAt(t);
        state.ResumeTiming();
        benchmark::DoNotOptimize(p.correct(t, T, imu::kAllDofs));
    }
}
BENCHMARK(BM_FeedbackCorrection)->Unit(benchmark::kMicrosecond);

// ATE + drift + end point for a 30 min trajectory at 200 Hz (360k poses).
void BM_EvalTrajectory30min(benchmark::State& state) {
    eval::Trajectory gt, est;
    for (int k = 0; k < 200 * 1800; ++k) {
        const double t = k * 0.005, a = t / 60.0;
        eval::StampedPose p;
        p.t_s = t;
        p.T.translation() =
            Eigen::Vector3d(20 * std::cos(a), 15 * std::sin(a), 0.1 * std::sin(5 * a));
        p.T.linear() = expSO3(Eigen::Vector3d(0, 0, a));
        gt.push_back(p);
        p.T.translation() *= 1.003;
        est.push_back(p);
    }
    for (auto _ : state) {
        const auto pairs = eval::associate(gt, est);
        benchmark::DoNotOptimize(eval::computeAte(pairs));
        benchmark::DoNotOptimize(eval::computeDrift(pairs));
        benchmark::DoNotOptimize(eval::computeEndPoint(pairs));
    }
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(est.size()));
}
BENCHMARK(BM_EvalTrajectory30min)->Unit(benchmark::kMillisecond);

// Point-to-mesh distance against a 200k-triangle scene (a grid-tessellated room, walls wavy).
void BM_MapErrorPerPoint(benchmark::State& state) {
    eval::PlyGeometry m;
    const int n = 316;  // (n-1)^2 * 2 ~ 200k triangles
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
            const double x = 20.0 * i / (n - 1), y = 20.0 * j / (n - 1);
            m.vertices.emplace_back(x, y, 0.3 * std::sin(x) * std::cos(y));
        }
    }
    for (int i = 0; i + 1 < n; ++i) {
        for (int j = 0; j + 1 < n; ++j) {
            const auto v = static_cast<std::uint32_t>(i * n + j);
            const auto un = static_cast<std::uint32_t>(n);
            m.triangles.push_back({v, v + 1, v + un});
            m.triangles.push_back({v + 1, v + un + 1, v + un});
        }
    }
    auto mesh = eval::MeshDistance::build(std::move(m));
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(0.0, 20.0), z(-0.5, 0.5);
    std::vector<Eigen::Vector3d> pts;
    for (int i = 0; i < 4096; ++i) pts.emplace_back(u(rng), u(rng), z(rng));
    std::size_t i = 0;
    for (auto _ : state) {
        benchmark::DoNotOptimize((*mesh)->distance(pts[i++ & 4095]));
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_MapErrorPerPoint);

}  // namespace
