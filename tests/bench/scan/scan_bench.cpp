// Scan matching speed on one core (issue 5 target: features + matching <= 50 ms per 1 Hz sweep of
// a UTM-30LX, 40 scans x 1081 steps), map update cost, and sweep assembly.
#include <benchmark/benchmark.h>

#include "handscan/scan/laser_odometry.hpp"
#include "handscan/scan/scan_matcher.hpp"
#include "handscan/scan/sweep_assembler.hpp"
#include "spin_sim.hpp"

namespace handscan::scan {
namespace {

using testing::deviceGeometry;
using testing::toWorld;

struct Fixture {
    testing::SimStreams streams;
    Sweep map_sweep;  // full revolution at pose A: builds the map
    Sweep sweep;      // full revolution at pose B: matched
    Eigen::Isometry3d A = testing::pose(0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    Eigen::Isometry3d B = testing::pose(0.03, 0.3, -0.02, 0.4, 0.03, 0.5);
    Eigen::Isometry3d guess = B * testing::pose(0.01, -0.01, 0.01, 0.05, -0.03, 0.04);

    Fixture() {
        SweepAssemblerConfig full;
        full.boundary = SweepBoundary::kFullRevolution;
        const auto scene = testing::officeRoom();
        const auto sa = testing::simulate(scene, testing::staticPose(A), deviceGeometry(),
                                          kNsPerSec, 2 * kNsPerSec);
        map_sweep = testing::assemble(sa, deviceGeometry(), testing::staticPose(A), full).at(0);
        streams = testing::simulate(scene, testing::staticPose(B), deviceGeometry(), kNsPerSec,
                                    2 * kNsPerSec);
        sweep = testing::assemble(streams, deviceGeometry(), testing::staticPose(B), full).at(0);
    }
};

const Fixture& fixture() {
    static const Fixture f;
    return f;
}

VoxelMap mapOf(const FeatureCloud& f, const Eigen::Isometry3d& T) {
    VoxelMap map;
    map.recenter(T.translation());
    map.insert(FeatureKind::kEdge, toWorld(T, f.edges));
    map.insert(FeatureKind::kPlanar, toWorld(T, f.planars));
    return map;
}

void BM_SweepAssembly(benchmark::State& state) {
    const Fixture& f = fixture();
    SweepAssemblerConfig full;
    full.boundary = SweepBoundary::kFullRevolution;
    for (auto _ : state) {
        auto sweeps =
            testing::assemble(f.streams, deviceGeometry(), testing::staticPose(f.B), full);
        benchmark::DoNotOptimize(sweeps);
    }
    state.counters["points"] = static_cast<double>(f.sweep.points.size());
}
BENCHMARK(BM_SweepAssembly)->Unit(benchmark::kMillisecond);

void BM_Features(benchmark::State& state) {
    const Fixture& f = fixture();
    FeatureCloud fc;
    for (auto _ : state) {
        fc = extractFeatures(f.sweep, FeatureConfig{});
        benchmark::DoNotOptimize(fc);
    }
    state.counters["edges"] = static_cast<double>(fc.edges.size());
    state.counters["planars"] = static_cast<double>(fc.planars.size());
}
BENCHMARK(BM_Features)->Unit(benchmark::kMillisecond);

// Map extraction (fine voxels + k-d trees) and matching, the map from one earlier revolution;
// the argument is ScanMatcherConfig::curvature_neighbours (0: planar matches without the
// curvature offset, the default 16: with it).
void BM_ExtractAndMatch(benchmark::State& state) {
    const Fixture& f = fixture();
    const VoxelMap map = mapOf(extractFeatures(f.map_sweep, FeatureConfig{}), f.A);
    const FeatureCloud fb = extractFeatures(f.sweep, FeatureConfig{});
    PosePrior prior{f.guess, Matrix6d::Identity() * 100.0};
    ScanMatcherConfig config;
    config.curvature_neighbours = static_cast<int>(state.range(0));
    const ScanMatcher matcher(config);
    MatchResult r;
    for (auto _ : state) {
        const LocalMap local =
            map.extract(toWorld(f.guess, fb.edges), toWorld(f.guess, fb.planars));
        r = matcher.match(fb, local, {prior});
        benchmark::DoNotOptimize(r);
    }
    const Eigen::Isometry3d d = f.B.inverse() * r.T_world_body;
    state.counters["err_cm"] = d.translation().norm() * 100;
    state.counters["iterations"] = r.iterations;
    state.counters["matches"] = r.edge_matches + r.plane_matches;
}
BENCHMARK(BM_ExtractAndMatch)->Arg(0)->Arg(16)->Unit(benchmark::kMillisecond);

// The figure: everything the matcher does per 1 Hz sweep on one core.
void BM_FeaturesAndMatchingPerSweep(benchmark::State& state) {
    const Fixture& f = fixture();
    const VoxelMap map = mapOf(extractFeatures(f.map_sweep, FeatureConfig{}), f.A);
    PosePrior prior{f.guess, Matrix6d::Identity() * 100.0};
    const ScanMatcher matcher;
    for (auto _ : state) {
        const FeatureCloud fb = extractFeatures(f.sweep, FeatureConfig{});
        const LocalMap local =
            map.extract(toWorld(f.guess, fb.edges), toWorld(f.guess, fb.planars));
        MatchResult r = matcher.match(fb, local, {prior});
        benchmark::DoNotOptimize(r);
    }
    state.counters["points"] = static_cast<double>(f.sweep.points.size());
}
BENCHMARK(BM_FeaturesAndMatchingPerSweep)->Unit(benchmark::kMillisecond);

// Merging one sweep's features into a map that already holds `range(0)` sweeps of the room.
void BM_MapUpdate(benchmark::State& state) {
    const Fixture& f = fixture();
    const FeatureCloud fb = extractFeatures(f.sweep, FeatureConfig{});
    const auto edges = toWorld(f.B, fb.edges);
    const auto planars = toWorld(f.B, fb.planars);
    VoxelMap base;
    base.recenter(f.B.translation());
    for (int i = 0; i < state.range(0); ++i) {
        const Eigen::Isometry3d jitter = testing::pose(0, 0.01 * i, 0, 0.03 * i, 0, 0.02 * i);
        base.insert(FeatureKind::kEdge, toWorld(jitter, edges));
        base.insert(FeatureKind::kPlanar, toWorld(jitter, planars));
    }
    for (auto _ : state) {
        state.PauseTiming();
        VoxelMap map = base;
        state.ResumeTiming();
        map.recenter(f.B.translation());
        benchmark::DoNotOptimize(map.insert(FeatureKind::kEdge, edges));
        benchmark::DoNotOptimize(map.insert(FeatureKind::kPlanar, planars));
    }
    state.counters["map_points"] =
        static_cast<double>(base.stats().points[0] + base.stats().points[1]);
    state.counters["map_MiB"] = static_cast<double>(base.stats().memory_bytes) / (1 << 20);
}
BENCHMARK(BM_MapUpdate)->Arg(1)->Arg(20)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace handscan::scan
