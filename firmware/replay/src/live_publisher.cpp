#include "live_publisher.hpp"

#include <cmath>
#include <filesystem>

#include "handscan/shm/text_field.hpp"

namespace handscan::replay {
namespace {

void sensor(shm::SensorStatus& s, const char* name, const StreamCounters& c, float expected_hz) {
    shm::setText(s.name, name);
    shm::setText(s.last_error, c.last_error);
    s.connected = c.messages > 0 ? 1 : 0;
    s.expected_rate_hz = expected_hz;
    s.rate_hz = c.messages > 0 ? expected_hz : 0.0f;
}

}  // namespace

Result<std::unique_ptr<LivePublisher>> LivePublisher::create(const std::string& name, std::string storage_dir) {
    shm::WriterOptions opt;
    if (!name.empty()) opt.name = name;
    auto w = shm::LiveMapWriter::create(opt);
    if (!w.isOk()) return w.status();
    (*w)->newScan();
    return std::unique_ptr<LivePublisher>(new LivePublisher(std::move(*w), std::move(storage_dir)));
}

void LivePublisher::pose(const PoseEstimate& pose) {
    if (first_pose_t_ == 0) first_pose_t_ = pose.t_host;
    last_pose_t_ = pose.t_host;
    writer_->publishPose(pose);
}

void LivePublisher::sweep(const lio::RegisteredSweep& sweep, const lio::LaserInertialOdometry&) {
    last_solved_mask_ = sweep.result.pose.solved_dof_mask;
    std::vector<shm::DisplayPoint> pts;
    for (std::size_t i = 0; i < sweep.points_world.size(); ++i) {
        const Eigen::Vector3f& p = sweep.points_world[i];
        const auto grey = static_cast<std::uint8_t>(std::min(255.0f, sweep.intensities[i] / 16.0f));
        const shm::DisplayPoint d{p.x(), p.y(), p.z(), grey, grey, grey, grey};
        if (shown_voxels_.insert(d)) pts.push_back(d);
    }
    (void)writer_->appendPoints(pts);  // a full display buffer only thins the display
}

void LivePublisher::status(const lio::LaserInertialOdometry& pipeline, const StreamCounters& hokuyo,
                           const StreamCounters& xsens, const StreamCounters& encoder, const ReplayOutputs& outputs,
                           bool finished) {
    shm::StatusBlock s;
    s.t_ns = last_pose_t_;
    s.sensor_count = 3;
    sensor(s.sensors[0], "hokuyo", hokuyo, 40.0f);
    sensor(s.sensors[1], "xsens", xsens, 200.0f);
    sensor(s.sensors[2], "encoder", encoder, 200.0f);
    s.module_count = 2;
    shm::setText(s.modules[0].name, "imu");
    s.modules[0].state = static_cast<std::uint8_t>(shm::ModuleState::kActive);
    s.modules[0].rate_hz = 200.0f;
    shm::setText(s.modules[1].name, "scan-match");
    s.modules[1].state = static_cast<std::uint8_t>(pipeline.stats().sweeps > 0 ? shm::ModuleState::kActive : shm::ModuleState::kOff);
    s.modules[1].degenerate_dof_mask = static_cast<std::uint8_t>(~last_solved_mask_ & 0x3F);
    s.modules[1].rate_hz = 2.0f;
    s.scan_state = static_cast<std::uint8_t>(finished ? shm::ScanState::kStopped : shm::ScanState::kScanning);
    s.elapsed_s = toSeconds(last_pose_t_ - first_pose_t_);
    s.distance_m = outputs.distance_m();
    s.point_count = outputs.registeredPoints();
    std::error_code ec;
    const auto space = std::filesystem::space(storage_dir_, ec);
    if (!ec) {
        s.free_storage_bytes = space.available;
        s.total_storage_bytes = space.capacity;
    }
    shm::setText(s.message, finished ? "replay finished" : (pipeline.aligned() ? "replaying" : "hold still: aligning with gravity"));
    writer_->setStatus(s);
}

}  // namespace handscan::replay
