// The replay's map.ply accumulator: points per second into the tiled, budgeted map (add + final
// drain) against the plain in-memory voxel filter, on a walk along a 200 m corridor loop (the
// sensor sees 15 m around it, so tiles are left and revisited on the second lap). Arg: budget MiB.
#include <benchmark/benchmark.h>

#include <cmath>
#include <filesystem>
#include <random>

#include "handscan/export/voxel_filter.hpp"
#include "handscan/replay/tiled_voxel_map.hpp"

namespace handscan::replay {
namespace {

struct Sweep {
    Eigen::Vector3d sensor;
    std::vector<journal::MapPoint> points;
};

// 2 laps x 200 sweeps x 10 000 points: 4 M points, walls, floor and ceiling of a 4 m wide corridor
// around a 60 m x 40 m block.
const std::vector<Sweep>& corridorWalk() {
    static const std::vector<Sweep> sweeps = [] {
        std::vector<Sweep> out;
        std::mt19937 rng(5);
        std::uniform_real_distribution<double> along(-15.0, 15.0), across(-2.0, 2.0), up(0.0, 3.0),
            noise(-0.005, 0.005);
        double t = 0.0;
        for (int lap = 0; lap < 2; ++lap) {
            for (int k = 0; k < 200; ++k) {
                const double s = 200.0 * k / 200.0;  // arc length along the loop's perimeter
                // Position on the 60 x 40 rectangle and the corridor's direction there.
                Eigen::Vector2d p, d;
                if (s < 60)
                    p = {s, 0}, d = {1, 0};
                else if (s < 100)
                    p = {60, s - 60}, d = {0, 1};
                else if (s < 160)
                    p = {160 - s, 40}, d = {-1, 0};
                else
                    p = {0, 200 - s}, d = {0, -1};
                Sweep sw;
                sw.sensor = {p.x(), p.y(), 1.5};
                const Eigen::Vector2d n(-d.y(), d.x());
                for (int i = 0; i < 10000; ++i) {
                    t += 5e-5;
                    const double a = along(rng);
                    Eigen::Vector2d q = p + a * d;
                    double z = up(rng);
                    switch (i % 4) {
                        case 0:
                            q += 2.0 * n;
                            break;  // left wall
                        case 1:
                            q -= 2.0 * n;
                            break;  // right wall
                        case 2:
                            q += across(rng) * n;
                            z = 0.0;
                            break;  // floor
                        default:
                            q += across(rng) * n;
                            z = 3.0;
                            break;  // ceiling
                    }
                    sw.points.push_back({t, static_cast<float>(q.x() + noise(rng)),
                                         static_cast<float>(q.y() + noise(rng)),
                                         static_cast<float>(z + noise(rng)), 128, 128, 128, 1000});
                }
                out.push_back(std::move(sw));
            }
        }
        return out;
    }();
    return sweeps;
}

void BM_InMemoryVoxelFilter(benchmark::State& state) {
    const auto& sweeps = corridorWalk();
    std::size_t kept = 0, bytes = 0;
    for (auto _ : state) {
        exporter::VoxelFilter f(0.02);
        for (const Sweep& s : sweeps) f.add(s.points);
        bytes = f.memoryBytes();
        kept = f.take().size();
    }
    state.counters["kept"] = static_cast<double>(kept);
    state.counters["table_MiB"] = static_cast<double>(bytes) / (1 << 20);
    state.counters["points_per_s"] = benchmark::Counter(
        static_cast<double>(sweeps.size() * 10000) * static_cast<double>(state.iterations()),
        benchmark::Counter::kIsRate);
}
BENCHMARK(BM_InMemoryVoxelFilter)->Unit(benchmark::kMillisecond)->Iterations(1)->UseRealTime();

void BM_TiledVoxelMap(benchmark::State& state) {
    const auto& sweeps = corridorWalk();
    const std::filesystem::path dir = std::filesystem::temp_directory_path();
    TiledMapStats st;
    std::uint64_t kept = 0;
    for (auto _ : state) {
        TiledMapConfig cfg;
        cfg.voxel_m = 0.02;
        cfg.memory_budget_bytes = static_cast<std::uint64_t>(state.range(0)) << 20;
        cfg.spill_dir = dir.string();
        TiledVoxelMap map(cfg);
        for (const Sweep& s : sweeps) {
            if (!map.add(s.points, s.sensor).isOk()) state.SkipWithError("add failed");
        }
        auto n = map.drain([](std::uint64_t) { return Status::ok(); },
                           [](std::span<const journal::MapPoint>) { return Status::ok(); });
        if (!n.isOk()) state.SkipWithError(n.status().message().c_str());
        kept = n.isOk() ? *n : 0;
        st = map.stats();
    }
    state.counters["kept"] = static_cast<double>(kept);
    state.counters["peak_resident_MiB"] = static_cast<double>(st.peak_resident_bytes) / (1 << 20);
    state.counters["flushed_voxels"] = static_cast<double>(st.cells_flushed);
    state.counters["peak_spill_MiB"] = static_cast<double>(st.peak_spill_bytes) / (1 << 20);
    state.counters["points_per_s"] = benchmark::Counter(
        static_cast<double>(sweeps.size() * 10000) * static_cast<double>(state.iterations()),
        benchmark::Counter::kIsRate);
}
BENCHMARK(BM_TiledVoxelMap)
    ->Arg(100000)
    ->Arg(64)
    ->Arg(16)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1)
    ->UseRealTime();

}  // namespace
}  // namespace handscan::replay
