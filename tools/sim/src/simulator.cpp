#include "handscan/sim/simulator.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <queue>
#include <stdexcept>

#include "handscan/core/log.hpp"
#include "handscan/recording/channels.hpp"

namespace handscan::sim {
namespace {

Scene loadScene(const std::string& name) {
    if (name.size() > 4 && name.substr(name.size() - 4) == ".obj") return importObj(name);
    return buildScene(name);
}

// A small circle around the middle of an imported mesh (no known free space: the user should
// bring a TUM trajectory).
std::vector<Eigen::Vector3d> fallbackLoop(const World& w) {
    Eigen::Vector3f lo, hi;
    w.bounds(lo, hi);
    const Eigen::Vector3d c = (0.5f * (lo + hi)).cast<double>();
    std::vector<Eigen::Vector3d> loop;
    for (int k = 0; k < 12; ++k) {
        const double a = 2 * std::numbers::pi * k / 12;
        loop.emplace_back(c.x() + std::cos(a), c.y() + std::sin(a), lo.z() + 1.3);
    }
    return loop;
}

// Indices (0..n-1) at which `count` faults happen, spread evenly.
std::vector<std::int64_t> faultSlots(int count, std::int64_t n) {
    std::vector<std::int64_t> v;
    for (int i = 0; i < count; ++i)
        v.push_back((static_cast<std::int64_t>(i) + 1) * n / (count + 1));
    return v;
}

bool takeSlot(std::vector<std::int64_t>& slots, std::int64_t k) {
    if (!slots.empty() && k >= slots.front()) {
        slots.erase(slots.begin());
        return true;
    }
    return false;
}

}  // namespace

Simulator::Simulator(const SimOptions& options, const DeviceConfig& device,
                     const Calibration& calibration)
    : opt_(options), device_(device), cal_(calibration) {
    // Device defaults from device.yaml and the calibration.
    dev_.xsens.rate_hz = device.xsens.rate_hz;
    dev_.xsens.baud = device.xsens.baud;
    dev_.xsens.delta_q_v = device.xsens.delta_q_v;
    dev_.xsens.precision = options.imu_precision;
    dev_.shaft.speed_rev_s = device.motor.target_speed_rev_s;
    dev_.can.interface = device.motor.can_interface;
    dev_.can.encoder_node = static_cast<std::uint8_t>(device.motor.encoder_node_id);
    dev_.can.drive_node = static_cast<std::uint8_t>(device.motor.drive_node_id);
    dev_.can.counts_per_rev = static_cast<std::uint32_t>(device.motor.encoder_counts_per_rev);
    dev_.can.tpdo_period_s = device.motor.tpdo_period_ms * 1e-3;
    dev_.can.encoder_zero_offset_rad = calibration.encoder_zero_offset_rad;
    dev_.tracking.fps = device.tracking_camera.fps;
    dev_.tracking.exposure_s = device.tracking_camera.exposure_ms * 1e-3;
    dev_.tracking.readout_s = device.tracking_camera.readout_ms * 1e-3;
    dev_.tracking.format = device.tracking_camera.format;
    dev_.tracking.width = calibration.tracking.resolution[0];
    dev_.tracking.height = calibration.tracking.resolution[1];
    dev_.tracking.channel = SimChannel::kTrackingCamera;
    dev_.tracking_render.exposure_s = dev_.tracking.exposure_s;
    dev_.tracking_render.reference_exposure_s = dev_.tracking.exposure_s;
    dev_.colour.fps = device.colour_camera.fps;
    dev_.colour.exposure_s = device.colour_camera.exposure_ms * 1e-3;
    dev_.colour.readout_s = device.colour_camera.readout_ms * 1e-3;
    // The colour camera's UVC MJPEG mode by default: 1600x1200 YUYV is 19 MB/s of incompressible
    // noise, which would make a one-minute recording over a gigabyte (--colour-format YUYV).
    dev_.colour.format = options.colour_format.empty() ? "MJPEG" : options.colour_format;
    dev_.colour.width = calibration.colour.resolution[0];
    dev_.colour.height = calibration.colour.resolution[1];
    dev_.colour.channel = SimChannel::kColourCamera;
    dev_.colour.start_of_exposure = false;  // UVC cameras stamp the end of the frame
    dev_.colour.clock = ClockModel{0.0, -12.0, 0.045, 0.003};
    dev_.colour_render.colour = true;
    dev_.colour_render.exposure_s = dev_.colour.exposure_s;
    dev_.colour_render.reference_exposure_s = dev_.colour.exposure_s;
    // Small rolling-shutter pixels are noisier, but a UVC camera's ISP denoises before its JPEG
    // encoder: what reaches the host has well under a DN of pixel noise.
    dev_.colour_render.read_noise_dn = 0.5;
    dev_.colour_render.render_scale = 0.5;  // shaded at 800x600, delivered at 1600x1200
    if (options.dark) {
        dev_.tracking_render.illumination = dev_.colour_render.illumination = 0.02;
    }
    dev_.tracking_render.motion_blur = dev_.colour_render.motion_blur = options.motion_blur;
    // Per-device clock offsets depend on the seed, so runs differ in more than noise.
    Rng clocks(options.seed, "clocks");
    dev_.hokuyo.clock.offset_s =
        clocks.uniform(100.0, 16000.0);  // 24-bit ms counter wraps at 4.66 h
    dev_.xsens.clock.offset_s = clocks.uniform(10.0, 400000.0);
    dev_.can.clock.offset_s = clocks.uniform(1.0, 1000.0);

    if (opt_.cameras && !cameraRecordsAvailable()) {
        log().warn("sim: built without drivers/camera, so no camera streams");
        opt_.cameras = false;
    }
    scene_ = loadScene(options.scene);
    moved_ = moveObjects(scene_, options.scene_change, options.seed);
    raycaster_ = std::make_unique<Raycaster>(scene_.world);
    shaft_ = std::make_unique<ShaftModel>(dev_.shaft);

    if (options.trajectory == "walk" || options.trajectory == "aggressive") {
        WalkOptions w;
        w.duration_s = options.duration_s;
        w.style = options.trajectory == "walk" ? MotionStyle::kWalk : MotionStyle::kAggressive;
        w.seed = options.seed;
        w.start_fraction = options.start_at;
        const auto& loop = scene_.walk_loop.empty() ? fallbackLoop(scene_.world) : scene_.walk_loop;
        WalkPlan plan = makeWalk(loop, w);
        trajectory_ = std::move(plan.trajectory);
        stats_.loop_closed = plan.closed;
        stats_.laps = plan.laps;
    } else {
        auto t = loadTum(options.trajectory);
        if (!t) throw std::runtime_error(t.status().message());
        trajectory_ = std::move(*t);
        stats_.loop_closed = false;
        opt_.duration_s = std::min(opt_.duration_s, trajectory_.duration());
    }
    if (opt_.incidents.drop_at_s >= 0.0) {
        // The floor under the hand where it slips: straight down from the device.
        const Eigen::Vector3d p =
            trajectory_.at(opt_.incidents.drop_at_s).T_world_body.translation();
        const RayHit floor = raycaster_->cast(Ray{p.cast<float>(), -Eigen::Vector3f::UnitZ(), 5.f});
        const double floor_z = floor.hit() ? p.z() - floor.t : p.z() - 1.3;
        trajectory_ = withDrop(trajectory_, opt_.incidents.drop_at_s, floor_z,
                               opt_.incidents.drop_lie_s, opt_.incidents.drop_pickup_s);
    }
    stats_.peak_rate_dps = trajectory_.peakAngularRate() * 180.0 / std::numbers::pi;
    stats_.path_length_m = trajectory_.pathLength();
}

Simulator::~Simulator() = default;

Eigen::Isometry3d Simulator::laserPose(double t) const {
    const Eigen::Isometry3d T_wc = trajectory_.at(t).T_world_body;
    const Eigen::Isometry3d R_shaft(Eigen::AngleAxisd(shaft_->angle(t), Eigen::Vector3d::UnitZ()));
    return T_wc * cal_.T_camera_shaftbase * R_shaft * cal_.T_shaft_laser;
}

Eigen::Isometry3d Simulator::colourCameraPose(double t) const {
    return trajectory_.at(t).T_world_body * cal_.T_colour_tracking.inverse();
}

Status Simulator::run(RecordingSink& sink, const std::function<void(double)>& progress) {
    const double T = opt_.duration_s;
    const TimeNs h0 = opt_.host_start_ns;
    std::unique_ptr<LaserHazards> hazards;
    LaserConfig laser_config = dev_.laser;
    if (opt_.hazards.any()) {
        hazards = std::make_unique<LaserHazards>(opt_.hazards, trajectory_, raycaster_->world(),
                                                 Rng(opt_.seed, "hazards"));
        laser_config.noise_base_m *= opt_.hazards.range_noise_scale;
        laser_config.noise_per_m *= opt_.hazards.range_noise_scale;
    }
    LaserModel laser(laser_config, *raycaster_, Rng(opt_.seed, "laser"), hazards.get());
    HokuyoStream hokuyo(dev_.hokuyo, dev_.laser, h0, Rng(opt_.seed, "hokuyo-tcp"));
    ImuModel imu(dev_.imu, cal_.tracking.T_cam_imu, dev_.xsens.rate_hz, Rng(opt_.seed, "imu"));
    XsensStream xsens(dev_.xsens, h0, Rng(opt_.seed, "xsens-serial"));
    CanStream can(dev_.can, *shaft_, h0, Rng(opt_.seed, "can"));
    std::unique_ptr<CameraRenderer> track_render, colour_render;
    std::unique_ptr<CameraStream> track_stream, colour_stream;
    if (opt_.cameras) {
        track_render = std::make_unique<CameraRenderer>(
            cal_.tracking, dev_.tracking_render, *raycaster_, Rng(opt_.seed, "track-render"));
        track_stream =
            std::make_unique<CameraStream>(dev_.tracking, h0, Rng(opt_.seed, "track-v4l2"));
        if (opt_.colour_camera) {
            colour_render = std::make_unique<CameraRenderer>(
                cal_.colour, dev_.colour_render, *raycaster_, Rng(opt_.seed, "colour-render"));
            colour_stream =
                std::make_unique<CameraStream>(dev_.colour, h0, Rng(opt_.seed, "colour-v4l2"));
        }
    }
    const double scan_dev0 = dev_.hokuyo.clock.deviceSeconds(0.1);
    auto scanTime = [&](std::int64_t k) {  // the mirror turns on the sensor's clock
        return dev_.hokuyo.clock.trueSeconds(scan_dev0 +
                                             static_cast<double>(k) * dev_.laser.scan_period_s);
    };
    const auto n_scans = static_cast<std::int64_t>(T / dev_.laser.scan_period_s);
    const auto n_imu = static_cast<std::int64_t>(T * dev_.xsens.rate_hz);
    const auto n_frames = static_cast<std::int64_t>(T * dev_.tracking.fps);
    auto scip_faults = faultSlots(opt_.faults.corrupt_scip_blocks, n_scans);
    auto xbus_faults = faultSlots(opt_.faults.dropped_xbus_bytes, n_imu);
    auto frame_faults = faultSlots(opt_.faults.lost_frames, n_frames);
    auto reconnects = faultSlots(opt_.faults.tcp_reconnects, n_scans);
    double hokuyo_down_until = -1.0;

    // Messages wait in a min-heap until no device can still produce an earlier receive time.
    struct Pending {
        StreamMessage m;
        std::uint64_t order;
    };
    auto later = [](const Pending& a, const Pending& b) {
        return a.m.t_host_rx != b.m.t_host_rx ? a.m.t_host_rx > b.m.t_host_rx : a.order > b.order;
    };
    std::priority_queue<Pending, std::vector<Pending>, decltype(later)> heap(later);
    std::uint64_t order = 0;
    std::vector<StreamMessage> batch;
    auto enqueue = [&]() {
        for (auto& m : batch) heap.push(Pending{std::move(m), order++});
        batch.clear();
    };
    auto flushBefore = [&](TimeNs limit) -> Status {
        while (!heap.empty() && heap.top().m.t_host_rx < limit) {
            const StreamMessage& m = heap.top().m;
            const auto c = static_cast<int>(m.channel);
            ++stats_.messages[c];
            stats_.bytes[c] += m.bytes.size();
            if (Status s = sink.write(m); !s) return s;
            heap.pop();
        }
        return Status::ok();
    };

    hokuyo.handshake(0.02, batch);
    xsens.handshake(0.01, batch);
    enqueue();
    std::int64_t k_scan = 0, k_imu = 0, k_gt = 0, k_track = 0, k_colour = 0;
    std::vector<std::uint8_t> pixels;
    const double window = 0.25;
    for (double w0 = 0.0; w0 < T; w0 += window) {
        const double w1 = std::min(w0 + window, T);
        // Laser scans whose step 0 falls in the window.
        for (; k_scan < n_scans && scanTime(k_scan) < w1; ++k_scan) {
            const double t0 = scanTime(k_scan);
            LaserScanTruth s = laser.scan(t0, [&](double t) { return laserPose(t); });
            ++stats_.laser_scans;
            if (opt_.incidents.laserBlind(t0)) {  // something right over the window
                std::fill(s.ranges_mm.begin(), s.ranges_mm.end(), dev_.laser.code_too_near);
                std::fill(s.intensities.begin(), s.intensities.end(), 0u);
            }
            if (takeSlot(reconnects, k_scan)) {
                hokuyo_down_until = t0 + 1.0;  // the driver notices the silence and reconnects
            }
            if (t0 < hokuyo_down_until) {
                if (scanTime(k_scan + 1) >= hokuyo_down_until)
                    hokuyo.handshake(hokuyo_down_until, batch);
                continue;
            }
            hokuyo.scan(s, takeSlot(scip_faults, k_scan), batch);
        }
        // IMU samples.
        for (; k_imu < n_imu && xsens.sampleTime(k_imu) < w1; ++k_imu) {
            const ImuMeasurement m = imu.sample(trajectory_.at(xsens.sampleTime(k_imu)));
            const bool drop_byte = takeSlot(xbus_faults, k_imu);
            if (opt_.incidents.imuSilent(xsens.sampleTime(k_imu))) continue;  // the link is down
            xsens.sample(k_imu, m, drop_byte, batch);
            ++stats_.imu_samples;
        }
        can.generate(w0, w1, batch);
        // Ground truth at 200 Hz of the host clock.
        for (; static_cast<double>(k_gt) / 200.0 < w1; ++k_gt) {
            const double t = static_cast<double>(k_gt) / 200.0;
            const Eigen::Isometry3d T_wb = trajectory_.at(t).T_world_body;
            recording::GroundTruthPose gt;
            gt.t = hostNs(h0, t);
            gt.p_world_body = T_wb.translation();
            gt.q_world_body = Eigen::Quaterniond(T_wb.linear());
            StreamMessage m{gt.t, SimChannel::kGroundTruth, {}};
            recording::encodeGroundTruthPose(gt, m.bytes);
            batch.push_back(std::move(m));
        }
        // Cameras.
        if (track_stream) {
            for (; k_track < n_frames && track_stream->exposureStart(k_track) < w1; ++k_track) {
                const bool lost = takeSlot(frame_faults, k_track);
                if (!lost)
                    track_render->render(
                        track_stream->exposureStart(k_track),
                        [&](double t) { return trajectory_.at(t).T_world_body; }, pixels);
                track_stream->frame(k_track, pixels, lost, batch);
                stats_.tracking_frames += lost ? 0 : 1;
            }
        }
        if (colour_stream) {
            for (; colour_stream->exposureStart(k_colour) < w1; ++k_colour) {
                colour_render->render(
                    colour_stream->exposureStart(k_colour),
                    [&](double t) { return colourCameraPose(t); }, pixels);
                colour_stream->frame(k_colour, pixels, false, batch);
                ++stats_.colour_frames;
            }
        }
        enqueue();
        // Nothing produced later can arrive more than ~0.2 s before its window (camera delays
        // are the longest), so everything older is final.
        if (Status s = flushBefore(hostNs(h0, w1 - 0.2)); !s) return s;
        if (progress) progress(w1);
    }
    if (Status s = flushBefore(std::numeric_limits<TimeNs>::max()); !s) return s;
    stats_.camera_rays = (track_render ? track_render->raysCast() : 0) +
                         (colour_render ? colour_render->raysCast() : 0);
    return Status::ok();
}

Status Simulator::writeGroundTruthTum(const std::string& path) const {
    std::ofstream out(path);
    if (!out) return {StatusCode::kIoError, path + ": cannot open for writing"};
    out << "# ground truth of the body frame {C} in the gravity-aligned world frame; t on the host "
           "clock (s)\n"
        << "# t x y z qx qy qz qw\n";
    char line[256];
    for (std::int64_t k = 0; static_cast<double>(k) / 200.0 <= opt_.duration_s + 1e-9; ++k) {
        const double t = static_cast<double>(k) / 200.0;
        const Eigen::Isometry3d T_wb = trajectory_.at(t).T_world_body;
        const Eigen::Quaterniond q(T_wb.linear());
        const Eigen::Vector3d p = T_wb.translation();
        std::snprintf(line, sizeof(line), "%.9f %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n",
                      toSeconds(hostNs(opt_.host_start_ns, t)), p.x(), p.y(), p.z(), q.x(), q.y(),
                      q.z(), q.w());
        out << line;
    }
    out.flush();
    if (!out) return {StatusCode::kIoError, path + ": write failed"};
    return Status::ok();
}

}  // namespace handscan::sim
