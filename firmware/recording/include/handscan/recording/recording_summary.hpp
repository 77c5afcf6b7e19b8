// What `handscan info` shows about a recording: per channel the message count, rate, first/last
// time, and gaps (the largest interval and how many intervals exceed 3x the median period, i.e.
// lost or late messages); for the file its duration and whether it was cut short and recovered.
#pragma once

#include <cstdint>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

#include "handscan/core/status.hpp"
#include "handscan/core/time.hpp"
#include "handscan/recording/mcap_reader.hpp"

namespace handscan::recording {

struct ChannelSummary {
    std::uint16_t id = 0;
    std::string topic;
    std::string message_encoding;
    std::uint64_t messages = 0;
    std::uint64_t bytes = 0;
    TimeNs first = 0;
    TimeNs last = 0;
    double rate_hz = 0.0;              // (messages - 1) / (last - first); 0 with < 2 messages
    TimeNs median_period_ns = 0;
    TimeNs largest_gap_ns = 0;         // longest interval between consecutive messages
    TimeNs largest_gap_after = 0;      // log time of the message before that interval
    std::uint64_t gaps = 0;            // intervals longer than kGapFactor x the median period

    static constexpr int kGapFactor = 3;
    TimeNs duration() const { return last - first; }
};

struct RecordingSummary {
    std::string name;
    std::uint64_t file_size = 0;
    std::string library;
    std::string profile;
    std::vector<ChannelSummary> channels;  // by channel id
    std::uint64_t messages = 0;
    TimeNs start = 0;
    TimeNs end = 0;
    std::size_t chunks = 0;
    bool indexed = false;    // read through the summary index
    bool truncated = false;  // no valid footer: cut short, recovered by a linear scan
    std::vector<DroppedRegion> dropped;
    // Filled by checkRecordingCrcs(): every chunk, data-section and summary CRC.
    bool crc_checked = false;
    std::string crc_problems;  // empty when every CRC matched

    TimeNs duration() const { return end - start; }
};

// Reads every message once. `progress` (optional) gets the fraction of the time span done.
[[nodiscard]] Result<RecordingSummary> summarizeRecording(McapReader& reader,
                                                          const std::function<void(double)>& progress = {});

// Runs McapReader::verify() and records the outcome in `s`; false on an I/O error.
[[nodiscard]] Status checkRecordingCrcs(McapReader& reader, RecordingSummary& s);

void printSummaryText(const RecordingSummary& s, std::ostream& out);
void printSummaryJson(const RecordingSummary& s, std::ostream& out);

}  // namespace handscan::recording
