#include "handscan/hil/recording_fakes.hpp"

#include <algorithm>
#include <fstream>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "handscan/camera/timed_frame_file.hpp"
#include "handscan/motor/candump_format.hpp"
#include "handscan/motor/motor_setup.hpp"

namespace handscan::hil {
namespace {

// The daemon's motor start-up (the same MotorDevice code and configuration, NMT and SDO
// requests, boot-up, the drive's enable sequence and speed) run against the emulated encoder and
// drive: the replies the daemon's candump bus hands back, in order, when the daemon asks. A
// recording's own start-up answers whatever master recorded it (the simulator's differs), so it
// is not replayed.
std::vector<motor::CandumpRecord> startupExchange(const MotorConfig& config) {
    motor::EmulatedMotorNodes nodes(config);
    std::ostringstream wire;
    nodes.bus().setRecorder(&wire);
    motor::MotorDevice device(nodes.bus(), motor::motorDeviceConfig(config),
                              [&] { return nodes.bus().now(); });
    if (Status s = device.start(); !s.isOk())
        throw std::runtime_error("emulated motor start-up: " + s.message());
    if (Status s = device.setMotorSpeed(2.0 * std::numbers::pi * config.target_speed_rev_s);
        !s.isOk())
        throw std::runtime_error("emulated motor start-up: " + s.message());
    std::vector<motor::CandumpRecord> out;
    std::istringstream lines(wire.str());
    for (std::string line; std::getline(lines, line);) {
        if (auto r = motor::parseCandumpAnyLine(line)) out.push_back(std::move(*r));
    }
    return out;
}

// Start-up traffic of a recording: NMT commands, SDO requests and replies, boot-up messages.
bool isStartupFrame(const transport::CanFrame& f) {
    if (f.extended) return false;
    const std::uint32_t fn = f.id & 0x780u;
    const bool boot_up = fn == 0x700u && f.len == 1 && f.data[0] == 0;
    return f.id == 0 || fn == 0x580u || fn == 0x600u || boot_up;
}

// The CAN log the daemon plays (candump -l lines on the host clock): the start-up exchange, then
// the recorded frames (PDOs, heartbeats, emergencies) due after it at their times. The exchange
// begins at `startup_at` (host time), or by default ends just before the recording's stream.
// Lines that do not parse are kept as they are (the daemon's log bus counts and skips them, as it
// would in the recording).
std::size_t writeHostClockCandump(const RecordedStreams& rec, const MotorConfig& motor,
                                  TimeNs offset, const std::filesystem::path& path,
                                  std::optional<TimeNs> startup_at = std::nullopt) {
    std::vector<std::pair<std::optional<motor::CandumpRecord>, const RecordedCanFrame*>> stream;
    for (const RecordedCanFrame& f : rec.can) {
        auto record = motor::parseCandumpAnyLine(f.line);
        if (!record) {
            stream.emplace_back(std::nullopt, &f);
        } else if (!isStartupFrame(record->frame)) {
            record->setTimeNs(f.t + offset);
            stream.emplace_back(std::move(*record), &f);
        }
    }
    std::ofstream out(path, std::ios::trunc);
    if (!out) throw std::runtime_error(path.string() + ": cannot write the CAN log for the daemon");
    const TimeNs first = rec.can.empty() ? rec.start : rec.can.front().t;
    std::vector<motor::CandumpRecord> startup = startupExchange(motor);
    TimeNs startup_end = startup_at.value_or(first + offset - kNsPerMs);
    if (!startup.empty()) {
        const TimeNs shift = startup_at ? *startup_at - startup.front().timeNs()
                                        : first + offset - kNsPerMs - startup.back().timeNs();
        for (motor::CandumpRecord& r : startup) {
            r.setTimeNs(r.timeNs() + shift);
            out << motor::formatCandumpLogLine(r) << '\n';
        }
        startup_end = startup.back().timeNs();
    }
    std::size_t n = 0;
    for (const auto& [record, frame] : stream) {
        if (frame->t + offset <= startup_end) continue;  // sent while the node was starting
        if (record) {
            out << motor::formatCandumpLogLine(*record) << '\n';
            ++n;
        } else {
            out << frame->line << '\n';
        }
    }
    out.flush();
    if (!out) throw std::runtime_error(path.string() + ": writing the CAN log failed (disk full?)");
    return n;
}

constexpr TimeNs kScanPeriod = 25 * kNsPerMs;  // UTM-30LX-EW, 2400 rpm

// The first recorded scan repeated for `seconds` before it, its sensor timestamp stepped back one
// scan period each (24-bit ms counter).
std::vector<hokuyo::SourceScanFrame> prerollScans(const RecordedStreams& rec, double seconds) {
    std::vector<hokuyo::SourceScanFrame> out;
    const auto n = static_cast<std::uint32_t>(fromSeconds(seconds) / kScanPeriod);
    const hokuyo::SourceScanFrame& first = rec.scans.front();
    for (std::uint32_t k = n; k > 0; --k) {
        hokuyo::SourceScanFrame f = first;
        f.scan.timestamp_ms =
            (first.scan.timestamp_ms - k * static_cast<std::uint32_t>(kScanPeriod / kNsPerMs)) &
            0xFFFFFFu;
        f.bytes = hokuyo::encodeScanFrame(f.request, f.scan);
        out.push_back(std::move(f));
    }
    return out;
}

}  // namespace

RecordingFakes::RecordingFakes(const RecordedStreams& rec, const MotorConfig& motor, TimeNs offset,
                               const std::filesystem::path& dir, FakesOptions options)
    : rec_(rec),
      motor_(motor),
      offset_(offset),
      dir_(dir),
      scans_(rec.scans.size()),
      xsens_chunks_(rec.xsens_measurement.size()) {
    if (options.hokuyo && !rec.scans.empty()) {
        hokuyo::FakeServerOptions o;
        std::vector<hokuyo::SourceScanFrame> source = prerollScans(rec, options.hokuyo_preroll_s);
        for (std::size_t k = source.size(); k > 0; --k)
            o.schedule.push_back(rec.scan_rx.front() + offset -
                                 static_cast<TimeNs>(k) * kScanPeriod);
        const std::size_t preroll = source.size();
        o.count_from = preroll;
        source.insert(source.end(), rec.scans.begin(), rec.scans.end());
        for (TimeNs t : rec.scan_rx) o.schedule.push_back(t + offset);
        if (options.hokuyo_disconnect_s) {
            const TimeNs at = rec.start + fromSeconds(*options.hokuyo_disconnect_s);
            const auto it = std::lower_bound(rec.scan_rx.begin(), rec.scan_rx.end(), at);
            if (it != rec.scan_rx.end()) {
                hokuyo::FakeLinkFault f;
                f.kind = hokuyo::FakeLinkFault::Kind::kCloseMidFrame;
                f.frame_index = preroll + static_cast<std::size_t>(it - rec.scan_rx.begin());
                f.byte_offset = 100;  // inside the first data block
                o.faults.push_back(f);
            }
        }
        hokuyo_ = std::make_unique<hokuyo::FakeHokuyoServer>(std::move(source), o);
        if (Status s = hokuyo_->start(); !s.isOk())
            throw std::runtime_error("fake Hokuyo: " + s.message());
    }
    if (options.xsens && !rec.xsens_measurement.empty()) {
        xsens::FakeXsensConfig xc;
        xc.streaming_at_start = false;  // the recorded stream starts after GoToMeasurement
        if (rec.xsens_device_id != 0) xc.device_id = rec.xsens_device_id;
        if (!rec.xsens_product_code.empty()) xc.product_code = rec.xsens_product_code;
        xsens_ = std::make_unique<xsens::FakeXsens>(xc);
        xsens::PtyXsensOptions po;
        po.real_time = true;
        for (const auto& c : rec.xsens_measurement)
            po.recorded_measurement.push_back({c.t_host_rx + offset, c.bytes});
        pty_ = std::make_unique<xsens::PtyXsens>(*xsens_, std::move(po));
    }
    if (options.motor && !rec.can.empty()) {
        candump_ = dir / "motor-host-clock.candump";
        can_frames_ = writeHostClockCandump(rec, motor, offset, candump_);
    }
    if (options.cameras) {
        const auto play = [offset](const std::string& file, std::size_t count, std::string& path,
                                   std::size_t& played) {
            if (file.empty() || count == 0) return;
            if (Status s = camera::TimedFrameFileWriter::setClockOffset(file, offset); !s.isOk())
                throw std::runtime_error("camera frames: " + s.message());
            path = file;
            played = count;
        };
        play(rec.track_frames, rec.track_frame_count, track_frames_, track_frame_count_);
        play(rec.colour_frames, rec.colour_frame_count, colour_frames_, colour_frame_count_);
    }
}

std::filesystem::path RecordingFakes::restartCandump(TimeNs startup_at) {
    if (candump_.empty()) return candump_;
    candump_ = dir_ / ("motor-host-clock-restart-" + std::to_string(++restarts_) + ".candump");
    (void)writeHostClockCandump(rec_, motor_, offset_, candump_, startup_at);
    return candump_;
}

RecordingFakes::~RecordingFakes() {
    pty_.reset();
    xsens_.reset();
    if (hokuyo_) hokuyo_->stop();
}

RecordingFakes::Counts RecordingFakes::counts() const {
    Counts c;
    c.scans_recorded = scans_;
    if (hokuyo_) {
        c.scans_sent = hokuyo_->framesSent();
        c.scans_skipped = hokuyo_->framesSkipped();
        c.hokuyo_connections = hokuyo_->connections();
    }
    c.xsens_chunks_recorded = xsens_chunks_;
    if (pty_) {
        c.xsens_chunks_sent = pty_->recordedChunksSent();
        c.xsens_chunks_lost = pty_->recordedChunksLost();
    }
    c.can_frames = can_frames_;
    c.track_frames = track_frame_count_;
    c.colour_frames = colour_frame_count_;
    return c;
}

}  // namespace handscan::hil
