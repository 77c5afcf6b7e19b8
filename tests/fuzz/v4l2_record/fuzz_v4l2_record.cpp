// Fuzzes the camera frame record decoder (concatenated records, as recordings and decode files
// hold them), the pixel conversions of every record that decodes, and the replay of the records
// through the real capture state machine. Properties: no crash / hang / unbounded memory; a
// decoded record re-encodes to the same bytes (PNG-coded ones to the same pixels).
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "handscan/camera/camera_device.hpp"
#include "handscan/camera/frame_record.hpp"
#include "handscan/camera/image_convert.hpp"
#include "handscan/camera/replay_v4l2_device.hpp"
#include "handscan/core/log.hpp"

using namespace handscan;
using namespace handscan::camera;

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    handscan::log().set_level(spdlog::level::off);
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    std::span<const std::uint8_t> in(data, size);
    ReplayDeviceConfig dc;
    std::size_t records = 0;
    FrameRecordHeader first{};
    std::vector<std::uint8_t> all;
    while (!in.empty() && records < 16) {
        auto r = decodeFrameRecord(in);
        if (!r) break;
        // Re-encoding an uncoded version-1 record gives back its bytes; a PNG-coded one decodes
        // to a payload that codes and decodes to the same bytes again.
        const auto again = encodeFrameRecord(r->header, r->payload);
        if (r->coding == FrameCoding::kRaw && r->record_size == again.size() &&
            !std::equal(again.begin(), again.end(), in.begin())) {
            std::abort();
        }
        if (r->coding == FrameCoding::kPng) {
            auto recoded =
                decodeFrameRecord(encodeFrameRecord(r->header, r->payload, FrameCoding::kPng));
            if (!recoded || !std::equal(recoded->payload.begin(), recoded->payload.end(),
                                        r->payload.begin(), r->payload.end())) {
                std::abort();
            }
        }
        if (records == 0) first = r->header;
        all.insert(all.end(), again.begin(), again.end());
        // Keep decode work bounded: conversions only for small images.
        if (auto fmt = pixelFormatFromFourcc(r->header.fourcc);
            fmt && static_cast<std::uint64_t>(r->header.width) * r->header.height <= (1u << 16)) {
            Image img;
            img.format = *fmt;
            img.width = static_cast<int>(r->header.width);
            img.height = static_cast<int>(r->header.height);
            img.stride_bytes = static_cast<int>(r->header.stride);
            img.data.assign(r->payload.begin(), r->payload.end());
            (void)toGrey(img);
            (void)toBgr(img);
        }
        in = in.subspan(r->record_size);
        ++records;
    }
    if (records == 0 || static_cast<std::uint64_t>(first.width) * first.height > (1u << 16) ||
        static_cast<std::uint64_t>(first.stride) * first.height > (1u << 24)) {
        return 0;  // the replay device would allocate buffers of this size: keep memory bounded
    }
    // Replay through the capture state machine in the first record's format.
    const std::uint32_t stride = first.stride;
    dc.formats = {{first.width, first.height, first.fourcc, transport::kV4l2FieldNone, stride,
                   std::max<std::uint32_t>(stride * first.height, first.bytesused)}};
    ReplayV4l2Device dev(dc);
    if (!dev.addRecords(all)) std::abort();  // what decoded once decodes again
    CameraConfig cfg;
    cfg.width = first.width;
    cfg.height = first.height;
    CameraDevice cam(dev, cfg, nullptr, [] { return TimeNs{0}; });
    if (cam.start()) {
        for (std::size_t i = 0; i < records + 1; ++i) (void)cam.grab(0);
        (void)cam.stop();
    }
    if (!dev.violations().empty()) {  // the driver broke the V4L2 call rules
        std::fprintf(stderr, "V4L2 rule broken: %s\n", dev.violations().front().c_str());
        std::abort();
    }
    return 0;
}
