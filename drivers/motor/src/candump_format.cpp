#include "handscan/motor/candump_format.hpp"

#include <cstdio>
#include <vector>

namespace handscan::motor {
namespace {

int hexNibble(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    return -1;
}

constexpr char kHexUpper[] = "0123456789ABCDEF";
constexpr std::int64_t kMaxTimestampSeconds = 9'000'000'000;  // keeps timeNs() inside int64

Status bad(std::string_view where, std::string_view what, std::string_view text) {
    std::string msg = "candump ";
    msg.append(where)
        .append(": ")
        .append(what)
        .append(" in '")
        .append(text.substr(0, 120))
        .append("'");
    return {StatusCode::kProtocolError, std::move(msg)};
}

std::string_view trimLineEnd(std::string_view s) {
    while (!s.empty() &&
           (s.back() == '\n' || s.back() == '\r' || s.back() == ' ' || s.back() == '\t')) {
        s.remove_suffix(1);
    }
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
    return s;
}

// Splits at blanks (spaces or tabs), no empty tokens.
std::vector<std::string_view> tokens(std::string_view s) {
    std::vector<std::string_view> out;
    std::size_t i = 0;
    while (i < s.size()) {
        while (i < s.size() && (s[i] == ' ' || s[i] == '\t')) ++i;
        const std::size_t start = i;
        while (i < s.size() && s[i] != ' ' && s[i] != '\t') ++i;
        if (i > start) out.push_back(s.substr(start, i - start));
    }
    return out;
}

// "(1700000000.123456)" -> seconds, microseconds.
Status parseTimestamp(std::string_view tok, CandumpRecord& rec) {
    if (tok.size() < 3 || tok.front() != '(' || tok.back() != ')')
        return bad("timestamp", "expected '(sec.usec)'", tok);
    const std::string_view inner = tok.substr(1, tok.size() - 2);
    const std::size_t dot = inner.find('.');
    if (dot == std::string_view::npos || dot == 0 || dot > 12 || inner.size() - dot - 1 != 6) {
        return bad("timestamp", "expected seconds '.' 6 digits of microseconds", tok);
    }
    std::int64_t s = 0;
    for (std::size_t i = 0; i < dot; ++i) {
        if (inner[i] < '0' || inner[i] > '9') return bad("timestamp", "non-digit", tok);
        s = s * 10 + (inner[i] - '0');
    }
    std::int32_t us = 0;
    for (std::size_t i = dot + 1; i < inner.size(); ++i) {
        if (inner[i] < '0' || inner[i] > '9') return bad("timestamp", "non-digit", tok);
        us = us * 10 + (inner[i] - '0');
    }
    if (s > kMaxTimestampSeconds)
        return bad("timestamp", "seconds beyond the year 2255 (nanoseconds would overflow)", tok);
    rec.has_time = true;
    rec.time_s = s;
    rec.time_us = us;
    return Status::ok();
}

void appendTimestamp(std::string& out, const CandumpRecord& rec) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "(%010lld.%06d)", static_cast<long long>(rec.time_s),
                  rec.time_us);
    out += buf;
}

// Parses an identifier of exactly 3 or 8 hex digits into the frame (EFF or ERR for 8 digits).
Status parseId(std::string_view digits, CanFrame& f, std::string_view text) {
    if (digits.size() != 3 && digits.size() != 8)
        return bad("identifier", "expected 3 or 8 hex digits", text);
    std::uint32_t id = 0;
    for (char c : digits) {
        const int n = hexNibble(c);
        if (n < 0) return bad("identifier", "non-hex digit", text);
        id = (id << 4) | static_cast<std::uint32_t>(n);
    }
    if (digits.size() == 8) {
        if (id & kCanErrFlag) {
            f.error = true;
            f.id = id & kCanErrMask;
        } else {
            if (id > kCanEffMask) return bad("identifier", "29-bit identifier out of range", text);
            f.extended = true;
            f.id = id;
        }
    } else {
        if (id > kCanSffMask) return bad("identifier", "11-bit identifier above 7FF", text);
        f.id = id;
    }
    return Status::ok();
}

void appendId(std::string& out, const CanFrame& f) {
    char buf[16];
    if (f.error) {
        std::snprintf(buf, sizeof buf, "%08X",
                      static_cast<unsigned>((f.id & kCanErrMask) | kCanErrFlag));
    } else if (f.extended) {
        std::snprintf(buf, sizeof buf, "%08X", static_cast<unsigned>(f.id & kCanEffMask));
    } else {
        std::snprintf(buf, sizeof buf, "%03X", static_cast<unsigned>(f.id & kCanSffMask));
    }
    out += buf;
}

}  // namespace

void CandumpRecord::setTimeNs(std::int64_t t_ns) {
    has_time = true;
    std::int64_t us = t_ns >= 0 ? t_ns / 1000 : -((-t_ns + 999) / 1000);
    if (us < 0) us = 0;  // candump cannot print times before the epoch
    time_s = us / 1'000'000;
    time_us = static_cast<std::int32_t>(us % 1'000'000);
}

Result<CanFrame> parseCanFrameText(std::string_view text) {
    CanFrame f;
    const std::size_t hash = text.find('#');
    if (hash == std::string_view::npos) return bad("frame", "missing '#'", text);
    if (Status s = parseId(text.substr(0, hash), f, text); !s) return s;
    std::size_t i = hash + 1;
    if (i < text.size() && (text[i] == 'R' || text[i] == 'r')) {
        if (f.error) return bad("frame", "error frames cannot be remote requests", text);
        f.remote = true;
        ++i;
        if (i < text.size()) {
            const int dlc = hexNibble(text[i]);
            if (dlc < 0 || dlc > 8) return bad("frame", "remote request length must be 0..8", text);
            f.len = static_cast<std::uint8_t>(dlc);
            ++i;
            if (dlc == 8 && i < text.size() && text[i] == '_') {
                const int raw = i + 1 < text.size() ? hexNibble(text[i + 1]) : -1;
                if (raw < 9 || raw > 15)
                    return bad("frame", "raw DLC after '_' must be 9..F", text);
                f.len8_dlc = static_cast<std::uint8_t>(raw);
                i += 2;
            }
        }
        if (i != text.size()) return bad("frame", "trailing characters after remote request", text);
        return f;
    }
    std::size_t max_len = kCanMaxDataLength;
    if (i < text.size() && text[i] == '#') {
        if (f.error) return bad("frame", "error frames cannot be CAN FD", text);
        const int flags = i + 1 < text.size() ? hexNibble(text[i + 1]) : -1;
        if (flags < 0) return bad("frame", "CAN FD '##' must be followed by a flags nibble", text);
        f.fd = true;
        f.fd_flags = static_cast<std::uint8_t>(flags);
        max_len = kCanFdMaxDataLength;
        i += 2;
    }
    std::size_t n = 0;
    while (i < text.size()) {
        if (text[i] == '.') {
            ++i;
            continue;
        }
        if (text[i] == '_') break;
        if (n == max_len)
            return bad("frame", f.fd ? "more than 64 data bytes" : "more than 8 data bytes", text);
        const int hi = hexNibble(text[i]);
        const int lo = i + 1 < text.size() ? hexNibble(text[i + 1]) : -1;
        if (hi < 0 || lo < 0) return bad("frame", "data must be pairs of hex digits", text);
        f.data[n++] = static_cast<std::uint8_t>((hi << 4) | lo);
        i += 2;
    }
    if (f.fd) {
        // CAN FD lengths are 0..8, 12, 16, 20, 24, 32, 48, 64.
        static constexpr std::size_t kFdLens[] = {0, 1,  2,  3,  4,  5,  6,  7,
                                                  8, 12, 16, 20, 24, 32, 48, 64};
        bool ok = false;
        for (std::size_t l : kFdLens) ok = ok || l == n;
        if (!ok)
            return bad("frame", "CAN FD length must be 0..8, 12, 16, 20, 24, 32, 48 or 64", text);
    }
    f.len = static_cast<std::uint8_t>(n);
    if (i < text.size()) {  // '_' raw DLC
        const int raw = i + 1 < text.size() ? hexNibble(text[i + 1]) : -1;
        if (f.fd || n != 8 || raw < 9 || raw > 15 || i + 2 != text.size()) {
            return bad("frame", "'_<raw dlc 9..F>' only after 8 classic data bytes", text);
        }
        f.len8_dlc = static_cast<std::uint8_t>(raw);
    }
    return f;
}

std::string formatCanFrameText(const CanFrame& f) {
    std::string out;
    out.reserve(20 + 2 * f.len);
    appendId(out, f);
    out += '#';
    if (f.remote && !f.fd) {
        out += 'R';
        if (f.len > 0 && f.len <= 8) {
            out += kHexUpper[f.len];
            if (f.len == 8 && f.len8_dlc > 8 && f.len8_dlc <= 15) {
                out += '_';
                out += kHexUpper[f.len8_dlc];
            }
        }
        return out;
    }
    if (f.fd) {
        out += '#';
        out += kHexUpper[f.fd_flags & 0x0F];
    }
    const std::size_t n =
        f.len <= (f.fd ? kCanFdMaxDataLength : kCanMaxDataLength) ? f.len : (f.fd ? 64 : 8);
    for (std::size_t k = 0; k < n; ++k) {
        out += kHexUpper[f.data[k] >> 4];
        out += kHexUpper[f.data[k] & 0x0F];
    }
    if (!f.fd && n == 8 && f.len8_dlc > 8 && f.len8_dlc <= 15) {
        out += '_';
        out += kHexUpper[f.len8_dlc];
    }
    return out;
}

Result<CandumpRecord> parseCandumpLogLine(std::string_view line) {
    const std::string_view s = trimLineEnd(line);
    const auto tok = tokens(s);
    if (tok.size() < 3 || tok.size() > 4)
        return bad("log line", "expected '(sec.usec) interface frame'", s);
    CandumpRecord rec;
    if (Status st = parseTimestamp(tok[0], rec); !st) return st;
    rec.interface = std::string(tok[1]);
    auto frame = parseCanFrameText(tok[2]);
    if (!frame) return frame.status();
    rec.frame = *frame;
    if (tok.size() == 4) rec.trailer = std::string(tok[3]);
    return rec;
}

std::string formatCandumpLogLine(const CandumpRecord& rec) {
    std::string out;
    appendTimestamp(out, rec);
    out += ' ';
    out += rec.interface.empty() ? std::string("can0") : rec.interface;
    out += ' ';
    out += formatCanFrameText(rec.frame);
    if (!rec.trailer.empty()) {
        out += ' ';
        out += rec.trailer;
    }
    return out;
}

Result<CandumpRecord> parseCandumpDefaultLine(std::string_view line) {
    const std::string_view s = trimLineEnd(line);
    auto tok = tokens(s);
    CandumpRecord rec;
    std::size_t k = 0;
    if (!tok.empty() && tok[0].front() == '(') {
        if (Status st = parseTimestamp(tok[0], rec); !st) return st;
        k = 1;
    }
    if (tok.size() < k + 3) return bad("line", "expected 'interface id [len] bytes'", s);
    rec.interface = std::string(tok[k]);
    if (Status st = parseId(tok[k + 1], rec.frame, s); !st) return st;
    const std::string_view len_tok = tok[k + 2];
    if (len_tok.size() < 3 || len_tok.front() != '[' || len_tok.back() != ']')
        return bad("length", "expected '[n]'", s);
    const std::string_view digits = len_tok.substr(1, len_tok.size() - 2);
    if (digits.size() > 2) return bad("length", "expected 1 or 2 digits", s);
    int len = 0;
    for (char c : digits) {
        if (c < '0' || c > '9') return bad("length", "non-digit", s);
        len = len * 10 + (c - '0');
    }
    rec.frame.fd = digits.size() == 2;  // candump prints "[%02d]" for CAN FD, "[%d]" for classic
    if (len > (rec.frame.fd ? 64 : 8)) return bad("length", "too long", s);
    rec.frame.len = static_cast<std::uint8_t>(len);
    const std::size_t first = k + 3;
    if (tok.size() == first + 2 && tok[first] == "remote" && tok[first + 1] == "request") {
        if (rec.frame.error || rec.frame.fd)
            return bad("frame", "error frames and CAN FD frames cannot be remote requests", s);
        rec.frame.remote = true;
        return rec;
    }
    if (tok.size() != first + static_cast<std::size_t>(len)) {
        return bad("data", "byte count differs from [len]", s);
    }
    for (int b = 0; b < len; ++b) {
        const std::string_view h = tok[first + static_cast<std::size_t>(b)];
        const int hi = h.size() == 2 ? hexNibble(h[0]) : -1;
        const int lo = h.size() == 2 ? hexNibble(h[1]) : -1;
        if (hi < 0 || lo < 0) return bad("data", "expected two hex digits per byte", s);
        rec.frame.data[static_cast<std::size_t>(b)] = static_cast<std::uint8_t>((hi << 4) | lo);
    }
    return rec;
}

std::string formatCandumpDefaultLine(const CandumpRecord& rec) {
    std::string out;
    if (rec.has_time) {
        appendTimestamp(out, rec);
        out += ' ';
    }
    out += "  ";
    out += rec.interface.empty() ? std::string("can0") : rec.interface;
    out += "  ";
    appendId(out, rec.frame);
    out += "  ";
    char buf[8];
    if (rec.frame.fd) {
        std::snprintf(buf, sizeof buf, "[%02u]", static_cast<unsigned>(rec.frame.len));
    } else {
        std::snprintf(buf, sizeof buf, " [%u]", static_cast<unsigned>(rec.frame.len));
    }
    out += buf;
    if (rec.frame.remote && !rec.frame.fd) {
        out += "  remote request";
        return out;
    }
    for (std::size_t k = 0; k < rec.frame.len && k < kCanFdMaxDataLength; ++k) {
        out += k == 0 ? "  " : " ";
        out += kHexUpper[rec.frame.data[k] >> 4];
        out += kHexUpper[rec.frame.data[k] & 0x0F];
    }
    return out;
}

Result<CandumpRecord> parseCandumpAnyLine(std::string_view line) {
    const auto tok = tokens(trimLineEnd(line));
    for (const auto& t : tok) {
        if (t.find('#') != std::string_view::npos) return parseCandumpLogLine(line);
    }
    return parseCandumpDefaultLine(line);
}

}  // namespace handscan::motor
