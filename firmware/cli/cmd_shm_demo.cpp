// `handscan shm-demo`: publishes a synthetic scan into the live-map shared memory and answers the
// UI's commands, for demos and UI tests until `handscan replay --live` publishes real output.
#include <csignal>
#include <thread>

#include "command_registry.hpp"
#include "handscan/core/log.hpp"
#include "handscan/shm/export_preview.hpp"
#include "handscan/shm/live_map_writer.hpp"
#include "handscan/shm_demo/demo_pipeline.hpp"

namespace handscan::cli {
namespace {

volatile std::sig_atomic_t g_interrupted = 0;
void onSignal(int) { g_interrupted = 1; }

struct ShmDemoArgs {
    std::string name = shm::kDefaultRegionName;
    double duration_s = 0;
    bool hold = false;
    bool autostart = false;
    std::size_t capacity = std::size_t{4} << 20;
    int samples_per_second = 40000;
    std::string export_root = "/tmp";
    std::vector<std::string> faults;
};

int runShmDemo(const ShmDemoArgs& a) {
    shm::WriterOptions wo;
    wo.name = a.name;
    wo.map_capacity_points = a.capacity;
    auto writer = shm::LiveMapWriter::create(wo);
    if (!writer) {
        log().error("{}", writer.status().message());
        return 1;
    }
    shm_demo::DemoOptions o;
    o.samples_per_second = a.samples_per_second;
    o.export_root = a.export_root;
    o.preview_png = shm::exportPreviewPath(a.name);
    for (const std::string& f : a.faults) {
        if (f == "camera-dark")
            o.faults.camera_dark = true;
        else if (f == "laser-degenerate")
            o.faults.laser_degenerate = true;
        else if (f == "sensor-lost")
            o.faults.sensor_lost = true;
        else if (f == "too-fast")
            o.faults.too_fast = true;
    }
    shm_demo::DemoPipeline demo(**writer, o);
    const TimeNs start = monotonicNow();
    if (a.autostart) demo.startScan(start);
    std::signal(SIGINT, onSignal);
    std::signal(SIGTERM, onSignal);
    log().info("publishing synthetic scan to /dev/shm{} ({}); Ctrl-C to stop", a.name,
               a.autostart ? "scanning" : "waiting for start from the UI");
    bool scanning_done = false;
    while (!g_interrupted && !demo.shutdownRequested()) {
        const TimeNs now = monotonicNow();
        if (!scanning_done && a.duration_s > 0 && toSeconds(now - start) >= a.duration_s) {
            scanning_done = true;
            if (!a.hold) break;
        }
        if (!scanning_done || demo.scanState() != shm::ScanState::kScanning) {
            demo.step(now);
        } else {
            (*writer)->heartbeat();  // --hold: keep the final state published
            while (auto cmd = (*writer)->pollCommand())
                (*writer)->ack(cmd->seq, shm::CommandState::kRejected, "demo finished (--hold)");
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    log().info("published {} display points", demo.pointsPublished());
    return 0;
}

const RegisterCommand kShmDemo{
    "shm-demo", "Publish a synthetic live map (poses, points, status) for the UI",
    [](CLI::App& sub) {
        auto a = std::make_shared<ShmDemoArgs>();
        sub.add_option("--shm-name", a->name, "shared-memory region name")->capture_default_str();
        sub.add_option("--duration", a->duration_s,
                       "seconds to publish (0 = until Ctrl-C or a shutdown command)");
        sub.add_flag("--hold", a->hold,
                     "after --duration, keep the final state published until interrupted");
        sub.add_flag("--autostart", a->autostart,
                     "start scanning at once instead of waiting for the UI's start");
        sub.add_option("--capacity", a->capacity, "display-map capacity in points")
            ->capture_default_str();
        sub.add_option("--samples-per-second", a->samples_per_second,
                       "synthetic surface samples per second")
            ->capture_default_str();
        sub.add_option("--export-root", a->export_root,
                       "where exports go when the UI names no target")
            ->capture_default_str();
        sub.add_option("--fault", a->faults,
                       "inject: camera-dark, laser-degenerate, sensor-lost, too-fast")
            ->check(CLI::IsMember({"camera-dark", "laser-degenerate", "sensor-lost", "too-fast"}));
        return std::function<int()>([a] { return runShmDemo(*a); });
    }};

}  // namespace
}  // namespace handscan::cli
