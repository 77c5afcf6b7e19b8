// Writes simulator messages into an MCAP recording on the project's channels
// (handscan/recording/channels.hpp): raw device streams plus /groundtruth/pose.
#pragma once

#include <array>
#include <memory>
#include <string>

#include "handscan/recording/mcap_writer.hpp"
#include "handscan/sim/simulator.hpp"

namespace handscan::sim {

class McapSink : public RecordingSink {
public:
    // A file sink (path) or, with an empty path, an in-memory one (tests; see takeBuffer()).
    [[nodiscard]] static Result<std::unique_ptr<McapSink>> create(const std::string& path,
                                                                  bool cameras);
    [[nodiscard]] Status write(const StreamMessage& message) override;
    [[nodiscard]] Status close();
    std::vector<std::uint8_t> takeBuffer() { return writer_->takeBuffer(); }
    std::uint64_t bytesWritten() const { return writer_->bytesWritten(); }

private:
    std::unique_ptr<recording::McapWriter> writer_;
    std::array<int, static_cast<std::size_t>(SimChannel::kCount)> ids_{};
};

}  // namespace handscan::sim
