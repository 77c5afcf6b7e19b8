#include "handscan/xsens/xsens_json.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "handscan/core/json.hpp"
#include "handscan/xsens/xbus_messages.hpp"

namespace handscan::xsens {
namespace {

void number(std::ostream& out, double v) {
    if (!std::isfinite(v)) {
        out << "null";  // JSON has no NaN / Inf
        return;
    }
    if (v == std::floor(v) && std::abs(v) < 9.0e15) {
        out << static_cast<long long>(v);
        return;
    }
    // The shortest text that reads back as the same double.
    char buf[32];
    for (int digits = 15; digits <= 17; ++digits) {
        std::snprintf(buf, sizeof buf, "%.*g", digits, v);
        if (std::strtod(buf, nullptr) == v) break;
    }
    out << buf;
}

void hex(std::ostream& out, std::span<const std::uint8_t> bytes) {
    static constexpr char kDigits[] = "0123456789abcdef";
    out << '"';
    for (std::uint8_t b : bytes) out << kDigits[b >> 4] << kDigits[b & 15];
    out << '"';
}

void quoted(std::ostream& out, std::string_view s) { out << jsonString(s); }

// Integer fields: the SI value, the key carrying its unit when it has one ("height_m").
void intFields(std::ostream& out, const std::vector<XdiField>& fields, int element, bool& first) {
    for (const auto& f : fields) {
        if (f.element != element) continue;
        out << (first ? "" : ",");
        first = false;
        std::string key(f.name);
        if (!f.si_unit.empty()) {
            key += '_';
            key += f.si_unit == "m/s" ? "mps" : std::string(f.si_unit);
        }
        quoted(out, key);
        out << ':';
        number(out, f.value * f.si_scale);
    }
}

std::string utcIso(const std::vector<XdiField>& f) {
    // ns, year, month, day, hour, minute, second, flags (see xdi.cpp); all unsigned, ns < 2^32.
    auto n = [&](std::size_t i) { return static_cast<long long>(f[i].value); };
    char buf[96];
    std::snprintf(buf, sizeof buf, "%04lld-%02lld-%02lldT%02lld:%02lld:%02lld.%09lldZ", n(1), n(2),
                  n(3), n(4), n(5), n(6), n(0));
    return buf;
}

}  // namespace

void writeItemJson(const MtData2Value& v, std::ostream& out) {
    if (!v.decoded()) {
        out << "{\"xdi\":";
        char buf[8];
        std::snprintf(buf, sizeof buf, "0x%04X", v.xdi);
        quoted(out, buf);
        out << ",\"raw\":";
        hex(out, v.raw);
        out << ",\"problem\":";
        quoted(out, v.problem);
        out << '}';
        return;
    }
    const XdiInfo& info = *v.info;
    if (info.layout == XdiLayout::kReals) {
        out << '{';
        for (const auto& f : v.fields) {
            quoted(out, f.name);
            out << ':';
            number(out, f.value * f.si_scale);
            out << ',';
        }
        out << "\"unit\":";
        quoted(out, info.si_unit);
        out << ",\"format\":";
        quoted(out, precisionName(v.precision()));
        if (info.has_coord_sys) {
            out << ",\"coords\":";
            quoted(out, coordSysName(v.coordSys()));
        }
        out << '}';
        return;
    }
    // A plain counter or flag word: just the number; a single value with a unit: both.
    if (v.fields.size() == 1) {
        const XdiField& f = v.fields[0];
        if (f.si_unit.empty()) {
            number(out, f.value);
            return;
        }
        out << "{\"raw\":";
        number(out, f.value);
        out << ',';
        quoted(out, f.si_unit);
        out << ':';
        number(out, f.value * f.si_scale);
        out << '}';
        return;
    }
    out << '{';
    bool first = true;
    intFields(out, v.fields, -1, first);
    if (info.type == xdi::kUtcTime) {
        out << ",\"iso\":";
        quoted(out, utcIso(v.fields));
    }
    if (info.layout == XdiLayout::kStructRepeated) {
        out << (first ? "" : ",") << "\"elements\":[";
        for (int e = 0;; ++e) {
            bool any = false;
            for (const auto& f : v.fields) any |= f.element == e;
            if (!any) break;
            out << (e == 0 ? "{" : ",{");
            bool efirst = true;
            intFields(out, v.fields, e, efirst);
            out << '}';
        }
        out << ']';
    }
    out << '}';
}

void XsensJsonDecoder::feed(TimeNs t_host, std::span<const std::uint8_t> bytes,
                            std::ostream& jsonl) {
    parser_.feed(bytes);
    while (auto f = parser_.next()) writeFrame(t_host, *f, jsonl);
}

XsensJsonSummary XsensJsonDecoder::summary() const {
    XsensJsonSummary s = summary_;
    s.checksum_failures = parser_.stats().checksum_failures;
    s.resyncs = parser_.stats().resyncs;
    return s;
}

void XsensJsonDecoder::writeFrame(TimeNs t_host, const XbusFrameView& frame, std::ostream& out) {
    ++summary_.messages;
    out << "{\"t_host_ns\":" << t_host << ",\"message\":";
    quoted(out, messageName(frame.mid));
    switch (static_cast<MessageId>(frame.mid)) {
        case MessageId::kMtData2: {
            auto packet = decodeMtData2(frame.payload);
            if (!packet) {
                out << ",\"error\":";
                quoted(out, packet.status().message());
                out << ",\"payload\":";
                hex(out, frame.payload);
                break;
            }
            writeMtData2(*packet, out);
            break;
        }
        case MessageId::kError: {
            auto e = decodeError(frame.payload);
            if (e) {
                out << ",\"code\":" << int{e->code} << ",\"error\":";
                quoted(out, errorText(e->code));
            }
            break;
        }
        case MessageId::kDeviceId: {
            if (auto id = decodeDeviceId(frame.payload)) {
                char buf[12];
                std::snprintf(buf, sizeof buf, "%08X", *id);
                out << ",\"device_id\":";
                quoted(out, buf);
            }
            break;
        }
        case MessageId::kProductCode:
            out << ",\"product_code\":";
            quoted(out, decodeProductCode(frame.payload));
            break;
        case MessageId::kSetOutputConfiguration:
        case MessageId::kSetOutputConfigurationAck: {
            if (auto entries = decodeOutputConfiguration(frame.payload)) {
                out << ",\"outputs\":[";
                for (std::size_t i = 0; i < entries->size(); ++i) {
                    const auto& e = (*entries)[i];
                    const XdiInfo* info = findXdi(e.xdi);
                    char buf[8];
                    std::snprintf(buf, sizeof buf, "0x%04X", e.xdi);
                    out << (i == 0 ? "{" : ",{") << "\"name\":";
                    quoted(out, info != nullptr ? info->name : std::string_view("Unknown"));
                    out << ",\"xdi\":";
                    quoted(out, buf);
                    out << ",\"rate_hz\":";
                    if (e.rate_hz == kEveryPacket) {
                        out << "\"every packet\"";
                    } else {
                        out << e.rate_hz;
                    }
                    out << '}';
                }
                out << ']';
            }
            break;
        }
        default:
            if (!frame.payload.empty()) {
                out << ",\"payload\":";
                hex(out, frame.payload);
            }
            break;
    }
    out << "}\n";
}

void XsensJsonDecoder::writeMtData2(const MtData2Packet& packet, std::ostream& out) {
    if (auto stf = packet.integer(xdi::kSampleTimeFine)) {
        const auto raw = static_cast<std::uint32_t>(*stf);
        // Unwrap the 32-bit 10 kHz counter (wraps every 4.97 days).
        stf_unwrapped_ =
            last_stf_ ? stf_unwrapped_ + static_cast<std::int32_t>(raw - *last_stf_) : raw;
        last_stf_ = raw;
        out << ",\"t_device_s\":";
        number(out, static_cast<double>(stf_unwrapped_) * 1e-4);
    }
    if (auto pc = packet.integer(xdi::kPacketCounter)) {
        if (const std::uint16_t missing = counter_.missingBefore(static_cast<std::uint16_t>(*pc));
            missing != 0) {
            ++summary_.gaps;
            summary_.lost_packets += missing;
            out << ",\"gap\":" << missing;
        }
    }
    for (const auto& v : packet.values) {
        out << ',';
        if (v.info != nullptr) {
            quoted(out, v.name());
        } else {
            char buf[24];
            std::snprintf(buf, sizeof buf, "Unknown_0x%04X", v.xdi);
            quoted(out, buf);
        }
        out << ':';
        writeItemJson(v, out);
    }
}

}  // namespace handscan::xsens
