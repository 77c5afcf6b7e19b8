// The daemon's hardware-in-the-loop rig: the devices the kernel lets us fake for real behind
// their real transports - a fake UTM-30LX-EW on loopback TCP (standing in a 6 x 4 m room, served
// at the sensor's pace) and a fake MTi-20 on a pty (at rest, so the pipeline aligns with gravity)
// - plus a temporary journal directory, a device.yaml pointing at them, a unique live-map name,
// and the UI's side of the command channel.
#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <thread>

#include "handscan/hil/command_client.hpp"
#include "handscan/hokuyo_fake/fake_hokuyo_server.hpp"
#include "handscan/pipeline_daemon/pipeline_daemon.hpp"
#include "handscan/shm/live_map_reader.hpp"
#include "handscan/xsens_fake/fake_xsens.hpp"
#include "handscan/xsens_fake/pty_xsens.hpp"

namespace handscan::pipeline_daemon::test {

namespace fs = std::filesystem;

struct RigDevices {
    bool hokuyo = true;
    bool xsens = true;
    std::string can_interface = "emulated";
    std::string tracking_camera;  // empty: disabled
    std::string colour_camera;    // empty: disabled
};

class DaemonRig {
public:
    explicit DaemonRig(const std::string& name, RigDevices devices = {});
    ~DaemonRig();

    const fs::path& dir() const { return dir_; }
    fs::path journalDir() const { return dir_ / "journal"; }
    const std::string& deviceYaml() const { return device_yaml_; }
    const std::string& shmName() const { return shm_name_; }
    static std::string calibrationYaml();
    hokuyo::FakeHokuyoServer* hokuyo() { return hokuyo_.get(); }
    // Stops the fake laser: its socket closes and nobody listens any more.
    void killHokuyo();

    // The UI's side.
    shm::LiveMapReader& ui() { return *reader_; }
    // Sends a command and waits for its final answer (collecting every ack state seen).
    shm::CommandAck command(shm::CommandType type, const std::string& argument = {},
                            std::vector<shm::CommandState>* seen = nullptr);
    // Polls the status block until `pred` holds (or `timeout_s` passes).
    std::optional<shm::StatusBlock> waitStatus(
        const std::function<bool(const shm::StatusBlock&)>& pred, double timeout_s);
    // The scan directories in the journal directory, sorted.
    std::vector<fs::path> scanDirs() const;

private:
    fs::path dir_;
    std::string shm_name_;
    std::string device_yaml_;
    std::unique_ptr<hokuyo::FakeHokuyoServer> hokuyo_;
    std::unique_ptr<xsens::FakeXsens> xsens_;
    std::unique_ptr<xsens::PtyXsens> pty_;
    std::unique_ptr<shm::LiveMapReader> reader_;
};

// The daemon's main loop on a thread of the test; stopped (as by SIGTERM) and joined when it goes
// out of scope, also when an assertion ends the test early.
class DaemonThread {
public:
    explicit DaemonThread(PipelineDaemon& daemon)
        : thread_([this, &daemon] { result_ = daemon.run(stop_); }) {}
    ~DaemonThread() { (void)stop(); }
    // Requests the clean shutdown and waits for it; the result of run().
    Status stop() {
        stop_ = true;
        return join();
    }
    // Waits for run() to return by itself (a shutdown command).
    Status join() {
        if (thread_.joinable()) thread_.join();
        return result_;
    }

private:
    std::atomic<bool> stop_{false};
    Status result_;
    std::thread thread_;
};

using hil::findSensor;
using hil::sensorConnected;

}  // namespace handscan::pipeline_daemon::test
