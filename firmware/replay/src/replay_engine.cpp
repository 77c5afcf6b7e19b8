#include "handscan/replay/replay_engine.hpp"

#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <thread>
#include <unordered_set>

#include "handscan/camera/frame_record.hpp"
#include "handscan/camera/frame_timing.hpp"
#include "handscan/camera/image_convert.hpp"
#include "handscan/colour/colouriser.hpp"
#include "handscan/core/config.hpp"
#include "handscan/core/log.hpp"
#include "handscan/export/voxel_filter.hpp"
#include "handscan/journal/journal_writer.hpp"
#include "handscan/lio/laser_inertial_odometry.hpp"
#include "handscan/live_output/live_publisher.hpp"
#include "handscan/live_output/sweep_points.hpp"
#include "handscan/recording/mcap_reader.hpp"
#include "handscan/replay/call_timer.hpp"
#include "handscan/replay/stream_decoders.hpp"
#include "handscan/scan/ply_writer.hpp"
#include "replay_outputs.hpp"

namespace handscan::replay {
namespace {

namespace fs = std::filesystem;

constexpr const char* kHokuyoTopic = "/hokuyo/raw";
constexpr const char* kXsensTopic = "/xsens/raw";
constexpr const char* kCanTopic = "/motor/can";
constexpr const char* kColourTopic = "/camera/colour";

// A recorded V4L2 buffer of the colour camera as an Image stamped at mid-exposure.
Result<Image> colourImage(std::span<const std::uint8_t> bytes) {
    auto rec = camera::decodeFrameRecord(bytes);
    if (!rec) return rec.status();
    const auto format = camera::pixelFormatFromFourcc(rec->header.fourcc);
    if (!format)
        return Status(StatusCode::kProtocolError, "colour frame with an unknown pixel format");
    Image img;
    const TimeNs exposure = static_cast<TimeNs>(rec->header.exposure_us) * kNsPerUs;
    img.t_host = camera::midExposureTime(rec->header.flags, rec->header.timestamp_ns, exposure, 0,
                                         rec->header.t_host_ns)
                     .t_mid_exposure;
    img.sequence = rec->header.sequence;
    img.format = *format;
    img.width = static_cast<int>(rec->header.width);
    img.height = static_cast<int>(rec->header.height);
    img.stride_bytes = static_cast<int>(rec->header.stride);
    img.exposure_ns = exposure;
    img.data.assign(rec->payload.begin(), rec->payload.end());
    return img;
}

// The replay's decoder counters as the status bar's sensors (nominal rates once data flows).
live_output::LiveSensor replaySensor(const char* name, const StreamCounters& c, float expected_hz) {
    return {name, c.messages > 0, c.messages > 0 ? expected_hz : 0.0f, expected_hz,
            0,    c.last_error};
}

live_output::LiveStatus replayStatus(const lio::LaserInertialOdometry& pipeline,
                                     const StreamCounters& hokuyo, const StreamCounters& xsens,
                                     const StreamCounters& encoder, const ReplayOutputs& outputs,
                                     bool finished) {
    live_output::LiveStatus s;
    s.sensors = {replaySensor("hokuyo", hokuyo, 40.0f), replaySensor("xsens", xsens, 200.0f),
                 replaySensor("encoder", encoder, 200.0f)};
    s.scan_state = finished ? shm::ScanState::kStopped : shm::ScanState::kScanning;
    s.point_count = outputs.registeredPoints();
    s.message = finished                     ? "replay finished"
                : !pipeline.aligned()        ? "hold still: aligning with gravity"
                : pipeline.tracking().lost() ? fusion::TrackingMonitor::kLostMessage
                                             : "replaying";
    return s;
}

double peakRssMiB() {
    rusage ru{};
    getrusage(RUSAGE_SELF, &ru);
    return static_cast<double>(ru.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

lio::LioConfig lioConfig(const ReplayOptions& o, const DeviceConfig& device) {
    lio::LioConfig c;
    c.laser_enabled = o.use_laser;
    c.imu_feedback = o.imu_feedback;
    c.assembler.boundary = device.motor.sweep_boundary == "full"
                               ? scan::SweepBoundary::kFullRevolution
                               : scan::SweepBoundary::kHalfRevolution;
    c.odometry.max_threads = 1;  // replay is deterministic: sweeps are matched in order
    c.reference_motion = o.reference_motion;
    c.reference_perturb_m = o.reference_perturb_m;
    c.reference_perturb_rad = o.reference_perturb_deg * M_PI / 180.0;
    return c;
}

}  // namespace

Result<ReplayReport> runReplay(const ReplayOptions& o) {
    const std::string config_dir = defaultConfigDir();
    const Calibration calibration =
        loadCalibration(o.calibration.empty() ? config_dir + "/calibration.yaml" : o.calibration);
    // The latencies calibration.yaml measured (`handscan calibrate`) replace device.yaml's.
    const DeviceConfig device = withCalibratedLatencies(
        loadDeviceConfig(o.device_config.empty() ? config_dir + "/device.yaml" : o.device_config),
        calibration);

    auto reader = recording::McapReader::open(o.recording);
    if (!reader.isOk()) return reader.status();
    recording::McapReader& rec = **reader;
    if (rec.truncated())
        log().warn("{}: recording was cut short; replaying every intact chunk", o.recording);
    for (const char* topic : {kXsensTopic, kHokuyoTopic, kCanTopic}) {
        const bool needed = std::string(topic) == kXsensTopic || o.use_laser;
        if (needed && !rec.findTopic(topic)) {
            return Status(StatusCode::kNotFound,
                          o.recording + ": no " + std::string(topic) +
                              " channel; the pipeline needs it (or choose --modules imu)");
        }
    }
    std::error_code ec;
    fs::create_directories(o.out_dir, ec);
    if (ec)
        return Status(StatusCode::kIoError,
                      "replay: cannot create " + o.out_dir + ": " + ec.message());
    if (!o.dump_sweeps_dir.empty()) fs::create_directories(o.dump_sweeps_dir, ec);

    lio::LaserInertialOdometry pipeline(lioConfig(o, device), calibration);
    HokuyoStreamDecoder hokuyo(hokuyoTiming(device));
    XsensStreamDecoder xsens(xsensTiming(device));
    EncoderStreamDecoder encoder(encoderStreamConfig(device));

    TiledMapConfig map_config;
    map_config.voxel_m = o.map_voxel_m;
    map_config.tile_m = o.map_tile_m;
    map_config.memory_budget_bytes = static_cast<std::uint64_t>(o.map_memory_mib * (1 << 20));
    map_config.spill_dir = o.map_spill_dir.empty() ? o.out_dir : o.map_spill_dir;
    ReplayOutputs outputs(o.out_dir, map_config);
    if (Status st = outputs.open(); !st.isOk()) return st;
    std::unique_ptr<journal::JournalWriter> journal;
    if (o.write_journal) {
        const std::string path = (fs::path(o.out_dir) / "journal.hsj").string();
        fs::remove(path, ec);
        auto j = journal::JournalWriter::create(
            path, "{\"source\": \"replay\", \"recording\": \"" + o.recording + "\"}");
        if (!j.isOk()) return j.status();
        journal = std::move(*j);
    }
    std::unique_ptr<live_output::LivePublisher> live;
    if (o.live) {
        auto p = live_output::LivePublisher::create(o.shm_name, o.out_dir);
        if (!p.isOk()) return p.status();
        live = std::move(*p);
    }

    std::unique_ptr<colour::Colouriser> colouriser;
    if (o.colourise && rec.findTopic(kColourTopic))
        colouriser = std::make_unique<colour::Colouriser>(calibration);
    std::uint64_t colour_errors = 0;
    CallTimer timer;
    std::vector<LaserScan> scans;
    std::vector<ImuSample> imu;
    std::vector<EncoderSample> enc;
    TimeNs t_first = 0, t_last = 0;
    const auto wall_start = std::chrono::steady_clock::now();
    const double duration_hint =
        rec.statistics()
            ? toSeconds(rec.statistics()->message_end_time - rec.statistics()->message_start_time)
            : 0.0;

    auto consume = [&]() -> Status {
        for (PoseEstimate& p : pipeline.takePoses()) {
            if (Status st = outputs.addPose(p); !st.isOk()) return st;
            // Poses guessed while tracking is lost are not the scan's trajectory.
            if (journal && !p.tracking_lost)
                (void)journal->appendPose(live_output::trajectoryPose(p));
            if (live) live->pose(p);
        }
        for (lio::RegisteredSweep& s : pipeline.takeSweeps()) {
            timer.add("scan_matching", s.result.total_ms * 1e3);
            if (!o.dump_sweeps_dir.empty()) {
                std::ostringstream name;
                name << "sweep_" << std::setw(6) << std::setfill('0') << s.sweep.index << ".ply";
                if (Status st = scan::writeSweepPly(
                        (fs::path(o.dump_sweeps_dir) / name.str()).string(), s.sweep);
                    !st.isOk()) {
                    return st;
                }
            }
            // A sweep the tracking monitor kept out of the map is journaled and shown nowhere.
            if (!s.tracking.enters_map) {
                if (Status st = outputs.addSweep(s, {}); !st.isOk()) return st;
                continue;
            }
            std::optional<colour::ColourResult> colours;
            if (colouriser) {
                const colour::PoseAtFn pose_at = [&](TimeNs t) {
                    auto p = pipeline.integratedPoseAt(t);
                    return p.isOk() ? p->T_world_body : Eigen::Isometry3d::Identity();
                };
                colours = timer.time("colourisation", [&] {
                    return colouriser->colourise(s.points_world, s.times, pose_at);
                });
            }
            const std::vector<journal::MapPoint> pts =
                live_output::sweepMapPoints(s, colours ? &*colours : nullptr);
            if (Status st = outputs.addSweep(s, pts); !st.isOk()) return st;
            if (journal) {
                if (Status st = journal->appendPoints(pts); !st.isOk()) return st;
                if (Status st = journal->flushIfDue(); !st.isOk()) return st;
            }
            if (live) live->sweep(s, pts);
        }
        return Status::ok();
    };

    std::vector<std::string> topics{kXsensTopic};
    if (colouriser) topics.push_back(kColourTopic);
    if (o.use_laser) {
        topics.push_back(kHokuyoTopic);
        topics.push_back(kCanTopic);
    }
    auto it = rec.messages({topics});
    recording::RecordedMessage msg;
    std::uint64_t n = 0;
    while (it.next(msg)) {
        if (t_first == 0) t_first = msg.log_time;
        t_last = msg.log_time;
        if (!o.fast) {
            // Recorded pace on the wall clock.
            const auto due =
                wall_start +
                std::chrono::nanoseconds(static_cast<std::int64_t>(
                    static_cast<double>(msg.log_time - t_first) / std::max(0.01, o.speed)));
            std::this_thread::sleep_until(due);
        }
        const std::string& topic = msg.channel->topic;
        if (topic == kXsensTopic) {
            imu.clear();
            timer.time("decode_xsens", [&] { xsens.feed(msg.log_time, msg.data, imu); });
            for (const ImuSample& s : imu) {
                timer.time("imu_prediction", [&] { pipeline.addImu(s); });
            }
        } else if (topic == kHokuyoTopic) {
            scans.clear();
            timer.time("decode_hokuyo", [&] { hokuyo.feed(msg.log_time, msg.data, scans); });
            for (const LaserScan& s : scans)
                timer.time("sweep_assembly_and_matching", [&] { pipeline.addScan(s); });
        } else if (topic == kColourTopic && colouriser) {
            timer.time("decode_colour", [&] {
                auto img = colourImage(msg.data);
                if (!img.isOk() || !colouriser->addImage(*img).isOk()) ++colour_errors;
            });
        } else if (topic == kCanTopic) {
            enc.clear();
            timer.time("decode_can", [&] { encoder.feed(msg.log_time, msg.data, enc); });
            for (const EncoderSample& s : enc)
                timer.time("sweep_assembly_and_matching", [&] { pipeline.addEncoder(s); });
        }
        if (Status st = consume(); !st.isOk()) return st;
        if (live && (++n % 64) == 0)
            live->status(pipeline, replayStatus(pipeline, hokuyo.counters(), xsens.counters(),
                                                encoder.counters(), outputs, false));
        if (o.progress && duration_hint > 0 && (n % 256) == 0)
            o.progress(toSeconds(msg.log_time - t_first) / duration_hint);
    }
    if (!it.status().isOk()) return it.status();
    pipeline.finish();
    if (Status st = consume(); !st.isOk()) return st;
    if (journal) {
        if (Status st = journal->finish(); !st.isOk()) return st;
    }
    const double wall_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();

    ReplayReport report;
    report.recording_s = toSeconds(t_last - t_first);
    report.wall_s = wall_s;
    report.realtime_factor = wall_s > 0 ? report.recording_s / wall_s : 0.0;
    report.poses = pipeline.stats().poses_out;
    report.sweeps = pipeline.stats().sweeps;
    if (Status st = outputs.writeTrajectory(); !st.isOk()) return st;
    auto map_points = outputs.writeMap();
    if (!map_points.isOk()) return map_points.status();
    report.map_points = *map_points;
    StatsInputs in{report,
                   timer.summary(),
                   pipeline,
                   hokuyo.counters(),
                   xsens.counters(),
                   encoder.counters(),
                   peakRssMiB(),
                   rec.truncated(),
                   rec.dropped().size()};
    auto stats_path = outputs.writeStats(in);
    if (!stats_path.isOk()) return stats_path.status();
    report.stats_json_path = *stats_path;
    if (live) {
        live->status(pipeline, replayStatus(pipeline, hokuyo.counters(), xsens.counters(),
                                            encoder.counters(), outputs, /*finished=*/true));
        while (o.hold && !(o.interrupted && o.interrupted())) {
            live->heartbeat();
            std::this_thread::sleep_for(std::chrono::milliseconds(100));
        }
    }
    return report;
}

}  // namespace handscan::replay
