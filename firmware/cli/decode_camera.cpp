// `handscan decode --device camera FILE|REC.mcap`: camera frame records (drivers/camera
// frame_record.hpp; a file of concatenated records or the /camera/track channel of a recording)
// as one JSON line per frame: V4L2 metadata, how the record stores the buffer (raw or lossless
// PNG, and its stored size), timestamp clock and source, the mid-exposure host time, and the mean
// grey level of the decoded image (proves the payload decodes). Summary:
// resyncs = bytes skipped to the next record magic after a bad record, gaps = frames lost
// according to the sequence numbers.
#include <algorithm>
#include <numeric>
#include <sstream>

#include "decoder_registry.hpp"
#include "handscan/camera/frame_record.hpp"
#include "handscan/camera/frame_timing.hpp"
#include "handscan/camera/image_convert.hpp"
#include "handscan/core/json.hpp"
#include "handscan/transport/v4l2_device.hpp"

namespace handscan::cli {
namespace {

using namespace camera;

const char* clockName(std::uint32_t flags) {
    switch (flags & transport::kV4l2BufFlagTimestampMask) {
        case transport::kV4l2BufFlagTimestampMonotonic:
            return "monotonic";
        case transport::kV4l2BufFlagTimestampCopy:
            return "copy";
        case transport::kV4l2BufFlagTimestampUnknown:
            return "unknown";
        default:
            return "other";
    }
}

class CameraDecoder final : public StreamDecoder {
public:
    void feed(TimeNs t_host, std::span<const std::uint8_t> bytes, std::ostream& out) override {
        buf_.insert(buf_.end(), bytes.begin(), bytes.end());
        drain(t_host, out, false);
    }

    DecodeSummary finish(std::ostream& out) override {
        drain(0, out, true);
        if (!buf_.empty()) {
            out << "{\"error\":\"" << buf_.size()
                << " trailing bytes are not a complete frame record\"}\n";
            buf_.clear();
        }
        summary_.gaps = sequence_.dropped();
        return summary_;
    }

private:
    void drain(TimeNs t_host, std::ostream& out, bool at_end) {
        std::size_t pos = 0;
        while (pos < buf_.size()) {
            auto r = decodeFrameRecord(std::span<const std::uint8_t>(buf_).subspan(pos));
            if (!r) {
                if (r.status().code() == StatusCode::kTruncated && !at_end)
                    break;  // wait for more bytes
                out << "{\"offset\":" << consumed_ + pos
                    << ",\"error\":" << jsonString(r.status().message()) << "}\n";
                ++summary_.resyncs;
                pos = nextMagic(pos + 1);
                continue;
            }
            frame(t_host, *r, out);
            pos += r->record_size;
        }
        consumed_ += pos;
        buf_.erase(buf_.begin(), buf_.begin() + static_cast<std::ptrdiff_t>(pos));
    }

    std::size_t nextMagic(std::size_t from) const {
        auto it =
            std::search(buf_.begin() + static_cast<std::ptrdiff_t>(std::min(from, buf_.size())),
                        buf_.end(), kFrameRecordMagic.begin(), kFrameRecordMagic.end());
        return static_cast<std::size_t>(it - buf_.begin());
    }

    void frame(TimeNs t_host, const FrameRecordView& r, std::ostream& out) {
        ++summary_.messages;
        const FrameRecordHeader& h = r.header;
        sequence_.update(h.sequence);
        std::ostringstream o;
        o << "{\"t_host_ns\":";
        if (t_host != 0) {
            o << t_host;
        } else {
            o << "null";
        }
        const bool soe =
            (h.flags & transport::kV4l2BufFlagTstampSrcMask) == transport::kV4l2BufFlagTstampSrcSoe;
        o << ",\"sequence\":" << h.sequence << ",\"timestamp_ns\":" << h.timestamp_ns
          << ",\"timestamp_clock\":\"" << clockName(h.flags) << "\",\"timestamp_source\":\""
          << (soe ? "start_of_exposure" : "end_of_frame")
          << "\",\"error_flag\":" << ((h.flags & transport::kV4l2BufFlagError) ? "true" : "false")
          << ",\"flags\":" << h.flags
          << ",\"format\":" << jsonString(transport::fourccName(h.fourcc))
          << ",\"width\":" << h.width << ",\"height\":" << h.height << ",\"stride\":" << h.stride
          << ",\"bytesused\":" << h.bytesused << ",\"coding\":\""
          << (r.coding == FrameCoding::kPng ? "png" : "raw")
          << "\",\"stored_bytes\":" << r.stored_size << ",\"exposure_us\":" << h.exposure_us
          << ",\"t_mid_exposure_ns\":" << h.t_host_ns;
        if (auto fmt = pixelFormatFromFourcc(h.fourcc)) {
            Image img;
            img.format = *fmt;
            img.width = static_cast<int>(h.width);
            img.height = static_cast<int>(h.height);
            img.stride_bytes = static_cast<int>(h.stride);
            img.sequence = h.sequence;
            img.data.assign(r.payload.begin(), r.payload.end());
            auto grey = toGrey(img);
            if (grey) {
                const double sum = std::accumulate(grey->data.begin(), grey->data.end(), 0.0);
                o << ",\"mean_grey\":"
                  << sum / static_cast<double>(std::max<std::size_t>(1, grey->data.size()));
            } else {
                o << ",\"decode_error\":" << jsonString(grey.status().message());
            }
        }
        o << "}\n";
        out << o.str();
    }

    std::vector<std::uint8_t> buf_;
    std::uint64_t consumed_ = 0;
    SequenceTracker sequence_;
    DecodeSummary summary_;
};

const RegisterDecoder kCamera{"camera", "/camera/track",
                              [] { return std::make_unique<CameraDecoder>(); }};

}  // namespace
}  // namespace handscan::cli
