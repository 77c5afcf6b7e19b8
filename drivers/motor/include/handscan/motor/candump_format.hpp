// The can-utils text formats of CAN frames (can-utils lib.c parse_canframe / snprintf_canframe):
//   candump -l / -L log line:  "(1700000000.123456) can0 181#11223344"
//     identifier 3 hex digits (11-bit) or 8 (29-bit, or an error frame with 0x20000000 set),
//     "#R[len]" marks a remote request, "##<flags nibble><data>" a CAN FD frame, an optional
//     "_<raw dlc>" after 8 data bytes the classic raw DLC 9..15, '.' separators are skipped.
//   candump default (screen) format: "  can0  181   [4]  11 22 33 44"
//     (with -t a a leading "(1700000000.123456) "; "remote request" for RTR; "[08]" for FD).
// Pure text <-> CanFrame conversion; recordings store CAN as one log line per message
// (channel /motor/can), and the candump-log transport reads and writes these lines.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "handscan/core/can_frame.hpp"
#include "handscan/core/status.hpp"

namespace handscan::motor {

struct CandumpRecord {
    bool has_time = false;     // false for default-format lines printed without -t
    std::int64_t time_s = 0;   // seconds part of the timestamp
    std::int32_t time_us = 0;  // microseconds part (0..999999)
    std::string interface;     // "can0"
    CanFrame frame;
    std::string
        trailer;  // anything after the frame (newer candump prints " R"/" T"), kept verbatim

    // Timestamp in ns (the recorder writes host CLOCK_MONOTONIC here).
    std::int64_t timeNs() const { return time_s * 1'000'000'000 + std::int64_t{time_us} * 1'000; }
    void setTimeNs(std::int64_t t_ns);
};

// The frame part alone: "181#11223344", "1F334455#R", "123##1AABB".
Result<CanFrame> parseCanFrameText(std::string_view text);
std::string formatCanFrameText(const CanFrame& frame);

// One `candump -l` line (no trailing newline needed; CR/LF are ignored).
Result<CandumpRecord> parseCandumpLogLine(std::string_view line);
std::string formatCandumpLogLine(const CandumpRecord& record);

// One default-format line.
Result<CandumpRecord> parseCandumpDefaultLine(std::string_view line);
std::string formatCandumpDefaultLine(const CandumpRecord& record);

// Either format, detected from the line (a log line has '#' in its frame token).
Result<CandumpRecord> parseCandumpAnyLine(std::string_view line);

}  // namespace handscan::motor
