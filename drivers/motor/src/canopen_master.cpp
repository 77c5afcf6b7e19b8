#include "handscan/motor/canopen_master.hpp"

#include <cstdio>
#include <optional>

#include "handscan/motor/candump_format.hpp"

namespace handscan::motor {
namespace {
std::string objectName(std::uint8_t node, std::uint16_t index, std::uint8_t sub) {
    char buf[48];
    std::snprintf(buf, sizeof buf, "node %u object %04Xh:%02X", static_cast<unsigned>(node), index,
                  static_cast<unsigned>(sub));
    return buf;
}
}  // namespace

CanOpenMaster::CanOpenMaster(transport::CanBus& bus, Clock clock, RawTap* tap,
                             std::string interface_name)
    : bus_(bus), clock_(std::move(clock)), tap_(tap), interface_(std::move(interface_name)) {}

void CanOpenMaster::tap(TimeNs t, const CanFrame& frame) {
    if (tap_ == nullptr) return;
    CandumpRecord rec;
    rec.setTimeNs(t);
    rec.interface = interface_;
    rec.frame = frame;
    const std::string line = formatCandumpLogLine(rec);
    tap_->onRaw(t, {reinterpret_cast<const std::uint8_t*>(line.data()), line.size()});
}

Status CanOpenMaster::send(const CanFrame& frame) {
    tap(clock_(), frame);
    return bus_.send(frame);
}

Result<TimedCanFrame> CanOpenMaster::receive(TimeNs timeout) {
    auto r = bus_.receive(timeout);
    if (r) tap(r->t_host, r->frame);
    return r;
}

Status CanOpenMaster::pumpUntil(const std::function<bool()>& done, TimeNs timeout,
                                const std::string& what) {
    const TimeNs deadline = clock_() + timeout;
    while (!done()) {
        const TimeNs left = deadline - clock_();
        if (left <= 0) {
            return {StatusCode::kTimeout, what + ": no answer within " +
                                              std::to_string(timeout / kNsPerMs) + " ms on " +
                                              bus_.describe()};
        }
        auto r = receive(left);
        if (!r) {
            if (r.status().code() == StatusCode::kTimeout) continue;
            return r.status();
        }
        if (handler_) handler_(*r);
    }
    return Status::ok();
}

Result<SdoMessage> CanOpenMaster::sdoTransfer(const CanFrame& request, SdoKind expect,
                                              TimeNs timeout, int retries) {
    auto req = decodeSdo(request);
    if (!req) return req.status();
    const std::string name = objectName(req->node, req->index, req->subindex);
    const char* verb = expect == SdoKind::kDownloadResponse ? "SDO write" : "SDO read";
    Status last;
    for (int attempt = 0; attempt <= retries; ++attempt) {
        if (Status s = send(request); !s) return s;
        std::optional<SdoMessage> answer;
        const FrameHandler owner = handler_;
        // Intercept the matching server response; everything else goes to the owner.
        auto intercept = [&](const TimedCanFrame& tf) {
            const CobIdInfo info = classifyCobId(tf.frame);
            if (info.function == CanOpenFunction::kSdoResponse && info.node == req->node) {
                auto m = decodeSdo(tf.frame);
                if (m && m->index == req->index && m->subindex == req->subindex &&
                    (m->kind == expect || m->kind == SdoKind::kAbort ||
                     m->kind == SdoKind::kSegmented)) {
                    answer = *m;
                    return;
                }
            }
            if (owner) owner(tf);
        };
        handler_ = intercept;
        last =
            pumpUntil([&] { return answer.has_value(); }, timeout, std::string(verb) + " " + name);
        handler_ = owner;
        if (answer) {
            if (answer->kind == SdoKind::kAbort) {
                char code[16];
                std::snprintf(code, sizeof code, "0x%08X", static_cast<unsigned>(answer->value));
                return Status(StatusCode::kDeviceError,
                              std::string(verb) + " " + name + " aborted by the device: " + code +
                                  " (" + sdoAbortText(answer->value) + ")");
            }
            if (answer->kind == SdoKind::kSegmented) {
                return Status(StatusCode::kUnsupported,
                              std::string(verb) + " " + name +
                                  ": device answered with a segmented transfer, which this driver "
                                  "does not carry");
            }
            return *answer;
        }
        if (last.code() != StatusCode::kTimeout) return last;
    }
    return Status(StatusCode::kTimeout,
                  last.message() + " (after " + std::to_string(retries + 1) +
                      " attempts; check node id, bitrate and that the node is powered)");
}

Status CanOpenMaster::sdoWrite(std::uint8_t node, std::uint16_t index, std::uint8_t sub,
                               std::uint32_t value, std::uint8_t size, TimeNs timeout,
                               int retries) {
    auto r = sdoTransfer(encodeSdoWrite(node, index, sub, value, size), SdoKind::kDownloadResponse,
                         timeout, retries);
    return r ? Status::ok() : r.status();
}

Result<std::uint32_t> CanOpenMaster::sdoRead(std::uint8_t node, std::uint16_t index,
                                             std::uint8_t sub, TimeNs timeout, int retries) {
    auto r =
        sdoTransfer(encodeSdoRead(node, index, sub), SdoKind::kUploadResponse, timeout, retries);
    if (!r) return r.status();
    return r->value;
}

}  // namespace handscan::motor
