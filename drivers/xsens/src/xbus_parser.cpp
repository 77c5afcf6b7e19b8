#include "handscan/xsens/xbus_parser.hpp"

#include <algorithm>

namespace handscan::xsens {
namespace {

// MTData2 items (XDI u16, size u8, data) must tile the payload exactly. A frame that passes the
// 8-bit checksum by chance after a lost byte almost never does, so this catches most of the 1 in
// 256 damaged frames the checksum alone would let through.
bool mtData2ItemsTile(std::span<const std::uint8_t> payload) {
    std::size_t off = 0;
    while (off + 3 <= payload.size()) off += 3 + payload[off + 2];
    return off == payload.size();
}

}  // namespace

void XbusParser::feed(std::span<const std::uint8_t> bytes) {
    // Compact before growing: views handed out earlier are documented as invalid now.
    if (head_ > 0) {
        buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(head_));
        head_ = 0;
    }
    buffer_.insert(buffer_.end(), bytes.begin(), bytes.end());
}

void XbusParser::reset() {
    buffer_.clear();
    head_ = 0;
    in_garbage_ = false;
}

void XbusParser::skip(std::size_t n) {
    if (!in_garbage_) {
        ++stats_.resyncs;
        in_garbage_ = true;
    }
    stats_.bytes_discarded += n;
    head_ += n;
}

std::optional<XbusFrameView> XbusParser::next() {
    for (;;) {
        const std::span<const std::uint8_t> avail(buffer_.data() + head_, buffer_.size() - head_);
        if (avail.empty()) return std::nullopt;
        // 1. Find a preamble followed by the master bus id.
        if (avail[0] != kPreamble) {
            const auto it = std::find(avail.begin() + 1, avail.end(), kPreamble);
            skip(static_cast<std::size_t>(it - avail.begin()));
            continue;
        }
        if (avail.size() < 2) return std::nullopt;
        if (avail[1] != kBusIdMaster) {
            skip(1);
            continue;
        }
        // 2. Length (standard or extended).
        if (avail.size() < 4) return std::nullopt;
        std::size_t header = 4;
        std::size_t n = avail[3];
        if (n == kExtendedLengthMarker) {
            if (avail.size() < 6) return std::nullopt;
            n = (std::size_t{avail[4]} << 8) | avail[5];
            header = 6;
            if (n > kMaxPayload) {
                ++stats_.oversize;
                skip(1);
                continue;
            }
        }
        const std::size_t total = header + n + 1;
        if (avail.size() < total) return std::nullopt;
        // 3. Checksum over BID..CS.
        unsigned sum = 0;
        for (std::size_t i = 1; i < total; ++i) sum += avail[i];
        if ((sum & 0xFF) != 0) {
            // Trust nothing after this preamble: the real next frame may start inside this one
            // (a lost byte makes the length field swallow the start of the next frame).
            ++stats_.checksum_failures;
            skip(1);
            continue;
        }
        const std::span<const std::uint8_t> payload = avail.subspan(header, n);
        if (avail[2] == toByte(MessageId::kMtData2) && !mtData2ItemsTile(payload)) {
            ++stats_.malformed;
            skip(1);
            continue;
        }
        in_garbage_ = false;
        ++stats_.frames;
        head_ += total;
        return XbusFrameView{avail[1], avail[2], payload};
    }
}

}  // namespace handscan::xsens
