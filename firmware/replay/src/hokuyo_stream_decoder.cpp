#include <variant>

#include "handscan/replay/stream_decoders.hpp"

namespace handscan::replay {

void HokuyoStreamDecoder::feed(TimeNs t_rx, std::span<const std::uint8_t> bytes, std::vector<LaserScan>& out) {
    events_.clear();
    parser_.feed(bytes, events_);
    for (const hokuyo::ScipEvent& ev : events_) {
        if (const auto* fault = std::get_if<hokuyo::ScipFault>(&ev)) {
            ++c_.errors;
            c_.last_error = fault->message;
            continue;
        }
        const auto& frame = std::get<hokuyo::ScipFrame>(ev);
        if (frame.command == "PP" && frame.ok()) {
            auto params = hokuyo::SensorParameters::fromPpReply(frame);
            if (params.isOk()) {
                params_ = *params;
            } else {
                ++c_.errors;
                c_.last_error = params.status().message();
            }
            continue;
        }
        if (!frame.scan || !frame.scan_request) continue;
        if (!params_) {
            ++c_.errors;
            c_.last_error = "hokuyo: scan before the PP reply: geometry unknown, scan dropped";
            continue;
        }
        const hokuyo::ScanPayload& scan = *frame.scan;
        const hokuyo::ScanRequest& req = *frame.scan_request;
        const double period = hokuyo::valuePeriodNs(req, *params_);
        const TimeNs t0 = timestamper_.stamp(scan.timestamp_ms, t_rx, frame.stream_end - frame.stream_offset,
                                             static_cast<int>(scan.ranges.size()), period);
        if (last_t_device_) {
            // Scans missing in between, from the sensor's own clock.
            const std::uint32_t dt = (scan.timestamp_ms - *last_t_device_) & 0xFFFFFFu;
            const double scan_ms = static_cast<double>(params_->scanPeriodNs()) * 1e-6 * (req.interval + 1);
            if (scan_ms > 0 && dt < 0x800000u && dt > 1.5 * scan_ms) {
                c_.gaps += static_cast<std::uint64_t>(static_cast<double>(dt) / scan_ms + 0.5) - 1;
            }
        }
        last_t_device_ = scan.timestamp_ms;
        out.push_back(hokuyo::toLaserScan(scan, req, *params_, t0));
        ++c_.messages;
    }
}

StreamCounters HokuyoStreamDecoder::counters() const {
    StreamCounters c = c_;
    c.checksum_failures = parser_.stats().checksum_failures;
    c.resyncs = parser_.stats().resyncs;
    return c;
}

}  // namespace handscan::replay
