#include "handscan/xsens_fake/fake_xsens_stream.hpp"

#include <algorithm>

namespace handscan::xsens {

Status FakeXsensStream::open() {
    open_ = true;
    return Status::ok();
}

Result<std::size_t> FakeXsensStream::read(std::span<std::uint8_t> buffer, TimeNs timeout) {
    if (!open_) return Status{StatusCode::kDisconnected, "fake-xsens: link is down"};
    if (pending_.empty()) {
        // Replies first; otherwise the next packet if it is due within the timeout.
        const bool mismatched = link_baud_ != device_.baudrate();
        if (device_.hasOutput()) {
            pending_ = device_.takeOutput();
            if (mismatched) FakeXsens::garble(pending_);
        } else if (device_.measuring()) {
            const TimeNs period = kNsPerSec / device_.rateHz();
            if (next_packet_ < clock_.now) next_packet_ = clock_.now + period;
            if (next_packet_ + latency_ <= clock_.now + timeout) {
                clock_.now = next_packet_ + latency_;
                next_packet_ += period;
                device_.emitPacket();
                pending_ = device_.takeOutput();
                if (mismatched) FakeXsens::garble(pending_);
            }
        }
        if (pending_.empty()) {
            clock_.now += timeout;
            return std::size_t{0};
        }
    }
    std::size_t n = std::min({buffer.size(), pending_.size(), max_chunk_});
    if (disconnect_after_) {
        if (*disconnect_after_ == 0) {
            open_ = false;
            pending_.clear();
            disconnect_after_.reset();  // one drop per call
            return Status{StatusCode::kDisconnected, "fake-xsens: link dropped"};
        }
        n = std::min(n, *disconnect_after_);
        *disconnect_after_ -= n;
    }
    std::copy_n(pending_.begin(), n, buffer.begin());
    pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(n));
    return n;
}

Status FakeXsensStream::writeAll(std::span<const std::uint8_t> data, TimeNs /*timeout*/) {
    if (!open_) return Status{StatusCode::kDisconnected, "fake-xsens: link is down"};
    if (link_baud_ == device_.baudrate()) device_.receive(data);  // else the device hears noise
    return Status::ok();
}

}  // namespace handscan::xsens
