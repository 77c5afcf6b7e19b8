// Cost of re-placing a sweep with the corrected IMU motion before it is matched (IMU feedback):
// one half-revolution sweep of the UTM-30LX (~21k points over 0.5 s), the motion sampled every
// 2 ms from a real ImuPredictor history; and of one solve of the online clock tracker.
#include <benchmark/benchmark.h>

#include <cmath>

#include "handscan/core/se3.hpp"
#include "handscan/imu/imu_predictor.hpp"
#include "handscan/lio/clock_tracker.hpp"
#include "handscan/lio/motion_compensation.hpp"

namespace {

using namespace handscan;

void BM_RecompensateHalfRevolutionSweep(benchmark::State& state) {
    imu::ImuPredictor p({}, Eigen::Isometry3d::Identity());
    p.initialize(imu::NavState{}, {});
    for (int k = 0; k < 200 * 2; ++k) {
        const double t = k * 0.005;
        ImuSample s;
        s.t_host = static_cast<TimeNs>(k) * 5 * kNsPerMs;
        s.gyro_radps_imu = Eigen::Vector3d(0.3 * std::sin(1.3 * t), 0.2 * std::cos(0.9 * t),
                                           0.5 * std::sin(0.5 * t));
        s.accel_mps2_imu = Eigen::Vector3d(0.5 * std::sin(0.6 * t), 0.4 * std::cos(1.1 * t), 9.81);
        (void)p.addImu(s);
    }
    scan::Sweep sweep;
    sweep.t_start = 1 * kNsPerSec;
    for (int i = 0; i < 21000; ++i) {
        scan::SweepPoint pt;
        pt.t = sweep.t_start + static_cast<TimeNs>(i) * 500 * kNsPerMs / 21000;
        pt.p_body = Eigen::Vector3d(3.0 * std::cos(0.01 * i), 2.0 * std::sin(0.01 * i), 1.0);
        sweep.points.push_back(pt);
    }
    auto query = [&p](TimeNs t) { return p.poseAt(t); };
    for (auto _ : state) {
        benchmark::DoNotOptimize(lio::recompensateSweep(sweep, query));
    }
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(sweep.points.size()));
}
BENCHMARK(BM_RecompensateHalfRevolutionSweep)->Unit(benchmark::kMillisecond);

// One solve of the online clock tracker with a full window: 30 s of trusted sweeps (2 per s, pairs
// 1 and 4 apart: ~115 pairs) against 35 s of 200 Hz gyro. It runs every 2 s of a scan.
void BM_ClockTrackerSolve(benchmark::State& state) {
    auto rotation = [](double t) {
        return expSO3(Eigen::Vector3d(0.4 * std::sin(1.3 * t), 0.3 * std::sin(0.9 * t + 0.5),
                                      0.6 * std::sin(0.5 * t)));
    };
    lio::ClockTrackerConfig config;
    config.update_period_s = 0.0;
    lio::ClockTracker tracker(config, Eigen::Matrix3d::Identity(), Eigen::Vector3d::UnitZ());
    const double h = 1e-4;
    for (int i = 0; i <= 200 * 35; ++i) {
        const double t = 0.005 * i;
        ImuSample s;
        s.t_host = fromSeconds(t);
        s.gyro_radps_imu = logSO3(rotation(t - h).transpose() * rotation(t + h)) / (2.0 * h);
        tracker.addImu(s);
        if (i % 100 == 0 && i > 0)
            tracker.addSweep(static_cast<std::uint64_t>(i / 100), fromSeconds(t),
                             Eigen::Quaterniond(rotation(t)), true);
    }
    double pairs = 0.0;
    for (auto _ : state) {
        state.PauseTiming();
        lio::ClockTracker fresh = tracker;  // not solved yet
        state.ResumeTiming();
        benchmark::DoNotOptimize(fresh.update(fromSeconds(35.0)));
        pairs = static_cast<double>(fresh.stats().pairs);
    }
    state.counters["pairs"] = pairs;
}
BENCHMARK(BM_ClockTrackerSolve)->Unit(benchmark::kMillisecond);

}  // namespace
