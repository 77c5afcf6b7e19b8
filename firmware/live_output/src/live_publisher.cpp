#include "handscan/live_output/live_publisher.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <filesystem>

#include "handscan/live_output/change_report.hpp"
#include "handscan/shm/text_field.hpp"

namespace handscan::live_output {

Result<std::unique_ptr<LivePublisher>> LivePublisher::create(const shm::WriterOptions& options,
                                                             std::string storage_dir) {
    auto w = shm::LiveMapWriter::create(options);
    if (!w.isOk()) return w.status();
    (*w)->newScan();
    return std::unique_ptr<LivePublisher>(new LivePublisher(std::move(*w), std::move(storage_dir)));
}

Result<std::unique_ptr<LivePublisher>> LivePublisher::create(const std::string& name,
                                                             std::string storage_dir) {
    shm::WriterOptions opt;
    if (!name.empty()) opt.name = name;
    return create(opt, std::move(storage_dir));
}

void LivePublisher::pose(const PoseEstimate& pose) {
    if (last_pose_ && pose.t_host > last_pose_->t_host) {
        const double dt = toSeconds(pose.t_host - last_pose_->t_host);
        const double step =
            (pose.T_world_body.translation() - last_pose_->T_world_body.translation()).norm();
        const double turn = Eigen::AngleAxisd(last_pose_->T_world_body.linear().transpose() *
                                              pose.T_world_body.linear())
                                .angle();
        // Smoothed over ~0.2 s so one noisy sample does not flash "moving too fast".
        const float a = static_cast<float>(std::min(1.0, dt / 0.2));
        linear_speed_mps_ += a * (static_cast<float>(step / dt) - linear_speed_mps_);
        angular_speed_radps_ += a * (static_cast<float>(turn / dt) - angular_speed_radps_);
        if (scanning_) {
            distance_m_ += step;
            elapsed_s_ += dt;
        }
    }
    last_pose_ = pose;
    writer_->publishPose(pose);
}

void LivePublisher::sweep(const lio::RegisteredSweep& sweep,
                          std::span<const journal::MapPoint> points) {
    last_solved_mask_ = sweep.result.pose.solved_dof_mask;
    std::vector<shm::DisplayPoint> shown;
    for (const journal::MapPoint& m : points) {
        const auto level = static_cast<std::uint8_t>(std::min(255, m.intensity / 16));
        const shm::DisplayPoint d{m.x, m.y, m.z, m.r, m.g, m.b, level};
        if (shown_voxels_.insert(d)) shown.push_back(d);
    }
    (void)writer_->appendPoints(shown);  // a full display buffer only thins the display
}

void LivePublisher::status(const lio::LaserInertialOdometry& pipeline, const LiveStatus& in) {
    shm::StatusBlock s;
    s.t_ns = last_pose_ ? last_pose_->t_host : monotonicNow();
    s.sensor_count = static_cast<std::uint32_t>(std::min(in.sensors.size(), shm::kMaxSensors));
    for (std::size_t i = 0; i < s.sensor_count; ++i) {
        const LiveSensor& from = in.sensors[i];
        shm::SensorStatus& to = s.sensors[i];
        shm::setText(to.name, from.name);
        shm::setText(to.last_error, from.last_error);
        to.connected = from.connected ? 1 : 0;
        to.rate_hz = from.rate_hz;
        to.expected_rate_hz = from.expected_rate_hz;
        to.last_sample_ns = from.last_sample_ns;
    }
    s.module_count = 2;
    shm::setText(s.modules[0].name, "imu");
    s.modules[0].state = static_cast<std::uint8_t>(pipeline.aligned() ? shm::ModuleState::kActive
                                                                      : shm::ModuleState::kOff);
    s.modules[0].rate_hz = 200.0f;
    shm::setText(s.modules[1].name, "scan-match");
    s.modules[1].state = static_cast<std::uint8_t>(
        pipeline.stats().sweeps > 0 ? shm::ModuleState::kActive : shm::ModuleState::kOff);
    s.modules[1].degenerate_dof_mask = static_cast<std::uint8_t>(~last_solved_mask_ & 0x3F);
    s.modules[1].rate_hz = 2.0f;
    s.scan_state = static_cast<std::uint8_t>(in.scan_state);
    s.elapsed_s = elapsed_s_;
    s.distance_m = distance_m_;
    s.point_count = in.point_count;
    s.linear_speed_mps = linear_speed_mps_;
    s.angular_speed_radps = angular_speed_radps_;
    s.camera_brightness = in.camera_brightness;
    if (in.export_status) s.export_status = *in.export_status;
    if (in.calibration) s.calibration = *in.calibration;
    std::error_code ec;
    const auto space = std::filesystem::space(storage_dir_, ec);
    if (!ec) {
        s.free_storage_bytes = space.available;
        s.total_storage_bytes = space.capacity;
    }
    s.localization = static_cast<std::uint8_t>(in.localization);
    s.can_continue = in.can_continue ? 1 : 0;
    shm::setText(s.message, in.message);
    writer_->setStatus(s);
}

void LivePublisher::changes(const localize::Localizer& localizer) {
    // Cells change only when a match is used (the lock, then each tracking update).
    const std::uint64_t used = localizer.stats().updates + (localizer.locked() ? 1 : 0);
    if (used == changes_of_matches_) return;
    changes_of_matches_ = used;
    const std::vector<localize::ChangeCell> cells = localizer.changes();
    writer_->setChanges(toChangeReport(cells, localizer.config().change_cell_m));
}

void LivePublisher::showEarlierScan(std::span<const shm::DisplayPoint> points,
                                    std::span<const journal::TrajectoryPose> trajectory) {
    std::vector<shm::DisplayPoint> shown;
    shown.reserve(points.size());
    for (const shm::DisplayPoint& d : points) {
        if (shown_voxels_.insert(d)) shown.push_back(d);
    }
    (void)writer_->appendPoints(shown);  // a full display buffer only thins the display
    for (const journal::TrajectoryPose& p : trajectory) {
        shm::PoseRecord r;
        r.t_ns = static_cast<std::int64_t>(p.t_s * 1e9);
        r.position_m[0] = p.x;
        r.position_m[1] = p.y;
        r.position_m[2] = p.z;
        r.orientation_xyzw[0] = p.qx;
        r.orientation_xyzw[1] = p.qy;
        r.orientation_xyzw[2] = p.qz;
        r.orientation_xyzw[3] = p.qw;
        writer_->appendTrack(r);  // thinned as the live path is
    }
}

void LivePublisher::newScan() {
    writer_->newScan();  // and its change report
    changes_of_matches_ = 0;
    shown_voxels_.clear();
    distance_m_ = 0;
    elapsed_s_ = 0;
}

}  // namespace handscan::live_output
