// Camera frames as the camera codec's V4L2 buffer records (drivers/camera frame_record.hpp),
// with the mid-exposure time computed by the codec's own rule (frame_timing.hpp). Uncompressed
// buffers (GREY, YUYV) are stored PNG-coded (png_payload.hpp): the same bytes on decoding, at
// about half the size of the noisy raw pixels.
#include "handscan/camera/frame_record.hpp"
#include "handscan/camera/frame_timing.hpp"
#include "handscan/camera/image_convert.hpp"
#include "handscan/sim/camera_stream.hpp"

namespace handscan::sim {

bool cameraRecordsAvailable() { return true; }

std::vector<std::uint8_t> encodeCameraRecord(const V4l2FrameInfo& info,
                                             const CameraStreamConfig& config,
                                             const std::vector<std::uint8_t>& data) {
    const PixelFormat format = config.format == "GREY"   ? PixelFormat::kGrey8
                               : config.format == "YUYV" ? PixelFormat::kYuyv
                                                         : PixelFormat::kMjpeg;
    camera::FrameRecordHeader h;
    h.sequence = info.sequence;
    h.flags = info.flags;
    h.timestamp_ns = info.timestamp_ns;
    h.bytesused = static_cast<std::uint32_t>(data.size());
    h.fourcc = camera::fourccFromPixelFormat(format);
    h.width = static_cast<std::uint32_t>(config.width);
    h.height = static_cast<std::uint32_t>(config.height);
    h.stride = format == PixelFormat::kGrey8  ? h.width
               : format == PixelFormat::kYuyv ? 2 * h.width
                                              : 0;
    h.exposure_us = static_cast<std::uint32_t>(info.exposure_ns / kNsPerUs);
    h.t_host_ns = camera::midExposureTime(info.flags, info.timestamp_ns, info.exposure_ns,
                                          info.readout_ns, info.t_dequeue_ns)
                      .t_mid_exposure;
    return camera::encodeFrameRecord(h, data, camera::FrameCoding::kPng);
}

}  // namespace handscan::sim
