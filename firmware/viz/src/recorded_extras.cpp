#include "handscan/viz/recorded_extras.hpp"

#include "handscan/camera/frame_record.hpp"
#include "handscan/camera/frame_timing.hpp"
#include "handscan/camera/image_convert.hpp"
#include "handscan/core/log.hpp"
#include "handscan/recording/channels.hpp"

namespace handscan::viz {

namespace ch = recording::channels;

std::vector<std::string> RecordedExtras::topics(bool colour) {
    std::vector<std::string> t{std::string(ch::kCameraTrack.topic),
                               std::string(ch::kGroundTruthPose.topic)};
    if (colour) t.emplace_back(ch::kCameraColour.topic);
    return t;
}

Status RecordedExtras::add(const recording::RecordedMessage& msg, VizWriter& writer) {
    const std::string& topic = msg.channel->topic;
    if (topic == ch::kCameraTrack.topic) return addFrame(msg, true, writer);
    if (colour_ && topic == ch::kCameraColour.topic) return addFrame(msg, false, writer);
    if (topic != ch::kGroundTruthPose.topic) return Status::ok();
    auto gt = recording::decodeGroundTruthPose(msg.data);
    if (gt.isOk()) return writer.groundTruth(*gt);
    if (errors_++ == 0) log().warn("viz: {}: {}", topic, gt.status().message());
    return Status::ok();
}

Status RecordedExtras::addFrame(const recording::RecordedMessage& msg, bool track,
                                VizWriter& writer) {
    const Camera camera = track ? Camera::kTrack : Camera::kColour;
    // A grey frame the recording holds as PNG (record version 2) is a PNG a viewer shows as it
    // is: handed over without decoding (decoding and encoding it again would cost more than the
    // pipeline). Its time by the rule the frame decoder applies (mid-exposure).
    auto header = camera::decodeFrameRecord(msg.data, camera::FramePayload::kHeaderOnly);
    if (header.isOk() && header->coding == camera::FrameCoding::kPng &&
        camera::pixelFormatFromFourcc(header->header.fourcc) == PixelFormat::kGrey8 &&
        header->header.stride == header->header.width) {
        const camera::FrameRecordHeader& h = header->header;
        const TimeNs exposure = static_cast<TimeNs>(h.exposure_us) * kNsPerUs;
        const TimeNs t = camera::midExposureTime(h.flags, h.timestamp_ns, exposure, 0, msg.log_time)
                             .t_mid_exposure;
        const auto png =
            msg.data.subspan(header->record_size - header->stored_size, header->stored_size);
        return writer.compressedImage(camera, t, png, "png", static_cast<int>(h.width),
                                      static_cast<int>(h.height));
    }
    auto image = (track ? track_ : colour_decoder_).decode(msg.log_time, msg.data);
    if (!image.isOk()) {
        if (errors_++ == 0) log().warn("viz: {}: {}", msg.channel->topic, image.status().message());
        return Status::ok();
    }
    return writer.image(camera, *image);
}

}  // namespace handscan::viz
