// What `handscan info` shows about a recording: per channel the message count, rate, first/last
// time, and gaps (the largest interval and how many intervals exceed 3x the median period, i.e.
// lost or late messages); for the file its duration and whether it was cut short and recovered.
// Raw device channels carry transport reads (TCP segments, serial reads, every CAN frame), so
// their message rate is not the device's: a caller that can decode them (firmware/replay
// device_rates.hpp) fills `devices` with the decoded sample rates, and the printers show both.
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
    double rate_hz = 0.0;  // (messages - 1) / (last - first); 0 with < 2 messages
    TimeNs median_period_ns = 0;
    TimeNs largest_gap_ns = 0;     // longest interval between consecutive messages
    TimeNs largest_gap_after = 0;  // log time of the message before that interval
    std::uint64_t gaps = 0;        // intervals longer than kGapFactor x the median period

    static constexpr int kGapFactor = 3;
    TimeNs duration() const { return last - first; }
};

// One device's decoded stream: samples (scans, IMU samples, encoder positions, frames) per
// second on the samples' own time stamps, next to the raw channel it was decoded from.
struct DeviceSummary {
    std::string device;         // "Hokuyo laser", "Xsens IMU", ...
    std::string topic;          // the raw channel
    std::string unit;           // "scans/s", "IMU samples/s", "positions/s", "frames/s", ...
    std::uint64_t samples = 0;  // decoded
    double rate_hz = 0.0;       // (samples - 1) / (last - first); 0 with < 2 samples
    TimeNs first = 0;           // time of the first and last sample (host clock)
    TimeNs last = 0;
    std::uint64_t lost = 0;    // samples missing according to the device's counters/sequence
    std::uint64_t errors = 0;  // checksum failures, resyncs, undecodable messages
    std::string last_error;    // the newest of those, for the operator
};

struct RecordingSummary {
    std::string name;
    std::uint64_t file_size = 0;
    std::string library;
    std::string profile;
    std::vector<ChannelSummary> channels;  // by channel id
    std::vector<DeviceSummary> devices;  // filled by a device decoder, not by summarizeRecording()
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

// Reads every message once. `progress` (optional) gets the fraction of the time span done;
// `observe` (optional) sees every message too, so a caller decodes in the same pass.
[[nodiscard]] Result<RecordingSummary> summarizeRecording(
    McapReader& reader, const std::function<void(double)>& progress = {},
    const std::function<void(const RecordedMessage&)>& observe = {});

// Runs McapReader::verify() and records the outcome in `s`; false on an I/O error.
[[nodiscard]] Status checkRecordingCrcs(McapReader& reader, RecordingSummary& s);

void printSummaryText(const RecordingSummary& s, std::ostream& out);
void printSummaryJson(const RecordingSummary& s, std::ostream& out);

}  // namespace handscan::recording
