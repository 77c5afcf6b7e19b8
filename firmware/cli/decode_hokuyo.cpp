// `handscan decode --device hokuyo`: the SCIP 2.0 stream of a UTM-30LX-EW (/hokuyo/raw) as JSON
// lines. One line per reply or scan: host receive time, device time (scan timestamp, ms), and every
// decoded field (echo, status and its meaning, PP/VV/II items, step range, ranges in mm - values
// below DMIN are the sensor's error codes - and intensities). Faults the parser recovered from get
// a line each; the summary counts frames, checksum failures, resyncs and scans missing between
// consecutive timestamps (scan period from the stream's own PP reply, else 25 ms).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <optional>
#include <ostream>

#include "decoder_registry.hpp"
#include "handscan/core/json.hpp"
#include "handscan/hokuyo/scip_stream_parser.hpp"
#include "handscan/hokuyo/sensor_parameters.hpp"

namespace handscan::cli {
namespace {

using hokuyo::ScipEvent;
using hokuyo::ScipFault;
using hokuyo::ScipFrame;

template <typename T>
void jsonArray(std::ostream& os, const std::vector<T>& v) {
    os << '[';
    for (std::size_t i = 0; i < v.size(); ++i) os << (i ? "," : "") << v[i];
    os << ']';
}

class HokuyoDecoder : public StreamDecoder {
public:
    void feed(TimeNs t_host, std::span<const std::uint8_t> bytes, std::ostream& jsonl) override {
        events_.clear();
        parser_.feed(bytes, events_);
        for (const ScipEvent& e : events_) {
            if (const auto* f = std::get_if<ScipFrame>(&e)) {
                printFrame(t_host, *f, jsonl);
            } else {
                const auto& fault = std::get<ScipFault>(e);
                jsonl << "{\"t_host_ns\":" << t_host << ",\"fault\":{\"code\":\""
                      << toString(fault.code) << "\",\"message\":" << jsonString(fault.message)
                      << "}}\n";
            }
        }
    }

    DecodeSummary finish(std::ostream& jsonl) override {
        if (!parser_.idle()) {
            jsonl << "{\"fault\":{\"code\":\"" << toString(StatusCode::kTruncated)
                  << "\",\"message\":\"stream ends inside a frame (at stream byte "
                  << parser_.stats().bytes << "); that frame is not counted\"}}\n";
        }
        DecodeSummary s;
        s.messages = parser_.stats().frames;
        s.checksum_failures = parser_.stats().checksum_failures;
        s.resyncs = parser_.stats().resyncs;
        s.gaps = missed_scans_;
        return s;
    }

private:
    void printFrame(TimeNs t_host, const ScipFrame& f, std::ostream& os) {
        os << std::setprecision(12) << "{\"t_host_ns\":" << t_host;
        if (f.scan) os << ",\"t_device_ms\":" << f.scan->timestamp_ms;
        os << ",\"stream_offset\":" << f.stream_offset << ",\"type\":\""
           << (f.scan ? "scan" : "reply") << "\",\"command\":" << jsonString(f.command)
           << ",\"echo\":" << jsonString(f.echo) << ",\"status\":" << jsonString(f.status)
           << ",\"ok\":" << (f.ok() ? "true" : "false")
           << ",\"status_text\":" << jsonString(f.statusText());
        if (!f.items.empty()) {
            os << ",\"items\":{";
            for (std::size_t i = 0; i < f.items.size(); ++i) {
                os << (i ? "," : "") << jsonString(f.items[i].first) << ':'
                   << jsonString(f.items[i].second);
            }
            os << '}';
        }
        if (!f.lines.empty()) {
            os << ",\"lines\":[";
            for (std::size_t i = 0; i < f.lines.size(); ++i)
                os << (i ? "," : "") << jsonString(f.lines[i]);
            os << ']';
        }
        if (f.command == "PP" && f.ok()) {
            if (auto p = hokuyo::SensorParameters::fromPpReply(f)) params_ = *p;
        }
        if (const auto& r = f.scan_request) {
            os << ",\"request\":{\"start_step\":" << r->start_step
               << ",\"end_step\":" << r->end_step << ",\"cluster\":" << r->cluster
               << ",\"interval\":" << r->interval << ",\"remaining\":" << r->count
               << ",\"tag\":" << jsonString(r->tag) << '}';
        }
        if (f.scan) {
            const auto& r = *f.scan_request;
            countGap(f.scan->timestamp_ms, r.interval);
            os << ",\"steps\":" << f.scan->ranges.size() << ",\"first_step\":" << r.start_step
               << ",\"last_step\":" << r.end_step;
            if (params_) {
                os << ",\"dmin_mm\":" << params_->dmin_mm
                   << ",\"angle_min_rad\":" << params_->angleRad(r.start_step)
                   << ",\"angle_increment_rad\":"
                   << std::max(r.cluster, 1) * params_->stepAngleRad();
            }
            os << ",\"ranges_mm\":";
            jsonArray(os, f.scan->ranges);
            if (!f.scan->intensities.empty()) {
                os << ",\"intensities\":";
                jsonArray(os, f.scan->intensities);
            }
        }
        os << "}\n";
    }

    void countGap(std::uint32_t t_ms, int interval) {
        const double period_ms =
            (params_ ? static_cast<double>(params_->scanPeriodNs()) * 1e-6 : 25.0) * (interval + 1);
        if (last_t_ms_) {
            const std::uint32_t dt = (t_ms - *last_t_ms_) & 0xFFFFFFu;
            const long missing = dt < 0x800000u ? std::lround(dt / period_ms) - 1 : 0;
            if (missing > 0) missed_scans_ += static_cast<std::uint64_t>(missing);
        }
        last_t_ms_ = t_ms;
    }

    hokuyo::ScipStreamParser parser_;
    std::vector<ScipEvent> events_;
    std::optional<hokuyo::SensorParameters> params_;
    std::optional<std::uint32_t> last_t_ms_;
    std::uint64_t missed_scans_ = 0;
};

const RegisterDecoder kHokuyo{"hokuyo", "/hokuyo/raw",
                              [] { return std::make_unique<HokuyoDecoder>(); }};

}  // namespace
}  // namespace handscan::cli
