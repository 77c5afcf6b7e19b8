// `handscan decode --device can FILE|REC.mcap`: candump lines (-l/-L log, or the default screen
// format) or the /motor/can channel of a recording, as one JSON line per CAN frame with its
// CANopen meaning (NMT, SYNC, EMCY, SDO, heartbeat, PDOs: 4-byte TPDO1 as the CiA 406 position,
// 2-byte TPDO1 as the CiA 402 statusword). Summary: resyncs = lines that did not parse (skipped),
// gaps = TPDO intervals longer than 2.5x the shortest interval seen on that COB-ID.
#include <cstdio>
#include <map>
#include <sstream>

#include "decoder_registry.hpp"
#include "handscan/core/json.hpp"
#include "handscan/motor/candump_format.hpp"
#include "handscan/motor/canopen.hpp"

namespace handscan::cli {
namespace {

using namespace motor;

std::string hex(unsigned v, int digits) {
    char b[16];
    std::snprintf(b, sizeof b, "%0*X", digits, v);
    return b;
}

void canopenFields(const CanFrame& f, std::ostream& o) {
    const CobIdInfo info = classifyCobId(f);
    o << ",\"canopen\":{\"function\":\"" << toString(info.function) << "\"";
    if (info.node != 0) o << ",\"node\":" << static_cast<unsigned>(info.node);
    switch (info.function) {
        case CanOpenFunction::kNmt:
            if (auto m = decodeNmt(f)) {
                o << ",\"command\":\"" << toString(m->command)
                  << "\",\"target_node\":" << static_cast<unsigned>(m->node);
            } else {
                o << ",\"error\":" << jsonString(m.status().message());
            }
            break;
        case CanOpenFunction::kSync:
            if (auto s = decodeSync(f); s && s->has_value())
                o << ",\"counter\":" << static_cast<unsigned>(**s);
            break;
        case CanOpenFunction::kHeartbeat:
            if (auto h = decodeHeartbeat(f)) {
                o << ",\"state\":\"" << toString(h->state) << "\"";
            } else {
                o << ",\"error\":" << jsonString(h.status().message());
            }
            break;
        case CanOpenFunction::kEmcy:
            if (auto e = decodeEmergency(f)) {
                o << ",\"error_code\":\"0x" << hex(e->error_code, 4) << "\",\"error_register\":\"0x"
                  << hex(e->error_register, 2) << "\"";
            } else {
                o << ",\"error\":" << jsonString(e.status().message());
            }
            break;
        case CanOpenFunction::kSdoRequest:
        case CanOpenFunction::kSdoResponse:
            if (auto s = decodeSdo(f)) {
                o << ",\"sdo\":\"" << toString(s->kind) << "\",\"index\":\"" << hex(s->index, 4)
                  << "\",\"subindex\":" << static_cast<unsigned>(s->subindex);
                if (s->kind == SdoKind::kAbort) {
                    o << ",\"abort_code\":\"0x" << hex(s->value, 8)
                      << "\",\"abort_text\":" << jsonString(sdoAbortText(s->value));
                } else if (s->kind == SdoKind::kDownloadRequest ||
                           s->kind == SdoKind::kUploadResponse) {
                    o << ",\"value\":" << s->value
                      << ",\"size\":" << static_cast<unsigned>(s->size);
                }
            } else {
                o << ",\"error\":" << jsonString(s.status().message());
            }
            break;
        case CanOpenFunction::kTpdo:
        case CanOpenFunction::kRpdo:
            o << ",\"pdo\":" << info.pdo;
            if (info.function == CanOpenFunction::kTpdo && info.pdo == 1 && f.len == 4) {
                if (auto p = decodeEncoderPositionTpdo(f)) o << ",\"position\":" << *p;
            } else if (info.function == CanOpenFunction::kTpdo && info.pdo == 1 && f.len == 2) {
                const auto sw = static_cast<std::uint16_t>(f.data[0] | (f.data[1] << 8));
                o << ",\"statusword\":\"0x" << hex(sw, 4) << "\",\"cia402_state\":\""
                  << toString(cia402StateFromStatusword(sw)) << "\"";
            }
            break;
        default:
            break;
    }
    o << "}";
}

class CanDecoder final : public StreamDecoder {
public:
    void feed(TimeNs t_host, std::span<const std::uint8_t> bytes, std::ostream& out) override {
        pending_.append(reinterpret_cast<const char*>(bytes.data()), bytes.size());
        std::size_t start = 0;
        for (std::size_t nl; (nl = pending_.find('\n', start)) != std::string::npos;
             start = nl + 1) {
            line(t_host, pending_.substr(start, nl - start), out);
        }
        pending_.erase(0, start);
        // A recorded message is one whole line without its newline.
        if (t_host != 0 && !pending_.empty()) {
            line(t_host, pending_, out);
            pending_.clear();
        }
    }

    DecodeSummary finish(std::ostream& out) override {
        if (!pending_.empty()) line(0, pending_, out);
        pending_.clear();
        return summary_;
    }

private:
    void line(TimeNs t_host, std::string text, std::ostream& out) {
        ++line_no_;
        while (!text.empty() && (text.back() == '\r' || text.back() == ' ')) text.pop_back();
        if (text.find_first_not_of(" \t") == std::string::npos) return;
        auto rec = parseCandumpAnyLine(text);
        if (!rec) {
            ++summary_.resyncs;
            out << "{\"line\":" << line_no_ << ",\"error\":" << jsonString(rec.status().message())
                << "}\n";
            return;
        }
        ++summary_.messages;
        const CanFrame& f = rec->frame;
        std::ostringstream o;
        o << "{\"t_host_ns\":";
        if (t_host != 0) {
            o << t_host;
        } else {
            o << "null";
        }
        o << ",\"t_log_ns\":";
        if (rec->has_time) {
            o << rec->timeNs();
        } else {
            o << "null";
        }
        o << ",\"interface\":" << jsonString(rec->interface) << ",\"id\":\""
          << hex(f.id, f.extended || f.error ? 8 : 3) << "\""
          << ",\"extended\":" << (f.extended ? "true" : "false")
          << ",\"remote\":" << (f.remote ? "true" : "false")
          << ",\"error_frame\":" << (f.error ? "true" : "false")
          << ",\"fd\":" << (f.fd ? "true" : "false") << ",\"len\":" << static_cast<unsigned>(f.len)
          << ",\"data\":\"";
        for (std::uint8_t b : f.payload()) o << hex(b, 2);
        o << "\"";
        if (!f.error && !f.extended) canopenFields(f, o);
        o << "}\n";
        out << o.str();
        countGap(rec->has_time ? rec->timeNs() : t_host, f);
    }

    void countGap(TimeNs t, const CanFrame& f) {
        if (t == 0 || classifyCobId(f).function != CanOpenFunction::kTpdo) return;
        auto& s = tpdo_[f.id];
        if (s.last != 0) {
            const TimeNs dt = t - s.last;
            if (dt > 0 && (s.min == 0 || dt < s.min)) s.min = dt;
            if (s.min > 0 && dt * 2 > s.min * 5) ++summary_.gaps;
        }
        s.last = t;
    }

    struct TpdoTiming {
        TimeNs last = 0;
        TimeNs min = 0;
    };
    std::string pending_;
    std::uint64_t line_no_ = 0;
    DecodeSummary summary_;
    std::map<std::uint32_t, TpdoTiming> tpdo_;
};

const RegisterDecoder kCan{"can", "/motor/can", [] { return std::make_unique<CanDecoder>(); }};

}  // namespace
}  // namespace handscan::cli
