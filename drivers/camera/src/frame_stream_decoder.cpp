#include "handscan/camera/frame_stream_decoder.hpp"

#include "handscan/camera/frame_record.hpp"
#include "handscan/camera/frame_timing.hpp"
#include "handscan/camera/image_convert.hpp"

namespace handscan::camera {

Result<Image> FrameStreamDecoder::decode(TimeNs t_rx, std::span<const std::uint8_t> record) {
    const auto fail = [&](Status s) -> Result<Image> {
        ++c_.errors;
        c_.last_error = "camera: " + s.message();
        return s;
    };
    auto rec = decodeFrameRecord(record);
    if (!rec) return fail(rec.status());
    const auto format = pixelFormatFromFourcc(rec->header.fourcc);
    if (!format)
        return fail(Status(StatusCode::kProtocolError, "frame with an unknown pixel format"));
    Image img;
    const TimeNs exposure = static_cast<TimeNs>(rec->header.exposure_us) * kNsPerUs;
    img.t_host =
        midExposureTime(rec->header.flags, rec->header.timestamp_ns, exposure, readout_, t_rx)
            .t_mid_exposure;
    img.sequence = rec->header.sequence;
    img.format = *format;
    img.width = static_cast<int>(rec->header.width);
    img.height = static_cast<int>(rec->header.height);
    img.stride_bytes = static_cast<int>(rec->header.stride);
    img.exposure_ns = exposure;
    img.data.assign(rec->payload.begin(), rec->payload.end());
    ++c_.messages;
    return img;
}

}  // namespace handscan::camera
