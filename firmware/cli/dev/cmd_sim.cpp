// `handscan sim`: the digital twin. Writes REC.mcap (raw device streams + ground truth) and
// REC.gt.tum; lists the built-in scenes; exports a scene's mesh as PLY.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <memory>

#include "command_registry.hpp"
#include "handscan/core/config.hpp"
#include "handscan/core/log.hpp"
#include "handscan/sim/mcap_sink.hpp"
#include "handscan/sim/ply_export.hpp"
#include "handscan/sim/scene_change.hpp"
#include "handscan/sim/scenes.hpp"
#include "handscan/sim/simulator.hpp"

namespace handscan::cli {
namespace {

struct SimArgs {
    sim::SimOptions options;
    bool list_scenes = false;
    bool no_camera = false;
    bool no_colour = false;
    std::string out = "sim.mcap";
    std::string export_mesh;
    bool ascii_ply = false;
    std::string device;
    std::string calibration;
    std::string blind_laser;  // T[:D]
    std::string imu_gap;      // T[:D]
};

// "T" or "T:D" (seconds): when an incident starts and how long it lasts.
bool parseIncident(const std::string& spec, double& at_s, double& for_s) {
    if (spec.empty()) return true;
    char* end = nullptr;
    const double at = std::strtod(spec.c_str(), &end);
    if (end == spec.c_str() || at < 0.0) return false;
    if (*end == ':') {
        const char* d = end + 1;
        const double dur = std::strtod(d, &end);
        if (end == d || dur <= 0.0) return false;
        for_s = dur;
    }
    if (*end != '\0') return false;
    at_s = at;
    return true;
}

const auto incidentSpec = CLI::Validator(
    [](std::string& spec) {
        double at = 0.0, dur = 0.0;
        return parseIncident(spec, at, dur)
                   ? std::string()
                   : "expected T or T:D in seconds (T >= 0, D > 0), got '" + spec + "'";
    },
    "T[:D]");

std::string gtPathFor(const std::string& mcap) {
    const std::string stem = mcap.size() > 5 && mcap.substr(mcap.size() - 5) == ".mcap"
                                 ? mcap.substr(0, mcap.size() - 5)
                                 : mcap;
    return stem + ".gt.tum";
}

int runSim(const SimArgs& a) {
    if (a.list_scenes) {
        for (const auto& s : sim::sceneCatalogue())
            std::printf("%-10s %s\n", s.name.c_str(), s.description.c_str());
        return 0;
    }
    const std::string dir = defaultConfigDir();
    const DeviceConfig device =
        loadDeviceConfig(a.device.empty() ? dir + "/device.yaml" : a.device);
    const Calibration cal =
        loadCalibration(a.calibration.empty() ? dir + "/calibration.yaml" : a.calibration);
    if (!a.export_mesh.empty()) {
        sim::Scene scene = a.options.scene.ends_with(".obj") ? sim::importObj(a.options.scene)
                                                             : sim::buildScene(a.options.scene);
        (void)sim::moveObjects(scene, a.options.scene_change, a.options.seed);
        if (Status s = sim::writePly(scene.world, a.export_mesh, !a.ascii_ply); !s) {
            log().error("{}", s.message());
            return 1;
        }
        std::printf("%s: %zu triangles of scene '%s'\n", a.export_mesh.c_str(),
                    scene.world.triangleCount(), scene.world.name.c_str());
        return 0;
    }
    sim::SimOptions o = a.options;
    (void)parseIncident(a.blind_laser, o.incidents.blind_laser_at_s,
                        o.incidents.blind_laser_for_s);  // validated by CLI11
    (void)parseIncident(a.imu_gap, o.incidents.imu_gap_at_s, o.incidents.imu_gap_for_s);
    o.cameras = !a.no_camera;
    o.colour_camera = !a.no_colour;
    const auto wall0 = std::chrono::steady_clock::now();
    sim::Simulator simulator(o, device, cal);
    const sim::SimStats& st = simulator.stats();
    log().info(
        "sim: scene '{}' ({} triangles), trajectory '{}' {:.1f} s, {:.1f} m, peak {:.0f} deg/s, {}",
        simulator.scene().world.name, simulator.scene().world.triangleCount(), o.trajectory,
        o.duration_s, st.path_length_m, st.peak_rate_dps,
        st.loop_closed ? fmt::format("closed loop ({} lap{})", st.laps, st.laps > 1 ? "s" : "")
                       : std::string("open (too short to close the loop)"));
    const sim::IncidentOptions& inc = o.incidents;
    if (inc.blind_laser_at_s >= 0.0)
        log().info("sim: the laser blinded from {:.2f} s for {:.2f} s", inc.blind_laser_at_s,
                   inc.blind_laser_for_s);
    if (inc.imu_gap_at_s >= 0.0)
        log().info("sim: no IMU frames from {:.2f} s for {:.2f} s", inc.imu_gap_at_s,
                   inc.imu_gap_for_s);
    if (inc.drop_at_s >= 0.0)
        log().info("sim: the scanner dropped at {:.2f} s, back in the hand {:.2f} s later",
                   inc.drop_at_s, inc.drop_lie_s + inc.drop_pickup_s + 0.5);
    // On stdout, for scripts (tests/e2e/localize): what the second session should see changed.
    for (const sim::MovedObject& m : simulator.movedObjects())
        std::printf("moved %s from %.3f,%.3f,%.3f to %.3f,%.3f,%.3f, turned %.1f deg\n",
                    m.name.c_str(), m.centre_before.x(), m.centre_before.y(), m.centre_before.z(),
                    m.centre_after.x(), m.centre_after.y(), m.centre_after.z(), m.turn_deg);
    auto sink = sim::McapSink::create(a.out, o.cameras);
    if (!sink) {
        log().error("{}", sink.status().message());
        return 1;
    }
    Status s;
    {
        Progress progress("sim " + a.out, o.duration_s);
        s = simulator.run(**sink, [&](double t) { progress.update(t); });
        progress.finish();
    }
    if (s) s = (*sink)->close();
    if (s) s = simulator.writeGroundTruthTum(gtPathFor(a.out));
    if (!s) {
        log().error("sim: {}", s.message());
        return 1;
    }
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
    static const char* kNames[] = {"/hokuyo/raw",   "/xsens/raw",     "/motor/can",
                                   "/camera/track", "/camera/colour", "/groundtruth/pose"};
    for (int c = 0; c < static_cast<int>(sim::SimChannel::kCount); ++c) {
        if (st.messages[c] == 0) continue;
        std::printf("  %-18s %8llu messages %10.1f MB\n", kNames[c],
                    static_cast<unsigned long long>(st.messages[c]),
                    static_cast<double>(st.bytes[c]) / 1e6);
    }
    std::printf(
        "%s: %.1f MB (%llu scans, %llu IMU samples, %llu + %llu camera frames) in %.1f s; ground "
        "truth %s\n",
        a.out.c_str(), static_cast<double>((*sink)->bytesWritten()) / 1e6,
        static_cast<unsigned long long>(st.laser_scans),
        static_cast<unsigned long long>(st.imu_samples),
        static_cast<unsigned long long>(st.tracking_frames),
        static_cast<unsigned long long>(st.colour_frames), wall, gtPathFor(a.out).c_str());
    return 0;
}

const RegisterCommand kSim{
    "sim", "Simulate a scan: write a byte-exact device recording (MCAP) with ground truth",
    [](CLI::App& sub) {
        auto a = std::make_shared<SimArgs>();
        sub.add_flag("--list-scenes", a->list_scenes, "list the built-in scenes and exit");
        sub.add_option("--scene", a->options.scene,
                       "built-in scene (see --list-scenes) or an .obj file")
            ->capture_default_str();
        sub.add_option("--seed", a->options.seed, "random seed (same seed, same bytes)")
            ->capture_default_str();
        sub.add_option("--duration", a->options.duration_s, "seconds to simulate")
            ->capture_default_str()
            ->check(CLI::PositiveNumber);
        sub.add_option("--trajectory", a->options.trajectory,
                       "walk | aggressive | a TUM file (t x y z qx qy qz qw of {C})")
            ->capture_default_str();
        sub.add_option("--start-at", a->options.start_at,
                       "start the walk this fraction of the way round the scene's loop (0..1): "
                       "another session through the same scene")
            ->check(CLI::Range(0.0, 1.0));
        sub.add_option("--scene-change", a->options.scene_change,
                       "move this many of the scene's furniture/benches/bushes first (which and "
                       "how depends on --seed): a scene changed between sessions")
            ->check(CLI::NonNegativeNumber);
        sub.add_flag("--no-camera", a->no_camera, "no camera streams (faster, smaller)");
        sub.add_flag("--no-colour", a->no_colour, "no colour camera");
        sub.add_flag("--dark", a->options.dark, "almost no light (camera degeneracy)");
        sub.add_flag("--motion-blur", a->options.motion_blur,
                     "render motion blur over each exposure");
        sub.add_option("--colour-format", a->options.colour_format,
                       "colour camera format MJPEG (default) | YUYV");
        sub.add_option("--imu-precision", a->options.imu_precision,
                       "MTData2 precision: 0 float32, 1 fp12.20, 2 fp16.32, 3 float64")
            ->check(CLI::Range(0, 3));
        sub.add_option("--out", a->out, "recording to write (ground truth goes to <stem>.gt.tum)")
            ->capture_default_str();
        sub.add_option("--export-mesh", a->export_mesh,
                       "write the scene's triangle mesh as PLY and exit");
        sub.add_flag("--ascii-ply", a->ascii_ply, "ASCII instead of binary PLY");
        sub.add_option("--fault-scip", a->options.faults.corrupt_scip_blocks,
                       "corrupt this many SCIP data blocks");
        sub.add_option("--fault-xbus", a->options.faults.dropped_xbus_bytes,
                       "drop one byte of this many Xbus frames");
        sub.add_option("--fault-frames", a->options.faults.lost_frames,
                       "lose this many tracking-camera frames");
        sub.add_option("--fault-reconnect", a->options.faults.tcp_reconnects,
                       "drop the Hokuyo TCP connection this many times");
        // A harder world for the laser (tools/sim laser_hazards.hpp); the cameras do not see it.
        sub.add_option("--people", a->options.hazards.people,
                       "people walking the operator's path (half ahead, half coming towards)")
            ->check(CLI::Range(0, 50));
        sub.add_option("--glass", a->options.hazards.glass_panes,
                       "glass panes beside the path (specular, mirrored and transmitted beams)")
            ->check(CLI::Range(0, 50));
        sub.add_flag("--mixed-pixels", a->options.hazards.mixed_pixels,
                     "beams straddling a depth edge report a range between the two surfaces");
        sub.add_option("--dark-surfaces", a->options.hazards.dark_surfaces,
                       "share of the scene's materials black at 905 nm (dropouts), 0-1")
            ->check(CLI::Range(0.0, 1.0));
        sub.add_option("--range-noise", a->options.hazards.range_noise_scale,
                       "range noise as a multiple of the datasheet's")
            ->check(CLI::Range(0.0, 20.0));
        // One failure during the walk (tools/sim incidents.hpp).
        sub.add_option("--blind-laser", a->blind_laser,
                       "T[:D]: the laser's window covered for D s (default 5) from T s")
            ->check(incidentSpec);
        sub.add_option("--imu-gap", a->imu_gap, "T[:D]: no IMU frames for D s (default 2) from T s")
            ->check(incidentSpec);
        sub.add_option("--drop", a->options.incidents.drop_at_s,
                       "T: the scanner falls to the floor at T s, lies 1.5 s, is picked up")
            ->check(CLI::NonNegativeNumber);
        sub.add_option("--device", a->device, "device.yaml (default: <config dir>/device.yaml)");
        sub.add_option("--calibration", a->calibration,
                       "calibration.yaml (default: <config dir>/calibration.yaml)");
        return std::function<int()>([a] { return runSim(*a); });
    }};

}  // namespace
}  // namespace handscan::cli
