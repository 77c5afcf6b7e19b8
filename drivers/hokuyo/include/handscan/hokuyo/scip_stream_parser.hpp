// ScipStreamParser: turns the sensor's byte stream into typed SCIP frames, fed in pieces split
// anywhere (TCP segments). Pure, byte-at-a-time in spirit (as PX4's distance-sensor parsers):
// it only sees bytes and never blocks.
//
// Every line's sum is checked. A scan is accepted only when every block but the last holds exactly
// 64 characters and the data add up to the number of values the echo asked for. After any fault
// (bad sum, garbage, a truncated or overlong frame) the parser reports it, drops the damaged frame
// and resynchronises: it skips to the next empty line (the SCIP frame terminator) or to the next
// line that is a well-formed echo, whichever comes first, so a lost terminator costs no frame.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "handscan/core/status.hpp"
#include "handscan/hokuyo/scip_codec.hpp"

namespace handscan::hokuyo {

// One complete, verified reply.
struct ScipFrame {
    std::string echo;     // echo line as received, without LF ("ME0000108001000", "PP", "TM1")
    std::string command;  // 2-character symbol ("ME", "PP", "TM") or "SCIP2.0"
    std::string status;   // "00", "99", "0E", ... ("0" for a SCIP 1.1-style ack)
    // PP/VV/II: the KEY:VALUE items in order.
    std::vector<std::pair<std::string, std::string>> items;
    // Other replies with data (TM1, unsupported commands): line payloads without their sums.
    std::vector<std::string> lines;
    std::optional<ScanRequest> scan_request;  // parsed echo of MD/MS/ME/GD/GS/GE
    std::optional<ScanPayload> scan;          // a scan with its data (status 99, or 00 for G*)
    std::uint64_t stream_offset = 0;          // stream byte at which the echo started
    std::uint64_t stream_end = 0;             // stream byte just past the frame's terminator

    bool ok() const { return isSuccessStatus(command, status); }
    std::string statusText() const { return describeStatus(command, status); }
    // The value of a PP/VV/II key, if present.
    std::optional<std::string> item(std::string_view key) const;
};

// A fault the parser recovered from; the damaged frame was dropped.
struct ScipFault {
    StatusCode code = StatusCode::kProtocolError;  // kChecksumError, kProtocolError, kTruncated
    std::string message;                           // what and where ("... at stream byte 123456")
};

using ScipEvent = std::variant<ScipFrame, ScipFault>;

struct ScipParserStats {
    std::uint64_t bytes = 0;
    std::uint64_t frames = 0;               // verified frames emitted (scans included)
    std::uint64_t scans = 0;                // frames carrying scan data
    std::uint64_t checksum_failures = 0;    // lines whose sum did not match
    std::uint64_t resyncs = 0;              // times the parser dropped a frame and searched again
    std::uint64_t discarded_bytes = 0;      // bytes skipped while resynchronising
    std::uint64_t missing_terminators = 0;  // complete scans not followed by the empty line
};

class ScipStreamParser {
public:
    // Consumes `bytes`; appends every completed frame or recovered fault to `out` in stream order.
    void feed(std::span<const std::uint8_t> bytes, std::vector<ScipEvent>& out);
    void feed(std::string_view bytes, std::vector<ScipEvent>& out);
    // Forgets any partial frame (after a reconnect the stream starts afresh). Stats are kept.
    void reset();
    // True when no partial frame is pending (the stream is between frames).
    bool idle() const;

    const ScipParserStats& stats() const { return stats_; }

private:
    enum class State { kIdle, kSkipping, kStatus, kBody, kScanTimestamp, kScanData, kScanEnd };

    void onLine(std::vector<ScipEvent>& out);
    void processLine(std::string_view line, std::vector<ScipEvent>& out);
    bool startFrame(std::string_view line);
    void onStatus(std::string_view line, std::vector<ScipEvent>& out);
    void onBodyLine(std::string_view line, std::vector<ScipEvent>& out);
    void onScanDataLine(std::string_view line, std::vector<ScipEvent>& out);
    void finishScan(std::vector<ScipEvent>& out);
    void emit(std::vector<ScipEvent>& out, std::uint64_t end_offset);
    void fail(StatusCode code, const std::string& what, std::vector<ScipEvent>& out);

    State state_ = State::kIdle;
    std::string line_;              // current line without LF
    bool line_overflow_ = false;    // current line exceeded kScipMaxLineChars
    std::uint64_t offset_ = 0;      // stream bytes consumed
    std::uint64_t line_start_ = 0;  // stream offset of line_[0]
    ScipFrame frame_;
    std::string scan_data_;  // concatenated block payloads of the current scan
    std::size_t scan_expected_chars_ = 0;
    ScipParserStats stats_;
};

}  // namespace handscan::hokuyo
