// Cost of re-placing a sweep with the corrected IMU motion before it is matched (IMU feedback):
// one half-revolution sweep of the UTM-30LX (~21k points over 0.5 s), the motion sampled every
// 2 ms from a real ImuPredictor history.
#include <benchmark/benchmark.h>

#include <cmath>

#include "handscan/imu/imu_predictor.hpp"
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

}  // namespace
