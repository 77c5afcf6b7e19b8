// Incremental Xbus frame parser: fed arbitrary byte chunks (a serial read, a USB transfer, a whole
// capture file), hands out complete frames whose checksum holds. Like PX4's serial parsers it is a
// pure state machine with no I/O. After garbage or a damaged frame (a lost byte, a flipped bit)
// it drops only the preamble it trusted and searches again from the next byte, so a frame that
// starts inside the damaged one is still found: only the damaged frame is lost. The 8-bit
// checksum lets 1 in 256 damaged frames through; MTData2 frames are also checked for items that
// tile the payload exactly, which rejects nearly all of those.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "handscan/xsens/xbus_frame.hpp"

namespace handscan::xsens {

struct XbusParserStats {
    std::uint64_t frames = 0;             // frames with a valid checksum handed out
    std::uint64_t checksum_failures = 0;  // complete frames whose checksum did not hold
    std::uint64_t resyncs = 0;            // times the parser lost framing and searched again
    std::uint64_t bytes_discarded = 0;    // bytes skipped while searching for a preamble
    std::uint64_t oversize = 0;           // length fields beyond kMaxPayload (taken as garbage)
    std::uint64_t malformed = 0;          // checksum held but the MTData2 items did not tile
};

class XbusParser {
public:
    // Appends a chunk. Views returned by next() before this call become invalid.
    void feed(std::span<const std::uint8_t> bytes);
    // The next complete, checksum-valid frame, or nullopt when more bytes are needed.
    std::optional<XbusFrameView> next();
    // Bytes held that do not yet form a complete frame.
    std::size_t pending() const { return buffer_.size() - head_; }
    // Forgets buffered bytes (e.g. after a reconnect); statistics are kept.
    void reset();
    const XbusParserStats& stats() const { return stats_; }

private:
    void skip(std::size_t n);  // drops n bytes of garbage, counting one resync per garbage run

    std::vector<std::uint8_t> buffer_;
    std::size_t head_ = 0;     // first byte not consumed yet
    bool in_garbage_ = false;  // inside a run of skipped bytes (one resync per run)
    XbusParserStats stats_;
};

}  // namespace handscan::xsens
