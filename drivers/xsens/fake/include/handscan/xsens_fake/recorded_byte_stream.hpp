// Replays a recorded byte stream (chunks as a driver's read() returned them, with their host
// receive times) as a ByteStream on a virtual clock: reads hand out each chunk when its receive
// time comes, writes are recorded and otherwise ignored (the recording already holds the
// device's replies, in order). Used to run the real device state machine over simulator output
// and recordings.
#pragma once

#include <vector>

#include "handscan/transport/byte_stream.hpp"
#include "handscan/xsens_fake/fake_xsens_stream.hpp"

namespace handscan::xsens {

struct RecordedChunk {
    TimeNs t_host_rx = 0;
    std::vector<std::uint8_t> bytes;
};

class RecordedByteStream : public transport::ByteStream {
public:
    RecordedByteStream(std::vector<RecordedChunk> chunks, VirtualClock& clock)
        : chunks_(std::move(chunks)), clock_(clock) {}

    Status open() override {
        open_ = true;
        return Status::ok();
    }
    void close() override { open_ = false; }
    bool isOpen() const override { return open_; }
    Result<std::size_t> read(std::span<std::uint8_t> buffer, TimeNs timeout) override;
    Status writeAll(std::span<const std::uint8_t> data, TimeNs timeout) override;
    std::string describe() const override { return "recording replay"; }

    bool finished() const { return next_ >= chunks_.size(); }
    const std::vector<std::uint8_t>& written() const { return written_; }

private:
    std::vector<RecordedChunk> chunks_;
    VirtualClock& clock_;
    std::size_t next_ = 0;
    std::size_t offset_ = 0;  // into chunks_[next_] when a read took only part of it
    std::vector<std::uint8_t> written_;
    bool open_ = false;
};

}  // namespace handscan::xsens
