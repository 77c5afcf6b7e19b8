// PipelineDaemon: `handscan-pipeline`, the scanner's real-time process. It opens every device of
// device.yaml through its driver on its own thread (sensor_sources.hpp), runs the laser-inertial
// pipeline on a worker thread fed by SPSC queues (pipeline_thread.hpp), publishes to the live-map
// shared memory and journals the scan, and executes the UI's and the buttons' commands
// (command_handler.hpp). The main loop also feeds systemd (READY=1 once every device has been
// tried, WATCHDOG=1 while the pipeline thread is alive, STATUS= lines). A stop request (SIGTERM)
// or a shutdown command ends the scan cleanly: queued samples processed, journal flushed and
// finished, devices stopped.
#pragma once

#include <atomic>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "handscan/core/config.hpp"
#include "handscan/export/usb_target.hpp"
#include "handscan/journal/journal_writer.hpp"
#include "handscan/pipeline_daemon/device_links.hpp"
#include "handscan/pipeline_daemon/sensor_sources.hpp"
#include "handscan/shm/layout.hpp"

namespace handscan::pipeline_daemon {

struct DaemonOptions {
    std::string device_config;  // default: <config dir>/device.yaml
    std::string calibration;    // default: <config dir>/calibration.yaml
    // The field calibration (CalibrateJob): read instead of `calibration` once it exists, and
    // where "calibrate" writes; "": "calibrate" replaces `calibration` itself.
    std::string field_calibration;
    std::string journal_dir;  // default: device.yaml storage.journal_dir
    std::string shm_name = shm::kDefaultRegionName;
    std::size_t map_capacity_points = std::size_t{4} << 20;
    TimeNs ready_timeout = 5 * kNsPerSec;  // READY=1 at the latest after this, devices or not
    exporter::SystemPaths usb_paths;       // where the USB stick is looked for
    // Written after a verified export to the stick: handscan-usb-eject.path unmounts it.
    std::string usb_eject_request = "/run/handscan/usb-eject";
    journal::JournalOptions journal;
    // "Continue scan" (section 9): every scan localizes on this earlier scan's directory and is
    // journaled in its frame once locked; "": every scan starts its own frame.
    std::string prior_map_dir;
    std::string initial_pose;  // "x,y,z,qx,qy,qz,qw" in the prior's frame; "": its start
};

class PipelineDaemon {
public:
    explicit PipelineDaemon(DaemonOptions options,
                            std::unique_ptr<DeviceLinks> links = makeLinuxDeviceLinks());
    ~PipelineDaemon();
    PipelineDaemon(const PipelineDaemon&) = delete;
    PipelineDaemon& operator=(const PipelineDaemon&) = delete;

    // Loads the configuration, creates the shared memory, starts the device and pipeline
    // threads. Errors name the file and key (bad configuration) or the resource.
    Status open();
    // The main loop, until a shutdown command or `stop` turns true; then the clean shutdown.
    Status run(const std::atomic<bool>& stop);

    const PanelLeds& leds() const { return leds_; }

private:
    struct Parts;
    void updateLeds();
    std::string statusLine();
    bool allAttempted() const;

    DaemonOptions options_;
    std::unique_ptr<DeviceLinks> links_;
    DeviceConfig device_;
    Calibration calibration_;
    SampleQueues queues_;
    PanelLeds leds_;
    std::mutex buttons_mutex_;
    std::vector<ButtonAction> buttons_;  // pressed on the panel thread, executed by the main loop
    std::unique_ptr<Parts> parts_;
};

}  // namespace handscan::pipeline_daemon
