// Simulator speed: one tracking frame, one colour frame, one laser scan, and (the acceptance
// figure) a 60 s office recording with every sensor, on one core.
#include <benchmark/benchmark.h>

#include <chrono>
#include <filesystem>
#include <string>

#include "handscan/core/config.hpp"
#include "handscan/sim/camera_model.hpp"
#include "handscan/sim/laser_model.hpp"
#include "handscan/sim/mcap_sink.hpp"
#include "handscan/sim/scenes.hpp"
#include "handscan/sim/simulator.hpp"
#include "handscan/sim/trajectory.hpp"

namespace handscan::sim {
namespace {

const Calibration& cal() {
    static const Calibration c =
        loadCalibration(std::string(HANDSCAN_BENCH_SOURCE_DIR) + "/config/calibration.yaml");
    return c;
}

const Scene& office() {
    static const Scene s = buildScene("office");
    return s;
}

const Trajectory& walk() {
    static const Trajectory t = [] {
        WalkOptions o;
        o.duration_s = 60;
        return makeWalk(office().walk_loop, o).trajectory;
    }();
    return t;
}

void renderCamera(benchmark::State& state, const CameraIntrinsics& cam, bool colour) {
    Raycaster rc(office().world);
    CameraRenderConfig cfg;
    cfg.colour = colour;
    CameraRenderer r(cam, cfg, rc, Rng(1, "bench"));
    std::vector<std::uint8_t> img;
    double t = 3.0;
    for (auto _ : state) {
        r.render(
            t, [](double s) { return walk().at(s).T_world_body; }, img);
        t += 0.37;
        if (t > 58) t = 3.0;
        benchmark::DoNotOptimize(img.data());
    }
    state.counters["rays/frame"] =
        static_cast<double>(r.raysCast()) / static_cast<double>(state.iterations());
}

void BM_TrackingFrame(benchmark::State& state) { renderCamera(state, cal().tracking, false); }
void BM_ColourFrame(benchmark::State& state) { renderCamera(state, cal().colour, true); }

void BM_LaserScan(benchmark::State& state) {
    Raycaster rc(office().world);
    LaserModel laser(LaserConfig{}, rc, Rng(1, "bench"));
    double t = 3.0;
    for (auto _ : state) {
        auto s = laser.scan(t, [](double u) { return walk().at(u).T_world_body; });
        benchmark::DoNotOptimize(s.ranges_mm.data());
        t += 0.025;
        if (t > 58) t = 3.0;
    }
}

// The acceptance figure: `handscan sim --scene office --duration 60` with every sensor, on one
// core, written to a file. Counters: file size, the payload bytes per channel, simulated seconds.
void BM_Office60s(benchmark::State& state) {
    const DeviceConfig device =
        loadDeviceConfig(std::string(HANDSCAN_BENCH_SOURCE_DIR) + "/config/device.yaml");
    const std::string path =
        (std::filesystem::temp_directory_path() / "handscan_bench_office60.mcap").string();
    std::uint64_t bytes = 0;
    SimStats stats;
    for (auto _ : state) {
        SimOptions o;
        o.scene = "office";
        o.duration_s = static_cast<double>(state.range(0));
        Simulator sim(o, device, cal());
        auto sink = McapSink::create(path, true);
        if (!sink || !sim.run(**sink).isOk() || !(*sink)->close().isOk()) {
            state.SkipWithError("simulation failed");
            break;
        }
        bytes = std::filesystem::file_size(path);
        stats = sim.stats();
    }
    std::filesystem::remove(path);
    state.counters["file_MB"] = static_cast<double>(bytes) / 1e6;
    // Where the bytes go: message payloads per channel, before the chunks' zstd.
    auto mb = [&](SimChannel c) {
        return static_cast<double>(stats.bytes[static_cast<int>(c)]) / 1e6;
    };
    state.counters["track_MB"] = mb(SimChannel::kTrackingCamera);
    state.counters["colour_MB"] = mb(SimChannel::kColourCamera);
    state.counters["laser_MB"] = mb(SimChannel::kHokuyo);
    state.counters["imu_can_gt_MB"] =
        mb(SimChannel::kXsens) + mb(SimChannel::kCan) + mb(SimChannel::kGroundTruth);
    state.counters["sim_s"] = static_cast<double>(state.range(0));
}

BENCHMARK(BM_Office60s)->Arg(60)->Iterations(1)->Unit(benchmark::kSecond);
BENCHMARK(BM_TrackingFrame)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ColourFrame)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_LaserScan)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace handscan::sim
