#include "handscan/sim/mcap_sink.hpp"

#include "handscan/recording/channels.hpp"

namespace handscan::sim {

namespace ch = handscan::recording::channels;

Result<std::unique_ptr<McapSink>> McapSink::create(const std::string& path, bool cameras) {
    recording::McapWriterOptions o;
    o.library = "handscan-sim";
    auto w =
        path.empty() ? recording::McapWriter::inMemory(o) : recording::McapWriter::create(path, o);
    if (!w) return w.status();
    auto sink = std::unique_ptr<McapSink>(new McapSink());
    sink->writer_ = std::move(*w);
    sink->ids_.fill(-1);
    const std::pair<SimChannel, const recording::ChannelSpec*> specs[] = {
        {SimChannel::kHokuyo, &ch::kHokuyoRaw},
        {SimChannel::kXsens, &ch::kXsensRaw},
        {SimChannel::kCan, &ch::kMotorCan},
        {SimChannel::kTrackingCamera, &ch::kCameraTrack},
        {SimChannel::kColourCamera, &ch::kCameraColour},
        {SimChannel::kGroundTruth, &ch::kGroundTruthPose},
    };
    for (const auto& [c, spec] : specs) {
        if (!cameras && (c == SimChannel::kTrackingCamera || c == SimChannel::kColourCamera))
            continue;
        auto id = recording::addChannel(*sink->writer_, *spec);
        if (!id) return id.status();
        sink->ids_[static_cast<std::size_t>(c)] = *id;
    }
    return sink;
}

Status McapSink::write(const StreamMessage& m) {
    const int id = ids_[static_cast<std::size_t>(m.channel)];
    if (id < 0)
        return Status(StatusCode::kInvalidArgument,
                      "McapSink: no channel registered for this stream");
    return writer_->write(static_cast<std::uint16_t>(id), m.t_host_rx, m.bytes);
}

Status McapSink::close() { return writer_->close(); }

}  // namespace handscan::sim
