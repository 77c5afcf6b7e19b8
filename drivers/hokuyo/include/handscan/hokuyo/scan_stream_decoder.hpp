// The receive side of a UTM-30LX-class sensor: SCIP 2.0 bytes as the host got them (with host
// receive times) in, LaserScans with per-step host times out. No transport and no commands, so the
// live HokuyoDevice, replay of a recording's /hokuyo/raw and tests share this one copy.
//
// The ScipStreamParser verifies every line; a PP reply in the stream gives the geometry (never
// assumed); each scan frame (MD/ME/GD...) becomes a LaserScan stamped by the ScanTimestamper from
// its 24-bit millisecond timestamp, the frame's bytes and the step period; scans missing between
// consecutive timestamps are counted. Every other frame (acks, replies) and every fault (damage,
// a scan before the geometry is known, an unusable PP reply) is handed back in stream order, for
// a state machine waiting for its replies or for the caller's counters.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "handscan/core/samples.hpp"
#include "handscan/core/stream_counters.hpp"
#include "handscan/hokuyo/scan_timestamper.hpp"
#include "handscan/hokuyo/scip_stream_parser.hpp"
#include "handscan/hokuyo/sensor_parameters.hpp"

namespace handscan::hokuyo {

struct ScanStreamStats {
    std::uint64_t scans = 0;         // LaserScans handed out
    std::uint64_t missed_scans = 0;  // scans missing between consecutive timestamps
    ScipParserStats parser;          // checksum failures, resyncs, discarded bytes
};

class ScanStreamDecoder {
public:
    explicit ScanStreamDecoder(ScanTimingConfig timing = {}) : timestamper_(timing) {}

    // Bytes received at host time `t_rx`: scans they complete are appended to `scans`, all other
    // frames and faults to `events`.
    void feed(TimeNs t_rx, std::span<const std::uint8_t> bytes, std::vector<LaserScan>& scans,
              std::vector<ScipEvent>& events);
    // The same for a recording: replies are of no use there, faults are only counted.
    void feed(TimeNs t_rx, std::span<const std::uint8_t> bytes, std::vector<LaserScan>& scans);
    // A new connection: buffered bytes are dropped (the sensor clock mapping and the scan
    // sequence continue, so scans missed while reconnecting are counted).
    void resetLink() { parser_.reset(); }

    const std::optional<SensorParameters>& parameters() const { return params_; }
    const ClockMapper& clock() const { return timestamper_.mapper(); }
    ScanStreamStats stats() const;
    // The same as the counters every stream decoder reports (faults: ScipFault events).
    StreamCounters counters() const;

private:
    void decodeScan(const ScipFrame& frame, TimeNs t_rx, std::vector<LaserScan>& scans);

    ScipStreamParser parser_;
    ScanTimestamper timestamper_;
    std::optional<SensorParameters> params_;
    std::optional<std::uint32_t> last_t_device_;
    std::vector<ScipEvent> parsed_;
    ScanStreamStats stats_;
    std::vector<ScipEvent> scratch_;
    std::uint64_t faults_ = 0;
    std::string last_fault_;
};

}  // namespace handscan::hokuyo
