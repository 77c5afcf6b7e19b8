#include "handscan/hokuyo/scan_stream_decoder.hpp"

#include <cmath>
#include <variant>

namespace handscan::hokuyo {

ScanStreamStats ScanStreamDecoder::stats() const {
    ScanStreamStats s = stats_;
    s.parser = parser_.stats();
    return s;
}

void ScanStreamDecoder::feed(TimeNs t_rx, std::span<const std::uint8_t> bytes,
                             std::vector<LaserScan>& scans, std::vector<ScipEvent>& events) {
    const std::size_t first_event = events.size();
    parsed_.clear();
    parser_.feed(bytes, parsed_);
    for (ScipEvent& ev : parsed_) {
        auto* frame = std::get_if<ScipFrame>(&ev);
        if (frame != nullptr && frame->scan && frame->scan_request) {
            if (params_) {
                decodeScan(*frame, t_rx, scans);
            } else {
                events.emplace_back(
                    ScipFault{StatusCode::kProtocolError,
                              "hokuyo: scan before the PP reply: geometry unknown, scan dropped"});
            }
            continue;
        }
        if (frame != nullptr && frame->command == "PP" && frame->ok()) {
            auto params = SensorParameters::fromPpReply(*frame);
            if (params.isOk()) {
                params_ = *params;
            } else {
                events.emplace_back(ScipFault{params.status().code(), params.status().message()});
            }
        }
        events.push_back(std::move(ev));
    }
    for (std::size_t i = first_event; i < events.size(); ++i) {
        if (const auto* fault = std::get_if<ScipFault>(&events[i])) {
            ++faults_;
            last_fault_ = fault->message;
        }
    }
}

void ScanStreamDecoder::feed(TimeNs t_rx, std::span<const std::uint8_t> bytes,
                             std::vector<LaserScan>& scans) {
    scratch_.clear();
    feed(t_rx, bytes, scans, scratch_);
}

StreamCounters ScanStreamDecoder::counters() const {
    const ScanStreamStats s = stats();
    StreamCounters c;
    c.messages = s.scans;
    c.checksum_failures = s.parser.checksum_failures;
    c.resyncs = s.parser.resyncs;
    c.gaps = s.missed_scans;
    c.errors = faults_;
    c.last_error = last_fault_;
    return c;
}

void ScanStreamDecoder::decodeScan(const ScipFrame& frame, TimeNs t_rx,
                                   std::vector<LaserScan>& scans) {
    const ScanPayload& scan = *frame.scan;
    const ScanRequest& req = *frame.scan_request;
    const double period = valuePeriodNs(req, *params_);
    // The frame's bytes as received: its transmission time comes off the arrival time.
    const TimeNs t0 =
        timestamper_.stamp(scan.timestamp_ms, t_rx, frame.stream_end - frame.stream_offset,
                           static_cast<int>(scan.ranges.size()), period);
    if (last_t_device_) {
        // Scans lost in between (damaged, or missed while reconnecting), from the sensor's clock.
        const std::uint32_t dt = (scan.timestamp_ms - *last_t_device_) & 0xFFFFFFu;
        const double scan_ms =
            static_cast<double>(params_->scanPeriodNs()) * 1e-6 * (req.interval + 1);
        if (scan_ms > 0 && dt < 0x800000u && dt > 1.5 * scan_ms) {
            stats_.missed_scans +=
                static_cast<std::uint64_t>(std::lround(static_cast<double>(dt) / scan_ms)) - 1;
        }
    }
    last_t_device_ = scan.timestamp_ms;
    scans.push_back(toLaserScan(scan, req, *params_, t0));
    ++stats_.scans;
}

}  // namespace handscan::hokuyo
