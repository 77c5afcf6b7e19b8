#include "handscan/recording/recording_summary.hpp"

#include <algorithm>
#include <cinttypes>
#include <cstdio>
#include <map>

#include "handscan/core/json.hpp"

namespace handscan::recording {
namespace {

void finishChannel(ChannelSummary& c, std::vector<TimeNs>& periods) {
    if (c.messages < 2) return;
    c.rate_hz = static_cast<double>(c.messages - 1) / toSeconds(c.last - c.first);
    const auto mid = periods.begin() + static_cast<std::ptrdiff_t>(periods.size() / 2);
    std::nth_element(periods.begin(), mid, periods.end());
    c.median_period_ns = *mid;
    for (TimeNs p : periods) {
        if (p > ChannelSummary::kGapFactor * c.median_period_ns) ++c.gaps;
    }
}

std::string fmt(const char* format, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, format, v);
    return buf;
}

}  // namespace

Result<RecordingSummary> summarizeRecording(
    McapReader& reader, const std::function<void(double)>& progress,
    const std::function<void(const RecordedMessage&)>& observe) {
    RecordingSummary s;
    s.name = reader.name();
    s.file_size = reader.fileSize();
    s.library = reader.header().library;
    s.profile = reader.header().profile;
    s.chunks = reader.chunkCount();
    s.indexed = reader.indexed();
    s.truncated = reader.truncated();

    std::map<std::uint16_t, std::size_t> index;
    for (const auto& ch : reader.channels()) {
        index[ch.id] = s.channels.size();
        ChannelSummary c;
        c.id = ch.id;
        c.topic = ch.topic;
        c.message_encoding = ch.message_encoding;
        s.channels.push_back(std::move(c));
    }
    std::vector<std::vector<TimeNs>> periods(s.channels.size());
    const std::pair<TimeNs, TimeNs> range = reader.timeRange();
    const TimeNs t0 = range.first;
    const TimeNs t1 = range.second;
    std::uint64_t n = 0;
    const Status st = reader.forEachMessage({}, [&](const RecordedMessage& m) {
        const std::size_t i = index.at(m.channel->id);
        ChannelSummary& c = s.channels[i];
        if (c.messages == 0) {
            c.first = m.log_time;
        } else {
            const TimeNs dt = m.log_time - c.last;  // >= 0: messages come in log-time order
            periods[i].push_back(dt);
            if (dt > c.largest_gap_ns) {
                c.largest_gap_ns = dt;
                c.largest_gap_after = c.last;
            }
        }
        c.last = m.log_time;
        ++c.messages;
        c.bytes += m.data.size();
        if (s.messages == 0) s.start = m.log_time;
        s.end = m.log_time;
        ++s.messages;
        if (observe) observe(m);
        if (progress && (++n & 0x3FF) == 0 && t1 > t0)
            progress(toSeconds(m.log_time - t0) / toSeconds(t1 - t0));
    });
    if (!st) return st;
    for (std::size_t i = 0; i < s.channels.size(); ++i) finishChannel(s.channels[i], periods[i]);
    s.dropped = reader.dropped();
    return s;
}

Status checkRecordingCrcs(McapReader& reader, RecordingSummary& s) {
    const Status v = reader.verify();
    if (!v && v.code() == StatusCode::kIoError) return v;
    s.crc_checked = true;
    s.crc_problems = v ? "" : v.message();
    return Status::ok();
}

void printSummaryText(const RecordingSummary& s, std::ostream& out) {
    out << s.name << ": " << s.file_size << " bytes, " << s.messages << " messages in " << s.chunks
        << " chunks, " << fmt("%.3f", toSeconds(s.duration())) << " s";
    if (!s.library.empty()) out << " (written by " << s.library << ")";
    out << "\n";
    if (s.truncated) {
        out << "TRUNCATED: no footer (recording cut short, e.g. a power cut); recovered "
            << "every complete chunk by scanning\n";
    } else if (!s.indexed) {
        out << "no summary index: read by scanning\n";
    }
    for (const auto& d : s.dropped)
        out << "dropped " << d.length << " bytes at " << d.offset << ": " << d.reason << "\n";
    if (s.crc_checked)
        out << "CRC check: " << (s.crc_problems.empty() ? "every CRC matches" : s.crc_problems)
            << "\n";
    out << "start " << fmt("%.6f", toSeconds(s.start)) << " s, end "
        << fmt("%.6f", toSeconds(s.end)) << " s (host clock)\n";
    char line[512];
    std::snprintf(line, sizeof line, "%-18s %-28s %9s %9s %12s %10s %11s %6s\n", "topic",
                  "encoding", "messages", "rate Hz", "duration s", "first s", "max gap ms", "gaps");
    out << line;
    for (const auto& c : s.channels) {
        std::snprintf(line, sizeof line,
                      "%-18s %-28s %9" PRIu64 " %9.2f %12.3f %10.3f %11.2f %6" PRIu64 "\n",
                      c.topic.c_str(), c.message_encoding.c_str(), c.messages, c.rate_hz,
                      toSeconds(c.duration()), toSeconds(c.first - s.start),
                      static_cast<double>(c.largest_gap_ns) * 1e-6, c.gaps);
        out << line;
    }
    if (s.devices.empty()) return;
    out << "devices (raw channels decoded with the drivers' codecs; rate on the samples' own "
           "times):\n";
    std::snprintf(line, sizeof line, "%-16s %-15s %9s %10s %-15s %11s %7s %7s\n", "device",
                  "channel", "samples", "rate", "unit", "raw msgs/s", "lost", "errors");
    out << line;
    for (const auto& d : s.devices) {
        double raw_rate = 0.0;
        for (const auto& c : s.channels) {
            if (c.topic == d.topic) raw_rate = c.rate_hz;
        }
        std::snprintf(line, sizeof line,
                      "%-16s %-15s %9" PRIu64 " %10.3f %-15s %11.2f %7" PRIu64 " %7" PRIu64 "\n",
                      d.device.c_str(), d.topic.c_str(), d.samples, d.rate_hz, d.unit.c_str(),
                      raw_rate, d.lost, d.errors);
        out << line;
        if (!d.last_error.empty()) out << "  last error: " << d.last_error << "\n";
    }
}

void printSummaryJson(const RecordingSummary& s, std::ostream& out) {
    Json j;
    j["file"] = s.name;
    j["file_size"] = s.file_size;
    j["library"] = s.library;
    j["profile"] = s.profile;
    j["messages"] = s.messages;
    j["chunks"] = s.chunks;
    j["start_ns"] = s.start;
    j["end_ns"] = s.end;
    j["duration_s"] = toSeconds(s.duration());
    j["indexed"] = s.indexed;
    j["truncated"] = s.truncated;
    j["recovered"] = s.truncated || !s.dropped.empty();
    j["dropped"] = Json::array();
    for (const auto& d : s.dropped)
        j["dropped"].push_back({{"offset", d.offset}, {"length", d.length}, {"reason", d.reason}});
    if (s.crc_checked) {
        j["crc_ok"] = s.crc_problems.empty();
        j["crc_problems"] = s.crc_problems;
    }
    j["channels"] = Json::array();
    for (const auto& c : s.channels) {
        j["channels"].push_back({{"id", c.id},
                                 {"topic", c.topic},
                                 {"message_encoding", c.message_encoding},
                                 {"messages", c.messages},
                                 {"bytes", c.bytes},
                                 {"rate_hz", c.rate_hz},
                                 {"first_ns", c.first},
                                 {"last_ns", c.last},
                                 {"duration_s", toSeconds(c.duration())},
                                 {"median_period_ns", c.median_period_ns},
                                 {"largest_gap_ns", c.largest_gap_ns},
                                 {"largest_gap_after_ns", c.largest_gap_after},
                                 {"gaps", c.gaps}});
    }
    j["devices"] = Json::array();
    for (const auto& d : s.devices) {
        j["devices"].push_back({{"device", d.device},
                                {"topic", d.topic},
                                {"unit", d.unit},
                                {"samples", d.samples},
                                {"rate_hz", d.rate_hz},
                                {"first_ns", d.first},
                                {"last_ns", d.last},
                                {"lost", d.lost},
                                {"errors", d.errors},
                                {"last_error", d.last_error}});
    }
    out << jsonText(j) << "\n";
}

}  // namespace handscan::recording
