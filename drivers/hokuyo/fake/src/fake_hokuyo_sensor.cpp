#include "handscan/hokuyo_fake/fake_hokuyo_sensor.hpp"

#include <algorithm>
#include <charconv>

#include "handscan/hokuyo/scip_stream_parser.hpp"

namespace handscan::hokuyo {

namespace {

bool allDigits(std::string_view s) {
    return !s.empty() &&
           std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
}

}  // namespace

std::vector<SourceScanFrame> splitScanFrames(std::string_view stream) {
    ScipStreamParser parser;
    std::vector<ScipEvent> events;
    parser.feed(stream, events);
    std::vector<SourceScanFrame> frames;
    for (auto& e : events) {
        auto* f = std::get_if<ScipFrame>(&e);
        if (f == nullptr || !f->scan) continue;
        frames.push_back(
            {std::string(stream.substr(f->stream_offset, f->stream_end - f->stream_offset)),
             *f->scan_request, std::move(*f->scan)});
    }
    return frames;
}

FakeHokuyoSensor::FakeHokuyoSensor(std::vector<SourceScanFrame> source, FakeHokuyoIdentity identity)
    : source_(std::move(source)), identity_(std::move(identity)) {}

void FakeHokuyoSensor::onHostBytes(std::string_view bytes) {
    for (char c : bytes) {
        if (c == '\n' || c == '\r') {
            if (!line_.empty()) onCommand(line_);  // CRLF: the LF ends an empty line, ignored
            line_.clear();
        } else if (line_.size() < 64) {
            line_ += c;
        }
    }
}

std::string FakeHokuyoSensor::takeReplies() { return std::exchange(out_, {}); }

void FakeHokuyoSensor::onDisconnect() {
    streaming_ = false;
    laser_on_ = false;
    line_.clear();
    out_.clear();
}

int FakeHokuyoSensor::ppInt(const char* key, int fallback) const {
    for (const auto& [k, v] : identity_.pp) {
        if (k == key) {
            int x = fallback;
            std::from_chars(v.data(), v.data() + v.size(), x);
            return x;
        }
    }
    return fallback;
}

void FakeHokuyoSensor::onCommand(const std::string& command) {
    const std::string body = command.substr(0, command.find(';'));
    const bool scan_command = body.size() >= 2 && (body[0] == 'M' || body[0] == 'G') &&
                              (body[1] == 'S' || body[1] == 'D' || body[1] == 'E');
    // SCIP2.0 included: a SCIP 2.0-only sensor answers it with "command not defined" (0E) too.
    if (body == "VV") {
        out_ += encodeKeyValueReply(command, "00", identity_.vv);
    } else if (body == "PP") {
        out_ += encodeKeyValueReply(command, "00", identity_.pp);
    } else if (body == "II") {
        const std::uint32_t now = next_ > 0 ? source_[next_ - 1].scan.timestamp_ms : time_ms_;
        out_ += encodeKeyValueReply(
            command, "00",
            {{"MODL", ppInt("ARES", 1440) == 1440 ? "UTM-30LX-EW" : "URG"},
             {"LASR", laser_on_ ? "ON" : "OFF"},
             {"SCSP", "Initial(" + std::to_string(ppInt("SCAN", 2400)) + "[rpm])"},
             {"MESM", "Measuring by Normal Mode"},
             {"SBPS", "Ethernet 100 [Mbps]"},
             {"TIME", encodeScipChars(now & 0xFFFFFFu, 4)},
             {"STAT", identity_.stat}});
    } else if (body == "BM") {
        out_ += encodeReply(command, laser_on_ ? "02" : "00");
        laser_on_ = true;
    } else if (body == "QT" || body == "RS") {
        streaming_ = false;
        laser_on_ = false;
        out_ += encodeReply(command, "00");
    } else if (body == "TM0" || body == "TM2") {
        out_ += encodeReply(command, "00");
    } else if (body == "TM1") {
        const std::uint32_t now = next_ > 0 ? source_[next_ - 1].scan.timestamp_ms : time_ms_;
        out_ += encodeReply(command, "00", {encodeScipChars(now & 0xFFFFFFu, 4)});
    } else if (scan_command) {
        onScanCommand(command);
    } else {
        out_ += encodeReply(command, "0E");  // command not defined
    }
}

void FakeHokuyoSensor::onScanCommand(const std::string& command) {
    const std::string body = command.substr(0, command.find(';'));
    const bool stream = body[0] == 'M';
    auto reply = [&](const char* status) { out_ += encodeReply(command, status); };
    if (body.size() != (stream ? 15u : 12u))
        return reply("0C");  // malformed length (unconfirmed code)
    if (!allDigits(body.substr(2, 4))) return reply("01");
    if (!allDigits(body.substr(6, 4))) return reply("02");
    if (!allDigits(body.substr(10, 2))) return reply("03");
    if (stream && !allDigits(body.substr(12, 1))) return reply("06");
    if (stream && !allDigits(body.substr(13, 2))) return reply("07");
    auto request = parseScanEcho(command);
    if (!request) return reply("0C");
    if (request->start_step < ppInt("AMIN", 0) || request->end_step > ppInt("AMAX", 1080))
        return reply("04");
    if (request->end_step < request->start_step) return reply("05");
    if (!stream) {
        if (!laser_on_) return reply("10");
        SourceScanFrame frame;
        if (next_ < source_.size()) {
            last_index_ = next_;
            frame = source_[next_++];
        } else {
            frame.request = *request;
            frame.scan.ranges.assign(static_cast<std::size_t>(request->valuesPerScan()), 0);
        }
        out_ += encodeForRequest(frame, *request);
        return;
    }
    reply("00");
    laser_on_ = true;  // MD/MS/ME switch the laser on themselves
    streaming_ = true;
    stream_request_ = *request;
    remaining_ = request->count;
}

std::optional<std::string> FakeHokuyoSensor::nextStreamFrame(std::uint32_t* timestamp_ms) {
    if (!streaming_ || next_ >= source_.size()) return std::nullopt;
    last_index_ = next_;
    const SourceScanFrame& frame = source_[next_++];
    ScanRequest r = stream_request_;
    if (remaining_ > 0) {
        r.count = --remaining_;
        if (remaining_ == 0) streaming_ = false;
    }
    if (timestamp_ms != nullptr) *timestamp_ms = frame.scan.timestamp_ms;
    if (frame.request == r) return frame.bytes;  // as recorded, byte for byte
    return encodeForRequest(frame, r);
}

std::string FakeHokuyoSensor::encodeForRequest(const SourceScanFrame& frame,
                                               const ScanRequest& r) const {
    // Each requested value is the minimum over its cluster of steps (as the sensor merges them).
    const ScanRequest& src = frame.request;
    const int src_cluster = std::max(src.cluster, 1);
    const int cluster = std::max(r.cluster, 1);
    ScanPayload out;
    out.timestamp_ms = frame.scan.timestamp_ms;
    const bool intensity = r.encoding == ScanEncoding::kThreeCharWithIntensity;
    const std::uint32_t max_value = r.encoding == ScanEncoding::kTwoChar ? 4095u : 262143u;
    for (int j = 0; j < r.valuesPerScan(); ++j) {
        std::uint32_t best = 0;
        std::uint32_t best_intensity = 0;
        bool found = false;
        const int first = r.start_step + j * cluster;
        const int last = std::min(first + cluster - 1, r.end_step);
        for (int step = first; step <= last; ++step) {
            if (step < src.start_step || step > src.end_step) continue;
            const auto i = static_cast<std::size_t>((step - src.start_step) / src_cluster);
            if (i >= frame.scan.ranges.size()) continue;
            if (!found || frame.scan.ranges[i] < best) {
                best = frame.scan.ranges[i];
                best_intensity = i < frame.scan.intensities.size() ? frame.scan.intensities[i] : 0;
                found = true;
            }
        }
        out.ranges.push_back(std::min(best, max_value));
        if (intensity) out.intensities.push_back(best_intensity);
    }
    return encodeScanFrame(r, out);
}

}  // namespace handscan::hokuyo
