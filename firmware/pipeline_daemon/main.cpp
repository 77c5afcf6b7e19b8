// handscan-pipeline: the scanner's real-time daemon (see pipeline_daemon.hpp). systemd starts it
// (systemd/handscan-pipeline.service, Type=notify); SIGTERM or SIGINT ends the scan cleanly.
#include <CLI/CLI.hpp>
#include <atomic>
#include <csignal>

#include "handscan/core/log.hpp"
#include "handscan/pipeline_daemon/pipeline_daemon.hpp"

namespace {

std::atomic<bool> g_stop{false};
void onSignal(int) { g_stop.store(true); }

}  // namespace

int main(int argc, char** argv) {
    using namespace handscan;
    pipeline_daemon::DaemonOptions o;
    CLI::App app{
        "handscan-pipeline: live drivers -> pipeline -> shared memory + journal; executes the UI's "
        "commands"};
    app.add_option("--config", o.device_config,
                   "device configuration (default: <config dir>/device.yaml)");
    app.add_option("--calibration", o.calibration,
                   "calibration (default: <config dir>/calibration.yaml)");
    app.add_option("--field-calibration", o.field_calibration,
                   "the calibration the UI's \"calibrate\" writes, read instead of --calibration "
                   "once it exists (default: none; calibrate replaces --calibration's file)");
    app.add_option("--journal-dir", o.journal_dir,
                   "where scans are journaled (default: storage.journal_dir)");
    app.add_option("--prior-map", o.prior_map_dir,
                   "continue an earlier scan: localize every scan on this scan directory "
                   "(its feature_map.hsf) and journal it in that scan's frame once locked")
        ->check(CLI::ExistingDirectory);
    app.add_option("--initial-pose", o.initial_pose,
                   "with --prior-map: where scanning starts in its frame, x,y,z,qx,qy,qz,qw "
                   "(default: where the earlier scan started)");
    app.add_option("--shm", o.shm_name, "live-map shared-memory name")->capture_default_str();
    app.add_option("--map-capacity", o.map_capacity_points, "display-map capacity in points")
        ->capture_default_str();
    std::string mountinfo;
    app.add_option("--usb-mountinfo", mountinfo,
                   "mount table to look for the USB stick in (tests)");
    CLI11_PARSE(app, argc, argv);
    if (!mountinfo.empty()) o.usb_paths.mountinfo = mountinfo;

    struct sigaction sa {};
    sa.sa_handler = onSignal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGTERM, &sa, nullptr);
    sigaction(SIGINT, &sa, nullptr);
    std::signal(SIGPIPE, SIG_IGN);  // a vanished TCP peer is an error return, not a signal

    pipeline_daemon::PipelineDaemon daemon(o);
    if (Status s = daemon.open(); !s.isOk()) {
        log().error("{}", s.message());
        return 1;
    }
    if (Status s = daemon.run(g_stop); !s.isOk()) {
        log().error("{}", s.message());
        return 1;
    }
    return 0;
}
