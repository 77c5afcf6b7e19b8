#include "handscan/replay/replay_bench.hpp"

#include <fmt/format.h>
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>

#include "handscan/core/json.hpp"
#include "handscan/export/safe_file.hpp"

namespace handscan::replay {
namespace {

double processCpuSeconds() {
    rusage ru{};
    getrusage(RUSAGE_SELF, &ru);
    auto s = [](const timeval& t) {
        return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec);
    };
    return s(ru.ru_utime) + s(ru.ru_stime);
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

Result<ReplayBench> benchReplay(ReplayOptions options, int runs) {
    if (runs < 1)
        return Status{StatusCode::kInvalidArgument,
                      fmt::format("replay --bench: {} runs; give 1 or more", runs)};
    options.fast = true;
    options.live = false;
    ReplayBench bench;
    std::vector<double> walls, cpus;
    std::string stats_json;
    for (int k = 0; k < runs; ++k) {
        const double cpu0 = processCpuSeconds();
        const auto t0 = std::chrono::steady_clock::now();
        auto report = runReplay(options);
        if (!report.isOk()) return report.status();
        const double wall =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const double cpu = processCpuSeconds() - cpu0;
        bench.recording_s = report->recording_s;
        bench.runs.push_back({wall, cpu});
        walls.push_back(wall);
        cpus.push_back(cpu);
        stats_json = report->stats_json_path;
    }
    bench.median_wall_s = median(walls);
    bench.median_cpu_s = median(cpus);
    bench.realtime_wall = bench.median_wall_s > 0 ? bench.recording_s / bench.median_wall_s : 0.0;
    bench.realtime_cpu = bench.median_cpu_s > 0 ? bench.recording_s / bench.median_cpu_s : 0.0;

    Json modules = Json::object();
    if (!stats_json.empty()) {
        std::ifstream is(stats_json);
        Json stats = Json::parse(is, nullptr, false);
        if (!stats.is_discarded() && stats.contains("modules")) modules = stats["modules"];
    }
    // The stages a reader compares between runs: per IMU sample, per sweep step, per camera frame.
    for (const char* name : {"imu_prediction", "sweep_assembly_and_matching",
                             "visual_inertial_odometry", "worker_per_sample"}) {
        if (!modules.contains(name)) continue;
        const Json& m = modules[name];
        bench.modules_line +=
            fmt::format("{}{} {:.1f} us x {}", bench.modules_line.empty() ? "" : ", ", name,
                        m.value("mean_us", 0.0), m.value("calls", 0));
    }
    Json j;
    j["recording"] = options.recording;
    j["recording_s"] = bench.recording_s;
    Json list = Json::array();
    for (const BenchRun& r : bench.runs) list.push_back({{"wall_s", r.wall_s}, {"cpu_s", r.cpu_s}});
    j["runs"] = list;
    j["median_wall_s"] = bench.median_wall_s;
    j["median_cpu_s"] = bench.median_cpu_s;
    j["realtime_factor_wall"] = bench.realtime_wall;
    j["realtime_factor_cpu"] = bench.realtime_cpu;
    j["modules_last_run"] = modules;
    bench.bench_json_path = (std::filesystem::path(options.out_dir) / "bench.json").string();
    if (Status s = exporter::writeSmallFile(bench.bench_json_path, jsonText(j, 2) + "\n");
        !s.isOk())
        return s;
    return bench;
}

}  // namespace handscan::replay
