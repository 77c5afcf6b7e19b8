#include "handscan/hokuyo/hokuyo_device.hpp"

#include <algorithm>
#include <cmath>
#include <thread>

#include "handscan/core/log.hpp"

namespace handscan::hokuyo {

namespace {

std::span<const std::uint8_t> bytesOf(const std::string& s) {
    return {reinterpret_cast<const std::uint8_t*>(s.data()), s.size()};
}

std::string withoutLf(std::string s) {
    while (!s.empty() && (s.back() == '\n' || s.back() == '\r')) s.pop_back();
    return s;
}

}  // namespace

HokuyoDeviceConfig hokuyoDeviceConfig(const HokuyoConfig& config) {
    HokuyoDeviceConfig c;
    c.reply_timeout_ns = std::max<TimeNs>(fromSeconds(config.connect_timeout_s), 100 * kNsPerMs);
    c.backoff_max_ns = std::max(fromSeconds(config.reconnect_max_backoff_s), c.backoff_initial_ns);
    return c;
}

HokuyoDevice::HokuyoDevice(transport::ByteStream& link, HokuyoDeviceConfig config, RawTap* tap,
                           Clock now, Sleep sleep)
    : link_(link),
      cfg_(config),
      tap_(tap),
      now_(std::move(now)),
      sleep_(sleep ? std::move(sleep) : Sleep([](TimeNs ns) {
          std::this_thread::sleep_for(std::chrono::nanoseconds(ns));
      })),
      decoder_(config.timing),
      rx_(16384),
      backoff_(config.backoff_initial_ns) {}

HokuyoDeviceStats HokuyoDevice::stats() const {
    HokuyoDeviceStats s = stats_;
    const ScanStreamStats d = decoder_.stats();
    s.scans = d.scans;
    s.missed_scans = d.missed_scans;
    s.parser = d.parser;
    return s;
}

Status HokuyoDevice::fault(Status status) {
    ++stats_.faults;
    last_fault_ = status.message();
    log().warn("hokuyo {}: {}", link_.describe(), status.message());
    return status;
}

void HokuyoDevice::dropLink(const Status& why) {
    link_.close();
    decoder_.resetLink();
    pending_.clear();
    if (state_ == State::kStreaming) ++stats_.disconnects;
    state_ = State::kDisconnected;
    // A link that streamed before starts over at the short back-off; failures in a row double it.
    if (scanned_since_connect_) backoff_ = cfg_.backoff_initial_ns;
    next_attempt_ = now_() + backoff_;
    log().info("hokuyo {}: reconnecting in {:.2f} s ({})", link_.describe(), toSeconds(backoff_),
               why.message());
    backoff_ = std::min(backoff_ * 2, cfg_.backoff_max_ns);
    scanned_since_connect_ = false;
}

Result<std::size_t> HokuyoDevice::readChunk(TimeNs timeout) {
    auto n = link_.read(rx_, timeout);
    if (!n) return n;
    if (*n > 0) {
        last_rx_ = now_();
        const std::span<const std::uint8_t> chunk(rx_.data(), *n);
        if (tap_ != nullptr) tap_->onRaw(last_rx_, chunk);
        scratch_.clear();
        const std::size_t scans_before = ready_.size();
        decoder_.feed(last_rx_, chunk, ready_, scratch_);
        for (auto& e : scratch_) pending_.push_back(std::move(e));
        if (ready_.size() > scans_before) {
            last_scan_rx_ = last_rx_;
            scanned_since_connect_ = true;
        }
    }
    return n;
}

Result<ScipFrame> HokuyoDevice::transact(const std::string& command) {
    const std::string echo = withoutLf(command);
    if (Status s = link_.writeAll(bytesOf(command), cfg_.reply_timeout_ns); !s) return s;
    const TimeNs deadline = now_() + cfg_.reply_timeout_ns;
    for (;;) {
        while (!pending_.empty()) {
            ScipEvent e = std::move(pending_.front());
            pending_.pop_front();
            if (auto* f = std::get_if<ScipFrame>(&e); f != nullptr && f->echo == echo) {
                return std::move(*f);
            }
            // Leftovers of an earlier stream or garbage: counted by the parser, otherwise ignored.
        }
        const TimeNs left = deadline - now_();
        if (left <= 0) {
            return Status(StatusCode::kTimeout,
                          "hokuyo " + link_.describe() + ": no reply to " + echo + " within " +
                              std::to_string(toSeconds(cfg_.reply_timeout_ns)) +
                              " s; is it a SCIP 2.0 sensor?");
        }
        auto n = readChunk(std::min(left, cfg_.read_slice_ns));
        if (!n) return n.status();
    }
}

Status HokuyoDevice::handshake() {
    auto need_ok = [&](const Result<ScipFrame>& r) -> Status {
        if (!r) return r.status();
        if (!r->ok()) {
            return Status(StatusCode::kDeviceError,
                          "hokuyo " + link_.describe() + ": " + r->statusText());
        }
        return Status::ok();
    };
    auto scip = transact(encodeScip20Command());
    if (Status s = need_ok(scip); !s) return s;
    auto vv = transact(encodeVersionCommand());
    if (Status s = need_ok(vv); !s) return s;
    identity_.vendor = vv->item("VEND").value_or("");
    identity_.product = vv->item("PROD").value_or("");
    identity_.firmware = vv->item("FIRM").value_or("");
    identity_.protocol = vv->item("PROT").value_or("");
    identity_.serial = vv->item("SERI").value_or("");
    auto pp = transact(encodeParametersCommand());
    if (Status s = need_ok(pp); !s) return s;
    auto params = SensorParameters::fromPpReply(*pp);
    if (!params) {
        return Status(params.status().code(),
                      "hokuyo " + link_.describe() + ": " + params.status().message());
    }
    params_ = *params;
    auto ii = transact(encodeStatusInfoCommand());
    if (Status s = need_ok(ii); !s) return s;
    identity_.status = ii->item("STAT").value_or("");
    auto bm = transact(encodeLaserOnCommand());
    if (Status s = need_ok(bm); !s) return s;

    request_ = ScanRequest{};
    request_.mode = 'M';
    request_.encoding = ScanEncoding::kThreeCharWithIntensity;
    request_.start_step =
        cfg_.start_step >= 0 ? std::max(cfg_.start_step, params_->amin) : params_->amin;
    request_.end_step = cfg_.end_step >= 0 ? std::min(cfg_.end_step, params_->amax) : params_->amax;
    request_.cluster = std::max(cfg_.cluster, 1);
    request_.interval = 0;
    request_.count = 0;  // unlimited
    auto me = transact(encodeScanCommand(request_));
    if (Status s = need_ok(me); !s) return s;
    log().info("hokuyo {}: {} {} serial {} firmware {}, {} steps {}..{} at {} rpm, streaming ME",
               link_.describe(), identity_.vendor, params_->model, identity_.serial,
               identity_.firmware, request_.valuesPerScan(), request_.start_step, request_.end_step,
               params_->scan_rpm);
    return Status::ok();
}

Status HokuyoDevice::connect() {
    decoder_.resetLink();
    pending_.clear();
    Status s = link_.open();
    if (s) s = handshake();
    if (!s) {
        ++stats_.connect_failures;
        Status reported = fault(s);
        dropLink(reported);
        return reported;
    }
    ++stats_.connects;
    state_ = State::kStreaming;
    last_scan_rx_ = now_();
    return Status::ok();
}

Status HokuyoDevice::handleEvents(std::vector<LaserScan>& out) {
    // The scans the decoder completed, in stream order with the replies below.
    out.insert(out.end(), std::make_move_iterator(ready_.begin()),
               std::make_move_iterator(ready_.end()));
    ready_.clear();
    Status result = Status::ok();
    while (!pending_.empty()) {
        ScipEvent e = std::move(pending_.front());
        pending_.pop_front();
        if (auto* f = std::get_if<ScipFault>(&e)) {
            result = fault(Status(f->code, "hokuyo " + link_.describe() + ": " + f->message));
            continue;
        }
        auto& frame = std::get<ScipFrame>(e);
        if (!frame.scan_request || frame.scan_request->mode != 'M') continue;  // late replies
        if (frame.status == "00" || frame.status == "98") continue;  // ack / resumed after an error
        // The sensor stopped the stream on an error (21..49) or a hardware fault (50..97).
        result = fault(Status(StatusCode::kDeviceError,
                              "hokuyo " + link_.describe() + ": " + frame.statusText()));
        dropLink(result);
        return result;
    }
    return result;
}

Status HokuyoDevice::poll(std::vector<LaserScan>& out) {
    if (state_ != State::kStreaming) {
        const TimeNs wait = next_attempt_ - now_();
        if (wait > 0) {
            sleep_(std::min(wait, cfg_.read_slice_ns));
            return Status::ok();
        }
        if (Status s = connect(); !s) return s;
        // Scans that arrived right behind the ME acknowledgement.
        return handleEvents(out);
    }
    auto n = readChunk(cfg_.read_slice_ns);
    if (!n) {
        Status reported = fault(n.status());
        dropLink(reported);
        return reported;
    }
    Status s = handleEvents(out);
    if (state_ == State::kStreaming && now_() - last_scan_rx_ > cfg_.stream_timeout_ns) {
        Status reported = fault(Status(
            StatusCode::kTimeout, "hokuyo " + link_.describe() + ": no valid scan for " +
                                      std::to_string(toSeconds(now_() - last_scan_rx_)) + " s"));
        dropLink(reported);
        return reported;
    }
    return s;
}

Status HokuyoDevice::stop() {
    Status result = Status::ok();
    if (link_.isOpen()) {
        auto qt = transact(encodeQuitCommand());
        if (!qt)
            result = qt.status();
        else if (!qt->ok())
            result = Status(StatusCode::kDeviceError,
                            "hokuyo " + link_.describe() + ": " + qt->statusText());
    }
    link_.close();
    decoder_.resetLink();
    pending_.clear();
    ready_.clear();
    state_ = State::kStopped;
    next_attempt_ = 0;
    return result;
}

}  // namespace handscan::hokuyo
