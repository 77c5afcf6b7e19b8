#include "handscan/xsens_fake/recorded_byte_stream.hpp"

#include <algorithm>

namespace handscan::xsens {

Result<std::size_t> RecordedByteStream::read(std::span<std::uint8_t> buffer, TimeNs timeout) {
    if (!open_) return Status{StatusCode::kDisconnected, "recording replay: not open"};
    if (finished() || chunks_[next_].t_host_rx > clock_.now + timeout) {
        clock_.now += timeout;
        return std::size_t{0};
    }
    const RecordedChunk& c = chunks_[next_];
    clock_.now = std::max(clock_.now, c.t_host_rx);
    const std::size_t n = std::min(buffer.size(), c.bytes.size() - offset_);
    std::copy_n(c.bytes.begin() + static_cast<std::ptrdiff_t>(offset_), n, buffer.begin());
    offset_ += n;
    if (offset_ == c.bytes.size()) {
        ++next_;
        offset_ = 0;
    }
    return n;
}

Status RecordedByteStream::writeAll(std::span<const std::uint8_t> data, TimeNs /*timeout*/) {
    if (!open_) return {StatusCode::kDisconnected, "recording replay: not open"};
    written_.insert(written_.end(), data.begin(), data.end());
    return Status::ok();
}

}  // namespace handscan::xsens
