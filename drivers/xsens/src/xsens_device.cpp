#include "handscan/xsens/xsens_device.hpp"

#include <algorithm>
#include <array>
#include <cstdio>

#include "handscan/core/log.hpp"

namespace handscan::xsens {
namespace {

constexpr std::size_t kMaxProblems = 32;
constexpr std::size_t kReadChunk = 4096;

}  // namespace

XsensDevice::XsensDevice(transport::ByteStream& stream, XsensDeviceConfig config, RawTap* tap)
    : stream_(stream),
      cfg_(std::move(config)),
      tap_(tap),
      decoder_("Xsens " + stream.describe()),
      rx_(kReadChunk),
      link_baud_(cfg_.baudrate) {
    decoder_.onProblem([this](const std::string& p) { note(p); });
}

std::vector<OutputConfigEntry> XsensDevice::outputConfigurationFor(
    const XsensDeviceConfig& config) {
    const std::uint16_t hz = config.output_rate_hz;
    std::vector<OutputConfigEntry> entries{
        {xdi::kPacketCounter, kEveryPacket},
        {xdi::kSampleTimeFine, kEveryPacket},
        {withFormat(xdi::kAcceleration, config.precision), hz},
        {withFormat(xdi::kRateOfTurn, config.precision), hz},
    };
    if (config.delta_q_delta_v) {
        entries.push_back({withFormat(xdi::kDeltaQ, config.precision), hz});
        entries.push_back({withFormat(xdi::kDeltaV, config.precision), hz});
    }
    entries.push_back({xdi::kStatusWord, kEveryPacket});
    return entries;
}

const XsensDeviceStats& XsensDevice::stats() const {
    static_cast<ImuStreamStats&>(stats_) = decoder_.stats();
    stats_.device_errors += refused_requests_;
    return stats_;
}

void XsensDevice::note(std::string problem) {
    log().warn("{}", problem);
    if (problems_.size() >= kMaxProblems) problems_.erase(problems_.begin());
    problems_.push_back(std::move(problem));
}

Status XsensDevice::readSome(TimeNs timeout, TimeNs& t_rx) {
    auto n = stream_.read(rx_, std::max<TimeNs>(timeout, 0));
    if (!n.isOk()) return n.status();
    t_rx = cfg_.clock();
    if (*n == 0) return Status::ok();
    last_rx_ = t_rx;
    const std::span<const std::uint8_t> chunk(rx_.data(), *n);
    if (tap_ != nullptr) tap_->onRaw(t_rx, chunk);
    stats_.bytes += *n;
    decoder_.feedRaw(chunk);
    return Status::ok();
}

Result<XsensDevice::Reply> XsensDevice::request(MessageId mid,
                                                std::span<const std::uint8_t> payload,
                                                const char* step) {
    const std::vector<std::uint8_t> frame = encodeFrame(mid, payload);
    const MessageId ack = ackOf(mid);
    std::string last_error;
    for (int attempt = 1; attempt <= cfg_.attempts; ++attempt) {
        if (Status s = stream_.writeAll(frame, cfg_.reply_timeout); !s) {
            return Status{s.code(), "Xsens " + std::string(step) + ": sending " +
                                        messageName(toByte(mid)) + " over " + stream_.describe() +
                                        " failed: " + s.message()};
        }
        const TimeNs deadline = cfg_.clock() + cfg_.reply_timeout;
        bool resend = false;
        for (TimeNs now = cfg_.clock(); now < deadline && !resend;) {
            if (Status s = readSome(deadline - now, now); !s) {
                return Status{s.code(), "Xsens " + std::string(step) + ": " + stream_.describe() +
                                            ": " + s.message()};
            }
            while (auto f = decoder_.nextFrame()) {
                if (f->mid == toByte(ack))
                    return Reply{f->mid, {f->payload.begin(), f->payload.end()}};
                if (f->mid == toByte(MessageId::kError)) {
                    ++refused_requests_;
                    auto e = decodeError(f->payload);
                    last_error = e.isOk() ? errorText(e->code) : e.status().message();
                    note("Xsens " + std::string(step) + ": device answered " +
                         messageName(toByte(mid)) + " with Error " + last_error + " (attempt " +
                         std::to_string(attempt) + " of " + std::to_string(cfg_.attempts) + ")");
                    resend = true;
                    break;
                }
                if (f->mid == toByte(MessageId::kWakeUp)) {
                    // The device (re)booted: acknowledging keeps it in config mode, which is
                    // where we are taking it anyway.
                    const auto wake_ack = encodeFrame(MessageId::kWakeUpAck);
                    if (Status s = stream_.writeAll(wake_ack, cfg_.reply_timeout); !s) return s;
                    note("Xsens " + std::string(step) + ": " + stream_.describe() +
                         " announced itself (WakeUp)");
                    continue;
                }
                // Anything else is left over from before the request (MTData2 while the device
                // still streams, late acks): skip it.
            }
        }
    }
    if (!last_error.empty()) {
        return Status{StatusCode::kDeviceError,
                      "Xsens " + std::string(step) + ": " + stream_.describe() + " refused " +
                          messageName(toByte(mid)) + " " + std::to_string(cfg_.attempts) +
                          " times; last error: " + last_error};
    }
    return Status{
        StatusCode::kTimeout,
        "Xsens " + std::string(step) + ": no " + messageName(toByte(ack)) + " from " +
            stream_.describe() + " after " + std::to_string(cfg_.attempts) + " attempts of " +
            std::to_string(cfg_.reply_timeout / kNsPerMs) +
            " ms; check power, cable, port and baud rate (MTi default 115200, configured 921600?)"};
}

Status XsensDevice::enterConfigMode() {
    // The device may be streaming since power-up: GoToConfig is resent until acked.
    auto r = request(MessageId::kGoToConfig, {}, "entering config mode");
    if (r || r.status().code() != StatusCode::kTimeout || !cfg_.set_link_baudrate)
        return r.status();
    // Silence at this rate: the device may talk at another one (factory default 115200).
    const int tried = link_baud_;
    const int saved_attempts = cfg_.attempts;
    cfg_.attempts = 2;
    Status found = r.status();
    for (int baud : {115200, 921600, 460800, 230400, 57600, 38400, 19200, 9600}) {
        if (baud == tried) continue;
        if (Status s = cfg_.set_link_baudrate(baud); !s) {
            found = s;
            break;
        }
        link_baud_ = baud;
        decoder_.resetLink();
        auto probe = request(MessageId::kGoToConfig, {}, "probing the baud rate");
        if (probe) {
            note("Xsens " + stream_.describe() + ": device found at " + std::to_string(baud) +
                 " baud, not " + std::to_string(tried));
            found = Status::ok();
            break;
        }
    }
    cfg_.attempts = saved_attempts;
    if (!found && cfg_.set_link_baudrate(tried)) link_baud_ = tried;
    if (!found) {
        return Status{StatusCode::kTimeout,
                      "Xsens entering config mode: no answer from " + stream_.describe() +
                          " at any Xbus baud rate (9600 ... 921600); check power, cable and "
                          "port (" +
                          r.status().message() + ")"};
    }
    return found;
}

Status XsensDevice::switchBaudrate(int baud) {
    const auto id = baudrateId(baud);
    if (!id) {
        return {StatusCode::kInvalidArgument,
                "Xsens: " + std::to_string(baud) +
                    " baud is not an Xbus rate; use 921600, 460800, 230400 or 115200"};
    }
    if (!cfg_.set_link_baudrate) {
        return {StatusCode::kUnsupported,
                "Xsens: " + stream_.describe() + " has no line rate to change"};
    }
    const std::uint8_t payload = *id;
    if (auto r = request(MessageId::kSetBaudrate, std::span(&payload, 1), "setting the baud rate");
        !r) {
        return r.status();
    }
    // The new rate takes effect when the device restarts; the ResetAck still comes at the old one.
    if (auto r = request(MessageId::kReset, {}, "resetting to apply the baud rate"); !r)
        return r.status();
    if (Status s = cfg_.set_link_baudrate(baud); !s) return s;
    link_baud_ = baud;
    decoder_.resetLink();
    // It reboots (WakeUp, which request() acknowledges) and must be caught in config mode again.
    if (auto r = request(MessageId::kGoToConfig, {}, "entering config mode after the baud change");
        !r) {
        return r.status();
    }
    log().info("Xsens {} now at {} baud", stream_.describe(), baud);
    return Status::ok();
}

Status XsensDevice::configure() {
    measuring_ = false;
    if (!stream_.isOpen()) {
        if (Status s = stream_.open(); !s) return s;
    }
    decoder_.resetLink();
    decoder_.setSource("Xsens " + stream_.describe());
    // 1. Config mode, at the right line rate.
    if (Status s = enterConfigMode(); !s) return s;
    if (cfg_.set_link_baudrate && link_baud_ != cfg_.baudrate) {
        if (Status s = switchBaudrate(cfg_.baudrate); !s) return s;
    }
    // 2. Identity.
    auto did = request(MessageId::kReqDid, {}, "reading the device id");
    if (!did) return did.status();
    auto id = decodeDeviceId(did->payload);
    if (!id) return id.status();
    device_id_ = *id;
    auto pc = request(MessageId::kReqProductCode, {}, "reading the product code");
    if (!pc) return pc.status();
    product_code_ = decodeProductCode(pc->payload);
    // 3. Outputs. The ack echoes the configuration the device actually took.
    const auto wanted = outputConfigurationFor(cfg_);
    auto oc = request(MessageId::kSetOutputConfiguration, encodeOutputConfiguration(wanted),
                      "setting the outputs");
    if (!oc) return oc.status();
    auto echoed = decodeOutputConfiguration(oc->payload);
    if (!echoed) return echoed.status();
    for (const auto& w : wanted) {
        if (std::find(echoed->begin(), echoed->end(), w) == echoed->end()) {
            char buf[96];
            std::snprintf(buf, sizeof buf, "XDI 0x%04X at %u Hz", w.xdi, w.rate_hz);
            return Status{StatusCode::kDeviceError, "Xsens setting the outputs: " + product_code_ +
                                                        " on " + stream_.describe() +
                                                        " did not take " + buf +
                                                        "; is it an MTi model with that output?"};
        }
    }
    output_config_ = *echoed;
    // 4. Measurement.
    if (auto r = request(MessageId::kGoToMeasurement, {}, "starting measurement"); !r)
        return r.status();
    measuring_ = true;
    decoder_.forgetCounter();
    decoder_.setSource("Xsens " + stream_.describe());
    log().info("Xsens {} (id {:08X}) on {} streaming at {} Hz", product_code_, device_id_,
               stream_.describe(), cfg_.output_rate_hz);
    return Status::ok();
}

Status XsensDevice::poll(std::vector<ImuSample>& out, TimeNs timeout) {
    // The line rate may have changed since the last call (probing, switchBaudrate).
    decoder_.setTiming({cfg_.frame_latency, cfg_.set_link_baudrate ? link_baud_ : 0});
    // Frames that arrived with the last reply of configure() are stamped with their own receive
    // time, not with the next read's.
    decoder_.decodePending(last_rx_, out);
    TimeNs t_rx = 0;
    if (Status s = readSome(timeout, t_rx); !s) {
        measuring_ = false;
        return Status{s.code(), "Xsens " + stream_.describe() + ": " + s.message() +
                                    "; reconnect with configure()"};
    }
    decoder_.decodePending(last_rx_, out);
    return Status::ok();
}

}  // namespace handscan::xsens
