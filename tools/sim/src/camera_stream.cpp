#include "handscan/sim/camera_stream.hpp"

#include <turbojpeg.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace handscan::sim {
namespace {

// videodev2.h values (kept here: the simulator includes no kernel headers).
constexpr std::uint32_t kFlagMapped = 0x00000001;
constexpr std::uint32_t kFlagTimestampMonotonic = 0x00002000;
constexpr std::uint32_t kFlagTstampSrcSoe = 0x00010000;

std::uint8_t clampByte(double v) {
    return static_cast<std::uint8_t>(std::clamp(std::lround(v), 0L, 255L));
}

}  // namespace

void rgbToYuyv(const std::vector<std::uint8_t>& rgb, int width, int height,
               std::vector<std::uint8_t>& out) {
    out.resize(static_cast<std::size_t>(width) * height * 2);
    for (int y = 0; y < height; ++y) {
        const std::uint8_t* row = &rgb[static_cast<std::size_t>(y) * width * 3];
        std::uint8_t* o = &out[static_cast<std::size_t>(y) * width * 2];
        for (int x = 0; x + 1 < width; x += 2) {
            const std::uint8_t* a = row + 3 * x;
            const std::uint8_t* b = a + 3;
            // BT.601, limited range (16..235 / 16..240), chroma averaged over the pixel pair.
            const double ya = 16 + 0.257 * a[0] + 0.504 * a[1] + 0.098 * a[2];
            const double yb = 16 + 0.257 * b[0] + 0.504 * b[1] + 0.098 * b[2];
            const double r = 0.5 * (a[0] + b[0]), g = 0.5 * (a[1] + b[1]), bl = 0.5 * (a[2] + b[2]);
            const double u = 128 - 0.148 * r - 0.291 * g + 0.439 * bl;
            const double v = 128 + 0.439 * r - 0.368 * g - 0.071 * bl;
            o[2 * x] = clampByte(ya);
            o[2 * x + 1] = clampByte(u);
            o[2 * x + 2] = clampByte(yb);
            o[2 * x + 3] = clampByte(v);
        }
    }
}

void rgbToMjpeg(const std::vector<std::uint8_t>& rgb, int width, int height, int quality,
                std::vector<std::uint8_t>& out) {
    tjhandle h = tjInitCompress();
    if (h == nullptr) throw std::runtime_error("turbojpeg: tjInitCompress failed");
    unsigned char* jpeg = nullptr;
    unsigned long size = 0;
    const int rc = tjCompress2(h, rgb.data(), width, width * 3, height, TJPF_RGB, &jpeg, &size,
                               TJSAMP_422, quality, TJFLAG_FASTDCT);
    if (rc != 0) {
        const std::string err = tjGetErrorStr2(h);
        tjDestroy(h);
        throw std::runtime_error("turbojpeg: " + err);
    }
    out.assign(jpeg, jpeg + size);
    tjFree(jpeg);
    tjDestroy(h);
}

CameraStream::CameraStream(const CameraStreamConfig& config, TimeNs host_start_ns, Rng rng)
    : cfg_(config), host_start_(host_start_ns), rng_(rng) {
    if (cfg_.format != "GREY" && cfg_.format != "YUYV" && cfg_.format != "MJPEG") {
        throw std::invalid_argument("camera format '" + cfg_.format +
                                    "': expected GREY, YUYV or MJPEG");
    }
}

double CameraStream::exposureStart(std::int64_t k) const {
    const double dev0 = cfg_.clock.deviceSeconds(0.03);
    return cfg_.clock.trueSeconds(dev0 + static_cast<double>(k) / cfg_.fps);
}

void CameraStream::frame(std::int64_t k, const std::vector<std::uint8_t>& pixels, bool lost,
                         std::vector<StreamMessage>& out) {
    const std::uint32_t seq = sequence_++;
    if (lost) return;  // the driver never dequeues it: a sequence gap
    const double t0 = exposureStart(k);
    const bool colour_in = pixels.size() == static_cast<std::size_t>(cfg_.width) * cfg_.height * 3;
    if (cfg_.format == "GREY") {
        if (colour_in) throw std::invalid_argument("GREY camera fed a colour image");
        packed_ = pixels;
    } else if (cfg_.format == "YUYV") {
        if (!colour_in) throw std::invalid_argument("YUYV camera needs an RGB image");
        rgbToYuyv(pixels, cfg_.width, cfg_.height, packed_);
    } else {
        if (!colour_in) throw std::invalid_argument("MJPEG camera needs an RGB image");
        rgbToMjpeg(pixels, cfg_.width, cfg_.height, cfg_.mjpeg_quality, packed_);
    }
    // Readout of a frame takes most of a frame period; UVC stamps the end of the transfer.
    const double readout = cfg_.readout_s;
    const double t_stamp = cfg_.start_of_exposure ? t0 : t0 + cfg_.exposure_s + readout;
    V4l2FrameInfo info;
    info.sequence = seq;
    info.timestamp_ns = hostNs(host_start_, t_stamp + 2e-5 * rng_.uniform());
    info.flags =
        kFlagMapped | kFlagTimestampMonotonic | (cfg_.start_of_exposure ? kFlagTstampSrcSoe : 0u);
    info.bytesused = static_cast<std::uint32_t>(packed_.size());
    info.t_exposure_start = t0;
    info.exposure_ns = fromSeconds(cfg_.exposure_s);
    info.readout_ns = fromSeconds(readout);
    info.t_dequeue_ns =
        hostNs(host_start_, t0 + cfg_.exposure_s + readout + cfg_.clock.delay(rng_));
    last_ = info;
    out.push_back({info.t_dequeue_ns, cfg_.channel, encodeCameraRecord(info, cfg_, packed_)});
}

}  // namespace handscan::sim
