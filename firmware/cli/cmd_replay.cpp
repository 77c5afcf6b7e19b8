// `handscan replay REC.mcap --out DIR`: a recording through the drivers' decoders and the pipeline.
#include <fmt/format.h>

#include <algorithm>
#include <csignal>
#include <iostream>

#include "command_registry.hpp"
#include "handscan/core/log.hpp"
#include "handscan/replay/replay_bench.hpp"
#include "handscan/replay/replay_engine.hpp"

namespace handscan::cli {
namespace {

volatile std::sig_atomic_t g_interrupted = 0;

const RegisterCommand kReplay{
    "replay", "Run the pipeline on a recording: trajectory.tum, map.ply, stats.json, journal",
    [](CLI::App& sub) {
        auto o = std::make_shared<replay::ReplayOptions>();
        // The default leaves the camera out: with the visual-inertial odometry as scan matching's
        // prior (--modules all) the degenerate scenes gain a lot (90 s seed 1, mean segment
        // drift imu,laser -> all: tunnel 24.9 % -> 9.7 %, field 33.2 % -> 7.9 %) but the
        // office loses (25 s seed 3: 0.23 % -> 1.37 %), so `all` is not the default yet.
        auto modules = std::make_shared<std::string>("imu,laser");
        auto bench_runs = std::make_shared<int>(0);
        sub.add_option("RECORDING", o->recording, "recording (.mcap)")
            ->required()
            ->check(CLI::ExistingFile);
        sub.add_option("--out", o->out_dir, "output directory")->required();
        sub.add_option("--modules", *modules,
                       "imu | imu,laser (default) | imu,vision | all (all: the visual-inertial "
                       "odometry on /camera/track too, as scan matching's prior)")
            ->check(CLI::IsMember(
                {"imu", "imu,laser", "laser,imu", "imu,vision", "vision,imu", "all"}));
        sub.add_flag("--skip-every-other", o->skip_every_other,
                     "drop every other sample of every sensor (the paper's 2x speed test)");
        sub.add_flag("--fast", o->fast,
                     "as fast as possible on the recording's clock (deterministic)");
        sub.add_option("--bench", *bench_runs,
                       "replay N times --fast and report the wall and CPU real-time factors "
                       "(medians) and the modules' per-call costs (DIR/bench.json)")
            ->check(CLI::Range(1, 100));
        sub.add_option("--speed", o->speed, "pace multiplier without --fast")
            ->check(CLI::Range(0.01, 1000.0));
        sub.add_option("--dump-sweeps", o->dump_sweeps_dir,
                       "write every assembled sweep as PLY into this directory");
        sub.add_option("--device", o->device_config, "device.yaml (default: config dir)");
        sub.add_option("--calibration", o->calibration, "calibration.yaml (default: config dir)");
        sub.add_option("--map-voxel", o->map_voxel_m, "map.ply voxel size in metres")
            ->check(CLI::Range(0.001, 1.0));
        sub.add_option("--map-memory", o->map_memory_mib,
                       "MiB of map voxels held in memory; beyond it the tiles farthest from the "
                       "sensor go to a "
                       "scratch file and are merged back at the end (same map.ply)")
            ->check(CLI::Range(1.0, 1e6));
        sub.add_option("--map-tile", o->map_tile_m, "edge of the map's tiles in metres")
            ->check(CLI::Range(1.0, 1000.0));
        sub.add_option("--map-spill-dir", o->map_spill_dir,
                       "directory for the map's scratch file (default: --out)");
        sub.add_flag("!--no-colour", o->colourise, "do not colour the map from /camera/colour");
        sub.add_flag(
            "--imu-feedback,!--no-imu-feedback", o->imu_feedback,
            "scan-matching poses correct the IMU prediction's velocity, biases and gravity "
            "(default on; "
            "--no-imu-feedback: the IMU runs open loop and only its increments seed the matcher)");
        sub.add_flag(
            "!--no-calibration-check", o->check_calibration,
            "map whatever the calibration (default: the first seconds check it, "
            "stats.json \"calibration_check\"; a wrong one keeps the scan out of the map)");
        sub.add_flag("!--no-clock-tracking", o->track_clocks,
                     "keep the configured IMU and encoder latencies (default: tracked online "
                     "within a bounded range, stats.json \"clocks\")");
        sub.add_option("--viz", o->viz_path,
                       "also write this MCAP with standard Foxglove channels (protobuf): /map, "
                       "/sweep, /pose, /tf, /imu, /status, camera images, ground truth");
        sub.add_option("--prior-map", o->prior_map_dir,
                       "continue an earlier scan: localize on its output directory's feature map "
                       "(section 9); the outputs are in its frame once locked, nothing before")
            ->check(CLI::ExistingDirectory);
        sub.add_option("--initial-pose", o->initial_pose,
                       "with --prior-map: where this session starts in the prior's frame, "
                       "x,y,z,qx,qy,qz,qw (searched a few metres and +-30 deg around; default: "
                       "where the prior scan started)");
        sub.add_flag("--live", o->live, "publish to the live-map shared memory (the UI shows it)");
        sub.add_flag("--hold", o->hold, "with --live: keep the final state published until Ctrl-C");
        sub.add_option("--shm-name", o->shm_name,
                       "shared-memory region name (default: the daemon's)");
        sub.add_option("--reference-motion", o->reference_motion,
                       "diagnostics: assemble sweeps with this TUM trajectory (ground truth) and "
                       "match from it; "
                       "trajectory.tum carries each match forward with it")
            ->check(CLI::ExistingFile);
        sub.add_option("--reference-perturb-m", o->reference_perturb_m,
                       "with --reference-motion: prior error (m)");
        sub.add_option("--reference-perturb-deg", o->reference_perturb_deg,
                       "with --reference-motion: prior error (deg)");
        return std::function<int()>([o, modules, bench_runs] {
            const bool vision_only = *modules == "imu,vision" || *modules == "vision,imu";
            o->use_laser = *modules != "imu" && !vision_only;
            o->use_vision = *modules == "all" || vision_only;
            o->vision_required = vision_only;
            if (*bench_runs > 0) {
                auto b = replay::benchReplay(*o, *bench_runs);
                if (!b.isOk()) {
                    log().error("{}", b.status().message());
                    return 1;
                }
                std::string walls, cpus;
                for (const replay::BenchRun& r : b->runs) {
                    walls += fmt::format("{}{:.2f}", walls.empty() ? "" : " / ", r.wall_s);
                    cpus += fmt::format("{}{:.2f}", cpus.empty() ? "" : " / ", r.cpu_s);
                }
                std::cout << fmt::format(
                    "bench: {} runs of {:.1f} s ({} modules): wall {} s, median {:.2f}x real "
                    "time; CPU {} s, median {:.2f}x real time on one core\n"
                    "bench: per call (last run): {}\nbench: -> {}\n",
                    b->runs.size(), b->recording_s, *modules, walls, b->realtime_wall, cpus,
                    b->realtime_cpu, b->modules_line, b->bench_json_path);
                return 0;
            }
            Progress bar("replay", 1.0);
            o->progress = [&](double f) { bar.update(f); };
            std::signal(SIGINT, [](int) { g_interrupted = 1; });
            std::signal(SIGTERM, [](int) { g_interrupted = 1; });
            o->interrupted = [] { return g_interrupted != 0; };
            auto r = replay::runReplay(*o);
            bar.finish();
            if (!r.isOk()) {
                log().error("{}", r.status().message());
                return 1;
            }
            if (r->prior_map && !r->locked)
                log().warn(
                    "replay: never locked on the prior map {}: no trajectory or map "
                    "written (start nearer the prior scan's start, or give "
                    "--initial-pose)",
                    o->prior_map_dir);
            std::cout << "replayed " << r->recording_s << " s in " << r->wall_s << " s ("
                      << r->realtime_factor << "x real time): " << r->poses << " poses, "
                      << r->sweeps << " sweeps, " << r->map_points << " map points -> "
                      << o->out_dir << "\n";
            return 0;
        });
    }};

}  // namespace
}  // namespace handscan::cli
