// Xbus stream -> JSON lines, for `handscan decode --device xsens` (support and golden tests).
// One line per message: host receive time, device time (SampleTimeFine in seconds, unwrapped),
// and every MTData2 item named as in Xsens' XDI table with its values in SI units (angles in
// rad, GNSS scaled integers converted); control messages with their decoded payload (Error with
// its explanation). Counts messages, checksum failures, resyncs and packet-counter gaps.
#pragma once

#include <cstdint>
#include <optional>
#include <ostream>
#include <span>

#include "handscan/core/time.hpp"
#include "handscan/xsens/mtdata2.hpp"
#include "handscan/xsens/xbus_parser.hpp"

namespace handscan::xsens {

struct XsensJsonSummary {
    std::uint64_t messages = 0;
    std::uint64_t checksum_failures = 0;
    std::uint64_t resyncs = 0;
    std::uint64_t gaps = 0;          // packet-counter discontinuities
    std::uint64_t lost_packets = 0;  // packets missing across them
};

class XsensJsonDecoder {
public:
    // `t_host`: host receive time of the chunk (0 for a plain capture file).
    void feed(TimeNs t_host, std::span<const std::uint8_t> bytes, std::ostream& jsonl);
    XsensJsonSummary summary() const;

private:
    void writeFrame(TimeNs t_host, const XbusFrameView& frame, std::ostream& out);
    void writeMtData2(const MtData2Packet& packet, std::ostream& out);

    XbusParser parser_;
    XsensJsonSummary summary_;
    PacketCounterTracker counter_;
    std::optional<std::uint32_t> last_stf_;
    std::int64_t stf_unwrapped_ = 0;
};

// One MTData2 item as a JSON value ({"x":..,"unit":..} / number / {"raw":..,"problem":..}).
void writeItemJson(const MtData2Value& value, std::ostream& out);

}  // namespace handscan::xsens
