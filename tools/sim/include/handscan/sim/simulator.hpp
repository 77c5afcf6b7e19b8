// The digital twin: moves the rig along a ground-truth trajectory through a scene and produces
// what each device would have sent, byte for byte, with the host receive times a driver would
// have seen - the Hokuyo's SCIP TCP stream, the MTi's Xbus serial stream, the CAN bus of the
// spinning shaft, both cameras' V4L2 buffers - plus the ground-truth pose of the body frame {C}
// at 200 Hz. Messages reach the sink in host-time order. Same options and seed: same bytes.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "handscan/core/config.hpp"
#include "handscan/core/status.hpp"
#include "handscan/sim/camera_model.hpp"
#include "handscan/sim/camera_stream.hpp"
#include "handscan/sim/can_stream.hpp"
#include "handscan/sim/hokuyo_stream.hpp"
#include "handscan/sim/imu_model.hpp"
#include "handscan/sim/incidents.hpp"
#include "handscan/sim/laser_model.hpp"
#include "handscan/sim/raycaster.hpp"
#include "handscan/sim/scene_change.hpp"
#include "handscan/sim/scenes.hpp"
#include "handscan/sim/shaft_model.hpp"
#include "handscan/sim/stream_message.hpp"
#include "handscan/sim/trajectory.hpp"
#include "handscan/sim/xsens_stream.hpp"

namespace handscan::sim {

// Faults injected on request, spread evenly over the recording.
struct FaultOptions {
    int corrupt_scip_blocks = 0;  // a data character changed in a scan frame
    int dropped_xbus_bytes = 0;   // one byte of an MTData2 frame lost
    int lost_frames = 0;          // tracking-camera frames lost (V4L2 sequence gaps)
    int tcp_reconnects = 0;       // the Hokuyo connection drops for 1 s, then a new session
};

struct SimOptions {
    std::string scene = "office";  // built-in name or an .obj path
    std::uint64_t seed = 1;
    double duration_s = 60.0;
    std::string trajectory = "walk";  // walk | aggressive | a TUM file
    // A second session through the same scene (issue 14): the walk starts this fraction of the
    // way round the scene's loop (0: where it always starts), and this many of the scene's
    // movable objects are moved first (scene_change.hpp; which and how depends on the seed).
    double start_at = 0.0;
    int scene_change = 0;
    bool cameras = true;
    bool colour_camera = true;
    bool dark = false;
    bool motion_blur = false;
    std::string colour_format;  // "" = MJPEG (see Simulator); YUYV as device.yaml allows
    int imu_precision = 0;      // 0 float32 (as shipped), 1 fp12.20, 2 fp16.32, 3 float64
    TimeNs host_start_ns = 1000 * kNsPerSec;  // host CLOCK_MONOTONIC at the first sample
    FaultOptions faults;
    HazardOptions hazards;      // a harder world for the laser (laser_hazards.hpp)
    IncidentOptions incidents;  // one failure during the walk (incidents.hpp)
};

// Every model's parameters, defaulted from the paper (section 10.2), device.yaml and the
// calibration; tests and callers may change any of them before run().
struct SimDevices {
    LaserConfig laser;
    HokuyoStreamConfig hokuyo;
    ImuNoise imu;
    XsensStreamConfig xsens;
    ShaftConfig shaft;
    CanStreamConfig can;
    CameraRenderConfig tracking_render;
    CameraStreamConfig tracking;
    CameraRenderConfig colour_render;
    CameraStreamConfig colour;
};

class RecordingSink {
public:
    virtual ~RecordingSink() = default;
    [[nodiscard]] virtual Status write(const StreamMessage& message) = 0;
};

struct SimStats {
    std::uint64_t messages[static_cast<int>(SimChannel::kCount)] = {};
    std::uint64_t bytes[static_cast<int>(SimChannel::kCount)] = {};
    std::uint64_t laser_scans = 0, imu_samples = 0, tracking_frames = 0, colour_frames = 0;
    std::uint64_t camera_rays = 0;
    double peak_rate_dps = 0.0;
    double path_length_m = 0.0;
    bool loop_closed = false;
    int laps = 0;
};

class Simulator {
public:
    Simulator(const SimOptions& options, const DeviceConfig& device,
              const Calibration& calibration);
    ~Simulator();

    SimDevices& devices() { return dev_; }
    const Scene& scene() const { return scene_; }
    // The objects SimOptions::scene_change moved (empty without one).
    const std::vector<MovedObject>& movedObjects() const { return moved_; }
    const Trajectory& trajectory() const { return trajectory_; }
    const Calibration& calibration() const { return cal_; }
    const SimOptions& options() const { return opt_; }

    // Runs the whole recording; `progress(t)` is called with the simulated time done.
    [[nodiscard]] Status run(RecordingSink& sink, const std::function<void(double)>& progress = {});
    // Ground truth at 200 Hz on the host clock: "t x y z qx qy qz qw" lines.
    [[nodiscard]] Status writeGroundTruthTum(const std::string& path) const;
    const SimStats& stats() const { return stats_; }

    // Poses the models use (exposed for tests).
    Eigen::Isometry3d laserPose(double t) const;
    Eigen::Isometry3d colourCameraPose(double t) const;

private:
    SimOptions opt_;
    DeviceConfig device_;
    Calibration cal_;
    SimDevices dev_;
    Scene scene_;
    std::vector<MovedObject> moved_;
    Trajectory trajectory_;
    std::unique_ptr<Raycaster> raycaster_;
    std::unique_ptr<ShaftModel> shaft_;
    SimStats stats_;
};

}  // namespace handscan::sim
