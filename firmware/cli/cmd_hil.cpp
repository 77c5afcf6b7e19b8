// `handscan hil REC.mcap --out DIR`: a recording through fake devices on real transports into
// the real handscan-pipeline (firmware/hil, hil_run.hpp).
#include <csignal>
#include <iostream>

#include "command_registry.hpp"
#include "handscan/core/log.hpp"
#include "handscan/hil/hil_run.hpp"

namespace handscan::cli {
namespace {

const RegisterCommand kHil{
    "hil",
    "Hardware-in-the-loop: a recording played by fake devices over TCP, a pty, a CAN log and V4L2 "
    "replay cameras into the real handscan-pipeline, driven through its shared-memory commands",
    [](CLI::App& sub) {
        auto o = std::make_shared<hil::HilOptions>();
        auto no_hokuyo = std::make_shared<bool>(false);
        auto no_xsens = std::make_shared<bool>(false);
        auto no_motor = std::make_shared<bool>(false);
        auto no_camera = std::make_shared<bool>(false);
        auto disconnect = std::make_shared<double>(-1.0);
        auto kill_at = std::make_shared<double>(-1.0);
        sub.add_option("RECORDING", o->recording, "recording (.mcap)")
            ->required()
            ->check(CLI::ExistingFile);
        sub.add_option("--out", o->out_dir,
                       "output directory: trajectory.tum (recording clock), stats.json, map.ply, "
                       "journal/, export/, daemon.log")
            ->required();
        sub.add_option("--daemon", o->daemon,
                       "handscan-pipeline binary (default: next to this program)");
        sub.add_option("--device", o->device_config,
                       "the recording's device.yaml; transports are pointed at the fakes "
                       "(default: config dir)");
        sub.add_option("--calibration", o->calibration, "calibration.yaml (default: config dir)");
        sub.add_option("--field-calibration", o->field_calibration,
                       "the daemon's field calibration: what --calibrate writes, read instead of "
                       "--calibration once it exists (default: none)");
        sub.add_option("--startup", o->startup_s,
                       "seconds the daemon gets to open the devices and start the scan before the "
                       "recording plays")
            ->capture_default_str()
            ->check(CLI::Range(0.5, 60.0));
        sub.add_option("--fault-hokuyo-disconnect", *disconnect,
                       "drop the laser's TCP connection T s into the recording")
            ->check(CLI::NonNegativeNumber);
        sub.add_option("--kill-at", *kill_at,
                       "kill -9 the daemon T s into the recording and start it again; the "
                       "recovered scan is exported")
            ->check(CLI::NonNegativeNumber);
        sub.add_option("--viz", o->viz_path,
                       "also write the daemon's scan (journal poses and points) with the "
                       "recording's camera frames and ground truth as a Foxglove MCAP");
        sub.add_option("--continue", o->continue_scan,
                       "continue an earlier scan (its directory: journal.hsj, feature_map.hsf) "
                       "instead of scanning on its own: the daemon localizes on it");
        sub.add_option("--initial-pose", o->initial_pose,
                       "with --continue: where the recording starts in that scan's frame, "
                       "x,y,z,qx,qy,qz,qw (default: where that scan started)");
        sub.add_option("--calibrate", o->calibrate_rounds,
                       "after the export, the UI's calibrate on the scan with at most N rounds: "
                       "the daemon writes --field-calibration (else replaces --calibration's "
                       "file), keeping the file it replaces as .prev")
            ->check(CLI::Range(1, 10));
        sub.add_flag("--no-hokuyo", *no_hokuyo, "no laser (the daemon finds nothing listening)");
        sub.add_flag("--no-xsens", *no_xsens, "no IMU (the daemon finds no tty)");
        sub.add_flag("--no-motor", *no_motor, "no CAN encoder (the daemon finds no CAN log)");
        sub.add_flag("--no-camera", *no_camera,
                     "leave the recorded cameras out (by default they play through the V4L2 "
                     "replay device)");
        return std::function<int()>([=] {
            o->fakes.hokuyo = !*no_hokuyo;
            o->fakes.xsens = !*no_xsens;
            o->fakes.motor = !*no_motor;
            o->fakes.cameras = !*no_camera;
            if (*disconnect >= 0.0) o->fakes.hokuyo_disconnect_s = *disconnect;
            if (*kill_at >= 0.0) o->kill_at_s = *kill_at;
            std::signal(SIGPIPE, SIG_IGN);  // the daemon's end of a fake may close at any time
            auto r = hil::runHil(*o);
            if (!r.isOk()) {
                log().error("hil: {}", r.status().message());
                return 1;
            }
            std::cout << r->summary << "-> " << o->out_dir << "\n";
            return 0;
        });
    }};

}  // namespace
}  // namespace handscan::cli
