#include "handscan/shm_demo/demo_pipeline.hpp"

#include <cmath>
#include <cstring>
#include <filesystem>

#include "handscan/core/log.hpp"
#include "handscan/export/point_formats.hpp"
#include "handscan/report/map_images.hpp"
#include "handscan/report/map_raster.hpp"
#include "handscan/shm/text_field.hpp"

namespace handscan::shm_demo {
namespace {

using shm::CommandState;
using shm::CommandType;
using shm::ScanState;

struct SensorSpec {
    const char* name;
    float rate_hz;
};
constexpr SensorSpec kSensors[] = {
    {"hokuyo", 40.0f},       {"xsens", 200.0f},     {"encoder", 100.0f},
    {"tracking-cam", 50.0f}, {"colour-cam", 10.0f},
};

}  // namespace

DemoPipeline::DemoPipeline(shm::LiveMapWriter& writer, DemoOptions options)
    : writer_(writer), o_(std::move(options)), room_(o_.room) {
    if (o_.faults.too_fast) {
        o_.room.walk_speed_mps = 2.5;
        room_ = SyntheticRoom(o_.room);
    }
}

void DemoPipeline::startScan(TimeNs now) {
    if (state_ == ScanState::kIdle) ++scan_number_;
    state_ = ScanState::kScanning;
    last_step_ = now;
}

void DemoPipeline::step(TimeNs now) {
    while (auto cmd = writer_.pollCommand()) handle(*cmd, now);
    if (state_ == ScanState::kScanning) {
        const double dt =
            std::min(toSeconds(now - last_step_), 0.5);  // a stalled caller does not teleport
        // Poses at 200 Hz over the elapsed interval.
        const int n = std::max(1, static_cast<int>(std::lround(dt * 200.0)));
        for (int i = 1; i <= n; ++i) {
            PoseEstimate p = room_.poseAt(scan_time_s_ + dt * i / n);
            p.t_host = now - static_cast<TimeNs>((n - i) * 5 * kNsPerMs);
            const std::uint8_t scan_mask = o_.faults.laser_degenerate ? 0x37 : 0x3F;  // tx unsolved
            const std::uint8_t vio_mask = o_.faults.camera_dark ? 0 : 0x3F;
            writer_.publishPose(shm::toPoseRecord(p, vio_mask, scan_mask));
            const Eigen::Vector3d pos = p.T_world_body.translation();
            if (last_position_) distance_m_ += (pos - *last_position_).norm();
            last_position_ = pos;
        }
        scan_time_s_ += dt;
        sample_debt_ += dt * o_.samples_per_second;
        const int samples = static_cast<int>(sample_debt_);
        sample_debt_ -= samples;
        auto pts = room_.observe(room_.poseAt(scan_time_s_), samples);
        if (!pts.empty()) {
            if (Status s = writer_.appendPoints(pts); !s) log().warn("{}", s.message());
            map_.insert(map_.end(), pts.begin(), pts.end());
            points_ += pts.size();
        }
    } else {
        writer_.heartbeat();
    }
    last_step_ = now;
    if (now - last_status_ >= 100 * kNsPerMs) publishStatus(now);
}

void DemoPipeline::handle(const shm::Command& cmd, TimeNs now) {
    log().info("command {} {} '{}'", cmd.seq, shm::toString(cmd.type), cmd.argument);
    switch (cmd.type) {
        case CommandType::kStartScan:
            if (state_ == ScanState::kScanning) {
                writer_.ack(cmd.seq, CommandState::kRejected, "already scanning");
                return;
            }
            startScan(now);
            writer_.ack(cmd.seq, CommandState::kDone, "scanning");
            break;
        case CommandType::kStopScan:
            if (state_ != ScanState::kScanning) {
                writer_.ack(cmd.seq, CommandState::kRejected, "not scanning");
                return;
            }
            state_ = ScanState::kStopped;
            writer_.ack(cmd.seq, CommandState::kDone,
                        "scan stopped: " + std::to_string(points_) + " points");
            break;
        case CommandType::kNewScan:
            if (state_ == ScanState::kScanning) {
                writer_.ack(cmd.seq, CommandState::kRejected, "stop the scan first");
                return;
            }
            writer_.newScan();
            room_.clear();
            map_.clear();
            points_ = 0;
            scan_time_s_ = distance_m_ = 0;
            last_position_.reset();
            state_ = ScanState::kIdle;
            writer_.ack(cmd.seq, CommandState::kDone, "new scan ready");
            break;
        case CommandType::kExport:
            if (state_ == ScanState::kScanning) {
                writer_.ack(cmd.seq, CommandState::kRejected, "stop the scan before exporting");
                return;
            }
            exportMap(cmd);
            break;
        case CommandType::kShutdown:
            shutdown_ = true;
            writer_.ack(cmd.seq, CommandState::kDone, "shutting down");
            break;
        case CommandType::kCalibrate:  // a synthetic room has no raw recording to calibrate on
            writer_.ack(cmd.seq, CommandState::kRejected,
                        "the demo has no raw recording to calibrate on (the pipeline daemon has)");
            break;
        case CommandType::kContinueScan:  // the demo has no localizer
        case CommandType::kNone:
            writer_.ack(cmd.seq, CommandState::kRejected,
                        std::string(shm::toString(cmd.type)) + ": not in the demo pipeline");
            break;
    }
    publishStatus(now);
}

void DemoPipeline::exportMap(const shm::Command& cmd) {
    namespace fs = std::filesystem;
    const fs::path dir = fs::path(cmd.argument.empty() ? o_.export_root : cmd.argument) /
                         ("scan-" + std::to_string(scan_number_));
    const fs::path file = dir / "map.ply";
    const auto fail = [&](const std::string& why) {
        export_.state = static_cast<std::uint8_t>(shm::ExportState::kFailed);
        shm::setText(export_.message, why);
        writer_.ack(cmd.seq, CommandState::kFailed, why);
        publishStatus(monotonicNow());
    };
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec)
        return fail(dir.string() + ": cannot create: " + ec.message() +
                    " (is the USB stick mounted writable?)");
    export_ = {};
    export_.state = static_cast<std::uint8_t>(shm::ExportState::kRunning);
    shm::setText(export_.target, file.string());
    // The export's PLY writer: a temporary file, verified after writing, then renamed.
    exporter::SafeFileWriter out(file.string());
    auto ply = exporter::makePlyWriter(out, {"handscan live-map export (display resolution)",
                                             "metres, world frame; intensity scaled to 0..255"});
    if (Status st = out.open(); !st.isOk()) return fail(st.message());
    if (Status st = ply->begin(map_.size()); !st.isOk()) return fail(st.message());
    // Write in slices and report progress after each, as a real export to a slow stick does.
    const std::size_t slice = std::max<std::size_t>(1, map_.size() / 20);
    std::vector<journal::MapPoint> points;
    for (std::size_t i = 0; i < map_.size(); i += slice) {
        const std::size_t n = std::min(slice, map_.size() - i);
        points.clear();
        for (std::size_t k = i; k < i + n; ++k) {
            const shm::DisplayPoint& d = map_[k];
            journal::MapPoint p;
            p.x = d.x_m;
            p.y = d.y_m;
            p.z = d.z_m;
            p.r = d.r;
            p.g = d.g;
            p.b = d.b;
            p.intensity = d.intensity;
            points.push_back(p);
        }
        if (Status st = ply->write(points); !st.isOk()) return fail(st.message());
        const float progress = static_cast<float>(i + n) / static_cast<float>(map_.size()) * 0.9f;
        export_.progress = progress;
        export_.bytes_written = out.bytesWritten();
        shm::setText(export_.message, "writing " + file.filename().string());
        writer_.ack(cmd.seq, CommandState::kInProgress, "writing " + file.string(), progress);
        publishStatus(monotonicNow());
    }
    if (Status st = ply->end(); !st.isOk()) return fail(st.message() + " (stick full or removed?)");
    writePreview();
    const auto size = fs::file_size(file, ec);
    export_.state = static_cast<std::uint8_t>(shm::ExportState::kDone);
    export_.progress = 1.0f;
    export_.safe_to_remove = 1;
    export_.bytes_written = size;
    shm::setText(export_.message,
                 "exported " + std::to_string(map_.size()) + " points: safe to remove");
    writer_.ack(cmd.seq, CommandState::kDone, "safe to remove: " + file.string(), 1.0f);
    publishStatus(monotonicNow());
}

// The map from above by height with the walk, as the export's report draws it (handscan::report).
void DemoPipeline::writePreview() const {
    if (o_.preview_png.empty() || map_.empty()) return;
    report::MapRaster top(report::View::kTop);
    std::vector<journal::MapPoint> points(map_.size());
    for (std::size_t i = 0; i < map_.size(); ++i) {
        points[i].x = map_[i].x_m;
        points[i].y = map_[i].y_m;
        points[i].z = map_[i].z_m;
    }
    top.add(points);
    auto image = report::renderMap(top, report::Colouring::kHeight, {}, "the exported map");
    if (!image.isOk() || !report::writePng(o_.preview_png, *image).isOk())
        log().warn("export preview {}: not written", o_.preview_png);
}

void DemoPipeline::publishStatus(TimeNs now) {
    last_status_ = now;
    shm::StatusBlock s;
    s.t_ns = now;
    const bool scanning = state_ == ScanState::kScanning;
    s.sensor_count = 0;
    for (const SensorSpec& spec : kSensors) {
        shm::SensorStatus& st = s.sensors[s.sensor_count++];
        shm::setText(st.name, spec.name);
        st.expected_rate_hz = spec.rate_hz;
        st.connected = 1;
        st.rate_hz = spec.rate_hz;
        st.last_sample_ns = now;
        if (o_.faults.sensor_lost && std::strcmp(spec.name, "colour-cam") == 0) {
            st.connected = 0;
            st.rate_hz = 0;
            shm::setText(st.last_error,
                         "/dev/video2: VIDIOC_DQBUF: No such device (check the camera cable)");
        }
    }
    const auto module = [&s](const char* name, shm::ModuleState state, std::uint8_t degenerate,
                             float rate) {
        shm::ModuleStatus& m = s.modules[s.module_count++];
        shm::setText(m.name, name);
        m.state = static_cast<std::uint8_t>(state);
        m.degenerate_dof_mask = degenerate;
        m.rate_hz = rate;
    };
    module("imu", shm::ModuleState::kActive, 0, 200.0f);
    module("vio", o_.faults.camera_dark ? shm::ModuleState::kBypassed : shm::ModuleState::kActive,
           o_.faults.camera_dark ? 0x3F : 0, 50.0f);
    module("scan-match", shm::ModuleState::kActive, o_.faults.laser_degenerate ? 0x08 : 0, 1.0f);
    s.scan_state = static_cast<std::uint8_t>(state_);
    s.elapsed_s = scan_time_s_;
    s.distance_m = distance_m_;
    s.point_count = points_ * 20;  // the full-resolution map is ~20x the 5 cm display map
    std::error_code ec;
    const auto space = std::filesystem::space(o_.export_root, ec);
    if (!ec) {
        s.free_storage_bytes = space.available;
        s.total_storage_bytes = space.capacity;
    }
    s.linear_speed_mps = scanning ? static_cast<float>(o_.room.walk_speed_mps) : 0.0f;
    s.angular_speed_radps = scanning ? (o_.faults.too_fast ? 3.0f : 0.4f) : 0.0f;
    s.camera_brightness = o_.faults.camera_dark ? 8.0f : 120.0f;
    s.export_status = export_;
    shm::setText(s.message, scanning ? "demo: synthetic room" : "demo: ready");
    writer_.setStatus(s);
}

}  // namespace handscan::shm_demo
