#include "handscan/hokuyo/scip_stream_parser.hpp"

#include <algorithm>
#include <cstdio>

namespace handscan::hokuyo {

namespace {

constexpr std::size_t kMaxEchoChars = 2 + 13 + 1 + 16;  // symbol, parameters, ';', tag
constexpr std::size_t kMaxBodyLines = 64;               // far more than any PP/VV/II reply

bool isUpper(char c) { return c >= 'A' && c <= 'Z'; }
bool isDigit(char c) { return c >= '0' && c <= '9'; }

std::string quoted(std::string_view s) {
    std::string out = "\"";
    for (char c : s.substr(0, 32)) {
        if (c >= 0x20 && c < 0x7F) {
            out += c;
        } else {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\x%02X", static_cast<unsigned char>(c));
            out += buf;
        }
    }
    if (s.size() > 32) out += "...";
    return out + "\"";
}

bool isKeyValueCommand(std::string_view command) {
    return command == "PP" || command == "VV" || command == "II";
}

}  // namespace

std::optional<std::string> ScipFrame::item(std::string_view key) const {
    for (const auto& [k, v] : items) {
        if (k == key) return v;
    }
    return std::nullopt;
}

void ScipStreamParser::feed(std::string_view bytes, std::vector<ScipEvent>& out) {
    feed(std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(bytes.data()),
                                       bytes.size()),
         out);
}

void ScipStreamParser::feed(std::span<const std::uint8_t> bytes, std::vector<ScipEvent>& out) {
    stats_.bytes += bytes.size();
    for (const std::uint8_t b : bytes) {
        ++offset_;
        if (b == '\n') {
            onLine(out);
            line_.clear();
            line_overflow_ = false;
            line_start_ = offset_;
        } else if (line_.size() < kScipMaxLineChars) {
            line_ += static_cast<char>(b);
        } else {
            line_overflow_ = true;
        }
    }
}

void ScipStreamParser::reset() {
    state_ = State::kIdle;
    line_.clear();
    line_overflow_ = false;
    line_start_ = offset_;
    frame_ = {};
    scan_data_.clear();
}

bool ScipStreamParser::idle() const { return state_ == State::kIdle && line_.empty(); }

void ScipStreamParser::onLine(std::vector<ScipEvent>& out) {
    if (line_overflow_) {
        if (state_ != State::kSkipping) {
            fail(StatusCode::kProtocolError,
                 "line longer than " + std::to_string(kScipMaxLineChars) + " characters", out);
        }
        stats_.discarded_bytes += offset_ - line_start_;
        state_ = State::kSkipping;
        return;
    }
    processLine(line_, out);
}

void ScipStreamParser::processLine(std::string_view line, std::vector<ScipEvent>& out) {
    switch (state_) {
        case State::kIdle:
            if (line.empty()) {
                ++stats_.discarded_bytes;  // a stray LF between frames
            } else if (startFrame(line)) {
                state_ = State::kStatus;
            } else {
                fail(StatusCode::kProtocolError, "expected an echo line, got " + quoted(line), out);
                processLine(line, out);
            }
            return;
        case State::kSkipping:
            if (line.empty()) {
                ++stats_.discarded_bytes;
                state_ = State::kIdle;
            } else if (startFrame(line)) {
                state_ = State::kStatus;
            } else {
                stats_.discarded_bytes += line.size() + 1;
            }
            return;
        case State::kStatus:
            onStatus(line, out);
            return;
        case State::kBody:
            onBodyLine(line, out);
            return;
        case State::kScanTimestamp: {
            if (line.size() != 5) {
                fail(line.empty() ? StatusCode::kTruncated : StatusCode::kProtocolError,
                     "scan timestamp line " + quoted(line) + ": expected 4 characters + sum", out);
                processLine(line, out);
                return;
            }
            auto payload = stripDataLineSum(line);
            if (!payload) {
                ++stats_.checksum_failures;
                fail(StatusCode::kChecksumError, "scan timestamp: " + payload.status().message(),
                     out);
                processLine(line, out);
                return;
            }
            auto ts = decodeScipChars(*payload);
            if (!ts) {
                fail(StatusCode::kProtocolError, ts.status().message(), out);
                processLine(line, out);
                return;
            }
            frame_.scan = ScanPayload{};
            frame_.scan->timestamp_ms = *ts;
            state_ = scan_expected_chars_ == 0 ? State::kScanEnd : State::kScanData;
            return;
        }
        case State::kScanData:
            onScanDataLine(line, out);
            return;
        case State::kScanEnd:
            if (line.empty()) {
                emit(out, offset_);
            } else {
                // The terminating empty line was lost; the scan itself is complete and verified.
                ++stats_.missing_terminators;
                emit(out, line_start_);
                processLine(line, out);
            }
            return;
    }
}

bool ScipStreamParser::startFrame(std::string_view line) {
    if (line.size() > kMaxEchoChars) return false;
    for (char c : line) {
        if (c < 0x20 || c > 0x7E) return false;
    }
    ScipFrame f;
    const auto semi = line.find(';');
    const std::string_view body = line.substr(0, semi);
    if (semi != std::string_view::npos && line.size() - semi - 1 > 16) return false;
    if (body == "SCIP2.0" || body == "SCIP1.1") {
        f.command = std::string(body);
    } else {
        if (body.size() < 2 || !isUpper(body[0]) || !isUpper(body[1]) || body.size() > 15) {
            return false;
        }
        if (!std::all_of(body.begin() + 2, body.end(),
                         [](char c) { return isDigit(c) || isUpper(c); })) {
            return false;
        }
        f.command = std::string(body.substr(0, 2));
        const bool scan_symbol = (body[0] == 'M' || body[0] == 'G') &&
                                 (body[1] == 'S' || body[1] == 'D' || body[1] == 'E');
        if (scan_symbol) {
            auto request = parseScanEcho(line);
            if (!request) return false;
            f.scan_request = *request;
        }
    }
    f.echo = std::string(line);
    f.stream_offset = line_start_;
    frame_ = std::move(f);
    scan_data_.clear();
    scan_expected_chars_ = 0;
    return true;
}

void ScipStreamParser::onStatus(std::string_view line, std::vector<ScipEvent>& out) {
    if (line.size() == 1 && isDigit(line[0])) {
        frame_.status = std::string(line);  // SCIP 1.1-style acknowledgement without a sum
    } else if (line.size() == 3 && (isDigit(line[0]) || isUpper(line[0])) &&
               (isDigit(line[1]) || isUpper(line[1]))) {
        if (scipChecksum(line.substr(0, 2)) != line[2]) {
            ++stats_.checksum_failures;
            fail(StatusCode::kChecksumError,
                 "status line " + quoted(line) + " of " + quoted(frame_.echo) + ": bad sum", out);
            processLine(line, out);
            return;
        }
        frame_.status = std::string(line.substr(0, 2));
    } else {
        fail(line.empty() ? StatusCode::kTruncated : StatusCode::kProtocolError,
             "reply to " + quoted(frame_.echo) + ": expected a status line, got " + quoted(line),
             out);
        processLine(line, out);
        return;
    }
    const auto& req = frame_.scan_request;
    const bool data_follows = req && ((req->mode == 'M' && frame_.status == "99") ||
                                      (req->mode == 'G' && frame_.status == "00"));
    if (data_follows) {
        scan_expected_chars_ = static_cast<std::size_t>(req->valuesPerScan()) *
                               static_cast<std::size_t>(req->charsPerValue());
        scan_data_.reserve(scan_expected_chars_);
        state_ = State::kScanTimestamp;
    } else {
        state_ = State::kBody;
    }
}

void ScipStreamParser::onBodyLine(std::string_view line, std::vector<ScipEvent>& out) {
    if (line.empty()) {
        emit(out, offset_);
        return;
    }
    if (frame_.items.size() + frame_.lines.size() >= kMaxBodyLines) {
        fail(StatusCode::kProtocolError,
             "reply to " + quoted(frame_.echo) + ": more than " + std::to_string(kMaxBodyLines) +
                 " lines without the terminating empty line",
             out);
        processLine(line, out);
        return;
    }
    if (isKeyValueCommand(frame_.command)) {
        auto kv = parseKeyValueLine(line);
        if (!kv) {
            if (kv.status().code() == StatusCode::kChecksumError) ++stats_.checksum_failures;
            fail(kv.status().code(), kv.status().message(), out);
            processLine(line, out);
            return;
        }
        frame_.items.push_back(std::move(*kv));
        return;
    }
    // Other data lines: the strict sum, or (as urg_library accepts) the sum over n-2 bytes.
    auto payload = stripDataLineSum(line);
    if (payload) {
        frame_.lines.emplace_back(*payload);
    } else if (line.size() >= 2 && scipChecksum(line.substr(0, line.size() - 2)) == line.back()) {
        frame_.lines.emplace_back(line.substr(0, line.size() - 2));
    } else {
        ++stats_.checksum_failures;
        fail(StatusCode::kChecksumError,
             "reply to " + quoted(frame_.echo) + ": " + payload.status().message(), out);
        processLine(line, out);
    }
}

void ScipStreamParser::onScanDataLine(std::string_view line, std::vector<ScipEvent>& out) {
    const auto where = [&] {
        return "scan " + quoted(frame_.echo) + " after " + std::to_string(scan_data_.size()) +
               " of " + std::to_string(scan_expected_chars_) + " data characters";
    };
    if (line.empty()) {
        fail(StatusCode::kTruncated, where() + ": frame ended early", out);
        processLine(line, out);
        return;
    }
    if (line.size() > kScipBlockChars + 1) {
        fail(StatusCode::kProtocolError,
             where() + ": block of " + std::to_string(line.size() - 1) + " characters (max 64)",
             out);
        processLine(line, out);
        return;
    }
    auto payload = stripDataLineSum(line);
    if (!payload) {
        ++stats_.checksum_failures;
        fail(StatusCode::kChecksumError, where() + ": " + payload.status().message(), out);
        processLine(line, out);
        return;
    }
    const std::size_t total = scan_data_.size() + payload->size();
    if (total > scan_expected_chars_) {
        fail(StatusCode::kProtocolError, where() + ": block overruns the requested scan size", out);
        processLine(line, out);
        return;
    }
    if (payload->size() != kScipBlockChars && total < scan_expected_chars_) {
        fail(StatusCode::kProtocolError,
             where() + ": short block of " + std::to_string(payload->size()) +
                 " characters before the last one",
             out);
        processLine(line, out);
        return;
    }
    scan_data_.append(*payload);
    if (total == scan_expected_chars_) finishScan(out);
}

void ScipStreamParser::finishScan(std::vector<ScipEvent>& out) {
    const ScanRequest& req = *frame_.scan_request;
    const int n = req.valuesPerScan();
    const bool intensity = req.encoding == ScanEncoding::kThreeCharWithIntensity;
    const std::size_t w = req.encoding == ScanEncoding::kTwoChar ? 2 : 3;
    ScanPayload& scan = *frame_.scan;
    scan.ranges.resize(static_cast<std::size_t>(n));
    if (intensity) scan.intensities.resize(static_cast<std::size_t>(n));
    std::size_t pos = 0;
    for (std::size_t i = 0; i < static_cast<std::size_t>(n); ++i) {
        auto r = decodeScipChars(std::string_view(scan_data_).substr(pos, w));
        pos += w;
        Result<std::uint32_t> in = std::uint32_t{0};
        if (intensity) {
            in = decodeScipChars(std::string_view(scan_data_).substr(pos, w));
            pos += w;
        }
        if (!r || !in) {
            fail(StatusCode::kProtocolError,
                 "scan " + quoted(frame_.echo) + " value " + std::to_string(i) + ": " +
                     (!r ? r.status() : in.status()).message(),
                 out);
            return;
        }
        scan.ranges[i] = *r;
        if (intensity) scan.intensities[i] = *in;
    }
    state_ = State::kScanEnd;
}

void ScipStreamParser::emit(std::vector<ScipEvent>& out, std::uint64_t end_offset) {
    ++stats_.frames;
    frame_.stream_end = end_offset;
    if (frame_.scan) ++stats_.scans;
    out.emplace_back(std::move(frame_));
    frame_ = {};
    scan_data_.clear();
    state_ = State::kIdle;
}

void ScipStreamParser::fail(StatusCode code, const std::string& what, std::vector<ScipEvent>& out) {
    ++stats_.resyncs;
    out.emplace_back(ScipFault{code, "SCIP stream: " + what + " (line at stream byte " +
                                         std::to_string(line_start_) + "); frame dropped"});
    frame_ = {};
    scan_data_.clear();
    state_ = State::kSkipping;
}

}  // namespace handscan::hokuyo
