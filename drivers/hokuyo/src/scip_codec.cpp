#include "handscan/hokuyo/scip_codec.hpp"

#include <algorithm>
#include <charconv>
#include <cstdio>

namespace handscan::hokuyo {

namespace {

std::string fourDigits(int v) {
    char buf[8];
    std::snprintf(buf, sizeof buf, "%04d", std::clamp(v, 0, 9999));
    return buf;
}

std::string twoDigits(int v) {
    char buf[8];
    std::snprintf(buf, sizeof buf, "%02d", std::clamp(v, 0, 99));
    return buf;
}

// Parses exactly `text.size()` decimal digits.
std::optional<int> parseDigits(std::string_view text) {
    int v = 0;
    if (text.empty()) return std::nullopt;
    for (char c : text) {
        if (c < '0' || c > '9') return std::nullopt;
        v = v * 10 + (c - '0');
    }
    return v;
}

std::string printable(std::string_view s) {
    std::string out;
    for (char c : s.substr(0, 40)) {
        if (c >= 0x20 && c < 0x7F) {
            out += c;
        } else {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\x%02X", static_cast<unsigned char>(c));
            out += buf;
        }
    }
    if (s.size() > 40) out += "...";
    return out;
}

}  // namespace

char scipChecksum(std::string_view payload) {
    unsigned sum = 0;
    for (char c : payload) sum += static_cast<unsigned char>(c);
    return static_cast<char>((sum & 0x3F) + 0x30);
}

void appendScipChars(std::string& out, std::uint32_t value, int width) {
    const int w = std::clamp(width, 1, 4);
    const std::uint32_t max = (std::uint32_t{1} << (6 * w)) - 1;
    const std::uint32_t v = std::min(value, max);
    for (int i = w - 1; i >= 0; --i) out += static_cast<char>(((v >> (6 * i)) & 0x3F) + 0x30);
}

std::string encodeScipChars(std::uint32_t value, int width) {
    std::string out;
    appendScipChars(out, value, width);
    return out;
}

Result<std::uint32_t> decodeScipChars(std::string_view chars) {
    if (chars.empty() || chars.size() > 4) {
        return Status(StatusCode::kInvalidArgument,
                      "SCIP value: expected 1..4 characters, got " + std::to_string(chars.size()));
    }
    std::uint32_t v = 0;
    for (char c : chars) {
        const auto u = static_cast<unsigned char>(c);
        if (u < 0x30 || u > 0x6F) {
            return Status(StatusCode::kProtocolError,
                          "SCIP value \"" + printable(chars) + "\": character outside 0x30..0x6F");
        }
        v = (v << 6) | (u - 0x30u);
    }
    return v;
}

// --- commands ----------------------------------------------------------------------------------

std::string ScanRequest::symbol() const {
    std::string s(1, mode);
    switch (encoding) {
        case ScanEncoding::kTwoChar:
            s += 'S';
            break;
        case ScanEncoding::kThreeChar:
            s += 'D';
            break;
        case ScanEncoding::kThreeCharWithIntensity:
            s += 'E';
            break;
    }
    return s;
}

int ScanRequest::valuesPerScan() const {
    if (end_step < start_step) return 0;
    const int c = std::max(cluster, 1);
    return (end_step - start_step) / c + 1;
}

int ScanRequest::charsPerValue() const {
    switch (encoding) {
        case ScanEncoding::kTwoChar:
            return 2;
        case ScanEncoding::kThreeChar:
            return 3;
        case ScanEncoding::kThreeCharWithIntensity:
            return 6;
    }
    return 3;
}

std::string encodeCommand(std::string_view symbol_and_parameters, std::string_view tag) {
    std::string out(symbol_and_parameters);
    if (!tag.empty()) {
        out += ';';
        out += tag.substr(0, 16);
    }
    out += '\n';
    return out;
}

std::string encodeScip20Command() { return "SCIP2.0\n"; }
std::string encodeVersionCommand() { return "VV\n"; }
std::string encodeParametersCommand() { return "PP\n"; }
std::string encodeStatusInfoCommand() { return "II\n"; }
std::string encodeLaserOnCommand() { return "BM\n"; }
std::string encodeQuitCommand() { return "QT\n"; }
std::string encodeResetCommand() { return "RS\n"; }
std::string encodeTimeAdjustCommand(int mode) {
    return "TM" + std::to_string(std::clamp(mode, 0, 2)) + "\n";
}

std::string encodeScanEcho(const ScanRequest& request) {
    std::string out = request.symbol() + fourDigits(request.start_step) +
                      fourDigits(request.end_step) + twoDigits(request.cluster);
    if (request.mode == 'M') {
        out += static_cast<char>('0' + std::clamp(request.interval, 0, 9));
        out += twoDigits(request.count);
    }
    if (!request.tag.empty()) {
        out += ';';
        out += request.tag.substr(0, 16);
    }
    return out;
}

std::string encodeScanCommand(const ScanRequest& request) { return encodeScanEcho(request) + "\n"; }

Result<ScanRequest> parseScanEcho(std::string_view echo) {
    auto bad = [&](const std::string& why) {
        return Status(StatusCode::kProtocolError,
                      "SCIP scan echo \"" + printable(echo) + "\": " + why);
    };
    ScanRequest r;
    const auto semi = echo.find(';');
    std::string_view body = echo.substr(0, semi);
    if (semi != std::string_view::npos) {
        r.tag = std::string(echo.substr(semi + 1));
        if (r.tag.size() > 16) return bad("tag longer than 16 characters");
    }
    if (body.size() < 2) return bad("too short");
    r.mode = body[0];
    if (r.mode != 'M' && r.mode != 'G') return bad("not an MD/MS/ME/GD/GS/GE command");
    switch (body[1]) {
        case 'S':
            r.encoding = ScanEncoding::kTwoChar;
            break;
        case 'D':
            r.encoding = ScanEncoding::kThreeChar;
            break;
        case 'E':
            r.encoding = ScanEncoding::kThreeCharWithIntensity;
            break;
        default:
            return bad("not an MD/MS/ME/GD/GS/GE command");
    }
    const std::size_t want = r.mode == 'M' ? 15 : 12;
    if (body.size() != want) {
        return bad("expected " + std::to_string(want) + " characters before any ';', got " +
                   std::to_string(body.size()));
    }
    const auto start = parseDigits(body.substr(2, 4));
    const auto end = parseDigits(body.substr(6, 4));
    const auto cluster = parseDigits(body.substr(10, 2));
    if (!start) return bad("start step is not 4 decimal digits");
    if (!end) return bad("end step is not 4 decimal digits");
    if (!cluster) return bad("cluster count is not 2 decimal digits");
    r.start_step = *start;
    r.end_step = *end;
    r.cluster = *cluster;
    if (r.mode == 'M') {
        const auto interval = parseDigits(body.substr(12, 1));
        const auto count = parseDigits(body.substr(13, 2));
        if (!interval) return bad("scan interval is not a decimal digit");
        if (!count) return bad("scan count is not 2 decimal digits");
        r.interval = *interval;
        r.count = *count;
    } else {
        r.interval = 0;
        r.count = 0;
    }
    return r;
}

// --- replies -----------------------------------------------------------------------------------

namespace {

void appendLineWithSum(std::string& out, std::string_view payload) {
    out.append(payload);
    out += scipChecksum(payload);
    out += '\n';
}

void appendHeader(std::string& out, std::string_view echo, std::string_view status) {
    out.append(echo);
    out += '\n';
    appendLineWithSum(out, status);
}

}  // namespace

std::string encodeReply(std::string_view echo, std::string_view status,
                        const std::vector<std::string>& lines) {
    std::string out;
    appendHeader(out, echo, status);
    for (const auto& l : lines) appendLineWithSum(out, l);
    out += '\n';
    return out;
}

std::string encodeKeyValueReply(std::string_view echo, std::string_view status,
                                const std::vector<std::pair<std::string, std::string>>& items) {
    std::string out;
    appendHeader(out, echo, status);
    for (const auto& [key, value] : items) {
        std::string kv = key;
        kv += ':';
        kv += value;
        out += kv;
        out += ';';
        out += scipChecksum(kv);
        out += '\n';
    }
    out += '\n';
    return out;
}

std::string encodeScanData(ScanEncoding encoding, const ScanPayload& scan) {
    std::string data;
    const bool with_intensity = encoding == ScanEncoding::kThreeCharWithIntensity;
    const int width = encoding == ScanEncoding::kTwoChar ? 2 : 3;
    data.reserve(scan.ranges.size() * (with_intensity ? 6 : static_cast<std::size_t>(width)));
    for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
        appendScipChars(data, scan.ranges[i], width);
        if (with_intensity) {
            appendScipChars(data, i < scan.intensities.size() ? scan.intensities[i] : 0, 3);
        }
    }
    return data;
}

void appendDataBlocks(std::string& out, std::string_view data) {
    for (std::size_t pos = 0; pos < data.size(); pos += kScipBlockChars) {
        appendLineWithSum(out, data.substr(pos, kScipBlockChars));
    }
}

std::string encodeScanFrame(const ScanRequest& request, const ScanPayload& scan) {
    std::string out;
    const std::string data = encodeScanData(request.encoding, scan);
    out.reserve(data.size() + data.size() / kScipBlockChars * 2 + 64);
    appendHeader(out, encodeScanEcho(request), request.mode == 'M' ? "99" : "00");
    appendLineWithSum(out, encodeScipChars(scan.timestamp_ms & 0xFFFFFFu, 4));
    appendDataBlocks(out, data);
    out += '\n';
    return out;
}

std::string encodeScanAck(const ScanRequest& request, std::string_view status) {
    return encodeReply(encodeScanEcho(request), status);
}

// --- line helpers ------------------------------------------------------------------------------

Result<std::string_view> stripDataLineSum(std::string_view line) {
    if (line.empty()) {
        return Status(StatusCode::kProtocolError, "SCIP data line: empty, expected payload + sum");
    }
    const std::string_view payload = line.substr(0, line.size() - 1);
    const char got = line.back();
    const char want = scipChecksum(payload);
    if (got != want) {
        return Status(StatusCode::kChecksumError, "SCIP data line \"" + printable(line) +
                                                      "\": sum '" + printable({&got, 1}) +
                                                      "', computed '" + std::string(1, want) + "'");
    }
    return payload;
}

Result<std::pair<std::string, std::string>> parseKeyValueLine(std::string_view line) {
    if (line.size() < 2) {
        return Status(StatusCode::kProtocolError,
                      "SCIP parameter line \"" + printable(line) + "\": too short for KEY:VALUE;S");
    }
    const char got = line.back();
    const std::string_view n1 = line.substr(0, line.size() - 1);  // includes the ';'
    const std::string_view n2 = line.substr(0, line.size() - 2);  // without the ';'
    if (got != scipChecksum(n1) && got != scipChecksum(n2)) {
        return Status(StatusCode::kChecksumError,
                      "SCIP parameter line \"" + printable(line) + "\": sum '" +
                          printable({&got, 1}) + "' matches neither \"" + printable(n2) + "\" ('" +
                          std::string(1, scipChecksum(n2)) + "') nor with ';'");
    }
    std::string_view body = n1;
    if (!body.empty() && body.back() == ';') body.remove_suffix(1);
    const auto colon = body.find(':');
    if (colon == std::string_view::npos || colon == 0) {
        return Status(StatusCode::kProtocolError,
                      "SCIP parameter line \"" + printable(line) + "\": no KEY: before the value");
    }
    return std::pair<std::string, std::string>{std::string(body.substr(0, colon)),
                                               std::string(body.substr(colon + 1))};
}

// --- status codes ------------------------------------------------------------------------------

bool isSuccessStatus(std::string_view command, std::string_view status) {
    if (status == "00" || status == "0") return true;
    if (status == "99" && command.size() >= 1 && command[0] == 'M') return true;
    if (command == "BM" && status == "02") return true;
    if (command == "SCIP2.0" && status == "0E") return true;
    return false;
}

std::string describeStatus(std::string_view command, std::string_view status) {
    const std::string cmd(command);
    const std::string st(status);
    auto with = [&](const std::string& text) { return cmd + " status " + st + ": " + text; };
    if (status == "00") return with("ok");
    if (status == "0") return with("ok (SCIP 1.1-style acknowledgement)");
    // A SCIP 2.0-only sensor (UTM-30LX-EW) does not know the mode switch and answers "0E"
    // (command not defined): it is already speaking SCIP 2.0.
    if (command == "SCIP2.0" && status == "0E") return with("ok, sensor already in SCIP 2.0 mode");
    if (command == "BM") {
        if (status == "01")
            return with(
                "laser could not be switched on (laser malfunction); "
                "power-cycle the sensor");
        if (status == "02") return with("laser already on");
    }
    const bool scan = !command.empty() && (command[0] == 'M' || command[0] == 'G');
    const auto code = parseDigits(status);
    if (scan && code) {
        const int c = *code;
        if (c == 99) return with("scan data follows");
        if (c == 98) return with("sensor resumed normal operation after an error");
        if (c >= 1 && c <= 7) {
            static const char* kWhat[] = {"",
                                          "start step is not a number",
                                          "end step is not a number",
                                          "cluster count is not a number",
                                          "end step out of the sensor's range",
                                          "end step smaller than start step",
                                          "scan interval is not a number",
                                          "scan count is not a number"};
            return with(std::string("bad scan request: ") + kWhat[c] +
                        "; check the request against the PP parameters");
        }
        if (c == 10) return with("laser is off; send BM before GD/GS/GE");
        if (c >= 21 && c <= 49) return with("scan stopped on a sensor error; restart the stream");
        if (c >= 50 && c <= 97) {
            return with("sensor hardware fault; power-cycle the sensor, check II STAT");
        }
    }
    if (!status.empty() && status[0] == '0' && status.size() == 2 && status[1] >= 'A' &&
        status[1] <= 'Z') {
        if (status == "0E") return with("command not defined on this sensor");
        return with("command rejected by the sensor (unknown, denied or malformed command)");
    }
    return with("unexpected status; see the SCIP 2.0 specification");
}

}  // namespace handscan::hokuyo
