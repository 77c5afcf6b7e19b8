#include "handscan/hil/recorded_streams.hpp"

#include <algorithm>
#include <array>
#include <optional>

#include "handscan/camera/timed_frame_file.hpp"
#include "handscan/hokuyo/scip_stream_parser.hpp"
#include "handscan/recording/channels.hpp"
#include "handscan/recording/mcap_reader.hpp"
#include "handscan/xsens/xbus_frame.hpp"
#include "handscan/xsens/xbus_messages.hpp"
#include "handscan/xsens/xbus_parser.hpp"

namespace handscan::hil {
namespace {

std::vector<std::uint8_t> concatenate(const std::vector<xsens::RecordedChunk>& reads,
                                      std::vector<std::size_t>* ends = nullptr) {
    std::vector<std::uint8_t> all;
    for (const auto& r : reads) {
        all.insert(all.end(), r.bytes.begin(), r.bytes.end());
        if (ends) ends->push_back(all.size());
    }
    return all;
}

// DeviceID and ProductCode from the recorded handshake replies, so the fake MTi answers the
// daemon's requests as the recorded device did.
void readXsensIdentity(const std::vector<xsens::RecordedChunk>& reads, RecordedStreams& out) {
    xsens::XbusParser parser;
    for (const auto& r : reads) {
        parser.feed(r.bytes);
        while (auto f = parser.next()) {
            if (f->mid == xsens::toByte(xsens::MessageId::kDeviceId)) {
                if (auto id = xsens::decodeDeviceId(f->payload); id.isOk())
                    out.xsens_device_id = *id;
            } else if (f->mid == xsens::toByte(xsens::MessageId::kProductCode)) {
                out.xsens_product_code = xsens::decodeProductCode(f->payload);
            } else if (f->mid == xsens::toByte(xsens::MessageId::kMtData2)) {
                return;  // past the handshake
            }
        }
    }
}

}  // namespace

void splitTimedScanFrames(const std::vector<xsens::RecordedChunk>& reads,
                          std::vector<hokuyo::SourceScanFrame>& frames, std::vector<TimeNs>& rx) {
    std::vector<std::size_t> ends;
    const std::vector<std::uint8_t> all = concatenate(reads, &ends);
    const std::string_view stream(reinterpret_cast<const char*>(all.data()), all.size());
    hokuyo::ScipStreamParser parser;
    std::vector<hokuyo::ScipEvent> events;
    parser.feed(stream, events);
    for (auto& e : events) {
        auto* f = std::get_if<hokuyo::ScipFrame>(&e);
        if (f == nullptr || !f->scan) continue;
        // The read that delivered the frame's last byte.
        const auto read = std::upper_bound(ends.begin(), ends.end(), f->stream_end - 1);
        if (read == ends.end()) continue;
        rx.push_back(reads[static_cast<std::size_t>(read - ends.begin())].t_host_rx);
        frames.push_back(
            {std::string(stream.substr(f->stream_offset, f->stream_end - f->stream_offset)),
             *f->scan_request, std::move(*f->scan)});
    }
}

std::vector<xsens::RecordedChunk> measurementBytes(const std::vector<xsens::RecordedChunk>& reads) {
    const std::vector<std::uint8_t> ack = xsens::encodeFrame(xsens::MessageId::kGoToMeasurementAck);
    std::vector<std::size_t> ends;
    const std::vector<std::uint8_t> all = concatenate(reads, &ends);
    const auto at = std::search(all.begin(), all.end(), ack.begin(), ack.end());
    const std::size_t from =
        at == all.end() ? 0 : static_cast<std::size_t>(at - all.begin()) + ack.size();
    std::vector<xsens::RecordedChunk> out;
    std::size_t begin = 0;
    for (std::size_t i = 0; i < reads.size(); begin = ends[i], ++i) {
        if (ends[i] <= from) continue;
        const std::size_t skip = from > begin ? from - begin : 0;
        out.push_back({reads[i].t_host_rx,
                       std::vector<std::uint8_t>(reads[i].bytes.begin() + static_cast<long>(skip),
                                                 reads[i].bytes.end())});
    }
    return out;
}

namespace {

// One camera's records into a timed frame file, created at the first record.
class CameraFile {
public:
    CameraFile(std::string path, std::string& out_path, std::size_t& count)
        : path_(std::move(path)), out_path_(out_path), count_(count) {}
    void add(TimeNs t_rx, std::span<const std::uint8_t> record) {
        if (!error_.isOk()) return;
        if (!writer_) {
            auto w = camera::TimedFrameFileWriter::create(path_);
            if (!w) {
                error_ = w.status();
                return;
            }
            writer_.emplace(std::move(*w));
            out_path_ = path_;
        }
        // A record that does not decode is the recording's: the camera driver skips it live, so
        // it is left out here and counted by nobody (replay counts it as a decode error).
        if (Status s = writer_->append(t_rx, record); s.isOk()) {
            ++count_;
        } else if (s.code() == StatusCode::kIoError) {
            error_ = s;
        }
    }
    Status close() {
        if (writer_ && error_.isOk()) error_ = writer_->close();
        return error_;
    }

private:
    std::string path_;
    std::string& out_path_;
    std::size_t& count_;
    std::optional<camera::TimedFrameFileWriter> writer_;
    Status error_ = Status::ok();
};

}  // namespace

Result<RecordedStreams> loadRecordedStreams(const std::string& path,
                                            const std::string& camera_dir) {
    auto reader = recording::McapReader::open(path);
    if (!reader.isOk()) return reader.status();
    RecordedStreams out;
    out.path = path;
    std::tie(out.start, out.end) = (*reader)->timeRange();
    namespace ch = recording::channels;
    recording::ReadOptions options;
    options.topics = {std::string(ch::kHokuyoRaw.topic), std::string(ch::kXsensRaw.topic),
                      std::string(ch::kMotorCan.topic)};
    if (!camera_dir.empty()) {
        options.topics.emplace_back(ch::kCameraTrack.topic);
        options.topics.emplace_back(ch::kCameraColour.topic);
    }
    CameraFile track(camera_dir + "/track.frames", out.track_frames, out.track_frame_count);
    CameraFile colour(camera_dir + "/colour.frames", out.colour_frames, out.colour_frame_count);
    std::vector<xsens::RecordedChunk> hokuyo_reads, xsens_reads;
    Status s = (*reader)->forEachMessage(options, [&](const recording::RecordedMessage& m) {
        const std::string_view topic = m.channel->topic;
        if (topic == ch::kCameraTrack.topic) return track.add(m.log_time, m.data);
        if (topic == ch::kCameraColour.topic) return colour.add(m.log_time, m.data);
        std::vector<std::uint8_t> bytes(m.data.begin(), m.data.end());
        if (topic == ch::kHokuyoRaw.topic) {
            hokuyo_reads.push_back({m.log_time, std::move(bytes)});
        } else if (topic == ch::kXsensRaw.topic) {
            xsens_reads.push_back({m.log_time, std::move(bytes)});
        } else {
            out.can.push_back({m.log_time, std::string(bytes.begin(), bytes.end())});
        }
    });
    if (!s.isOk()) return s;
    if (Status t = track.close(); !t.isOk()) return t;
    if (Status c = colour.close(); !c.isOk()) return c;
    if (hokuyo_reads.empty() && xsens_reads.empty() && out.can.empty()) {
        return Status(StatusCode::kInvalidArgument,
                      path +
                          ": no raw device streams (/hokuyo/raw, /xsens/raw, /motor/can) to "
                          "play; record with the drivers' taps or `handscan sim`");
    }
    splitTimedScanFrames(hokuyo_reads, out.scans, out.scan_rx);
    readXsensIdentity(xsens_reads, out);
    out.xsens_measurement = measurementBytes(xsens_reads);
    return out;
}

}  // namespace handscan::hil
