// ScipCodec: the pure wire format of SCIP 2.0 (Hokuyo URG / UTM-30LX-EW), both directions, byte
// for byte. No I/O. The driver decodes with it; the simulator and the fake sensor encode with it.
//
// Wire facts (SCIP 2.0 spec C-42-03320B; urg_library urg_sensor.c):
//  - every line ends in LF; a reply is: echo line, status line (2 chars + sum), data lines
//    (payload + sum), then one empty line;
//  - sum = (sum of the payload bytes & 0x3F) + 0x30;
//  - numbers are 2/3/4 characters of 6 bits each, +0x30 per character;
//  - range data comes in blocks of 64 characters (+ sum + LF) with a short last block, and a value
//    may straddle two blocks;
//  - PP/VV/II lines are "KEY:VALUE;S" where the UTM-30LX-EW sums "KEY:VALUE" (without ';'), and
//    urg_library accepts a sum over n-1 or n-2 bytes, so we do too.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "handscan/core/status.hpp"

namespace handscan::hokuyo {

inline constexpr std::size_t kScipBlockChars = 64;     // data characters per line of range data
inline constexpr std::size_t kScipMaxLineChars = 128;  // longer than any legal SCIP line

// --- sums and character encoding --------------------------------------------------------------

// The SCIP sum character of `payload`.
char scipChecksum(std::string_view payload);

// Encodes `value` in `width` (2, 3 or 4) characters. Values that do not fit are clamped to the
// largest encodable value (2^(6*width) - 1) - callers check ranges first.
std::string encodeScipChars(std::uint32_t value, int width);
void appendScipChars(std::string& out, std::uint32_t value, int width);
// Decodes 1..4 characters; every character must be in 0x30..0x6F.
Result<std::uint32_t> decodeScipChars(std::string_view chars);

// --- commands (host -> sensor) -----------------------------------------------------------------

// The scan commands: MD/MS/ME stream (M*), GD/GS/GE fetch one scan (G*, needs BM first).
// D = 3-character ranges, S = 2-character ranges, E = 3-character range + 3-character intensity.
enum class ScanEncoding : std::uint8_t { kTwoChar, kThreeChar, kThreeCharWithIntensity };

struct ScanRequest {
    char mode = 'M';  // 'M' (stream) or 'G' (single scan)
    ScanEncoding encoding = ScanEncoding::kThreeCharWithIntensity;
    int start_step = 0;   // 0..9999
    int end_step = 1080;  // 0..9999
    int cluster = 1;      // 0..99 steps merged into one value (0 is treated as 1)
    int interval = 0;     // M* only: scans skipped between transmitted scans (0..9)
    int count = 0;        // M* only: number of scans (0 = unlimited, 1..99); in a scan frame's
                          // echo, the scans still to come
    std::string tag;      // optional ";tag" (<= 16 characters) echoed back by the sensor

    std::string symbol() const;  // "ME", "GD", ...
    int valuesPerScan() const;   // number of (range[, intensity]) values in one scan
    int charsPerValue() const;   // 2, 3 or 6 (range + intensity)
    bool operator==(const ScanRequest&) const = default;
};

std::string encodeCommand(std::string_view symbol_and_parameters, std::string_view tag = {});
std::string encodeScip20Command();              // "SCIP2.0\n"
std::string encodeVersionCommand();             // "VV\n"
std::string encodeParametersCommand();          // "PP\n"
std::string encodeStatusInfoCommand();          // "II\n"
std::string encodeLaserOnCommand();             // "BM\n"
std::string encodeQuitCommand();                // "QT\n" (stop streaming, laser off)
std::string encodeResetCommand();               // "RS\n"
std::string encodeTimeAdjustCommand(int mode);  // "TM0\n" enter, "TM1\n" read, "TM2\n" leave
// The echo text of a scan request (no LF): "ME0000108001000" (+ ";tag").
std::string encodeScanEcho(const ScanRequest& request);
std::string encodeScanCommand(const ScanRequest& request);  // echo + LF
// Parses the echo / command text of a scan request ("ME0000108001000;tag"). Used by the parser
// (sensor echoes) and by the fake sensor (host commands).
Result<ScanRequest> parseScanEcho(std::string_view echo);

// --- replies (sensor -> host) ------------------------------------------------------------------

// A generic reply: echo LF, status+sum LF, every line+sum LF, LF. `lines` are payloads (no sum).
std::string encodeReply(std::string_view echo, std::string_view status,
                        const std::vector<std::string>& lines = {});
// A PP/VV/II reply: each pair becomes "KEY:VALUE;S" with the sum over "KEY:VALUE" (UTM-30LX-EW).
std::string encodeKeyValueReply(std::string_view echo, std::string_view status,
                                const std::vector<std::pair<std::string, std::string>>& items);

// One scan as the sensor sends it.
struct ScanPayload {
    std::uint32_t timestamp_ms = 0;          // 24-bit sensor clock, milliseconds
    std::vector<std::uint32_t> ranges;       // mm; values below DMIN are error codes
    std::vector<std::uint32_t> intensities;  // ME/GE only, same length as ranges
};

// Data characters of one scan (values concatenated, before splitting into blocks).
std::string encodeScanData(ScanEncoding encoding, const ScanPayload& scan);
// Splits data characters into 64-character lines + sum + LF (the short last block included).
void appendDataBlocks(std::string& out, std::string_view data);
// A full streamed (M*, status "99") or fetched (G*, status "00") scan frame. For M*,
// `request.count` must already hold the remaining count as the sensor echoes it.
std::string encodeScanFrame(const ScanRequest& request, const ScanPayload& scan);
// The acknowledgement of a scan request (echo, status, empty line), e.g. "00" or an error "04".
std::string encodeScanAck(const ScanRequest& request, std::string_view status = "00");

// --- line helpers ------------------------------------------------------------------------------

// Checks and strips the sum of a data line ("payload" + sum). Returns the payload.
Result<std::string_view> stripDataLineSum(std::string_view line_without_lf);
// A "KEY:VALUE;S" line: verifies the sum (over n-1 or n-2 bytes) and splits it.
Result<std::pair<std::string, std::string>> parseKeyValueLine(std::string_view line_without_lf);

// --- status codes ------------------------------------------------------------------------------

// What a status means for the command it answers, in words an operator can act on. `command` is
// the 2-character symbol (or "SCIP2.0").
std::string describeStatus(std::string_view command, std::string_view status);
// Whether `status` is a success for `command` ("00"; "99" for streamed scans; "02" for BM = laser
// already on; "0E" for SCIP2.0 = already in SCIP 2.0 mode; "0" = SCIP 1.1-style ack).
bool isSuccessStatus(std::string_view command, std::string_view status);

}  // namespace handscan::hokuyo
