// A camera thread: CameraDevice over a V4L2 node. The colour camera's frames go to the
// colouriser; the tracking camera (its visual odometry is a later module) reports how bright the
// scene is, so the operator is warned in the dark. A vanished node is reported and reopened.
#include <cmath>

#include "handscan/camera/camera_device.hpp"
#include "handscan/pipeline_daemon/sensor_sources.hpp"

namespace handscan::pipeline_daemon {
namespace {

camera::CameraConfig cameraConfig(const CameraConfig& c) {
    camera::CameraConfig cc;
    cc.width = static_cast<std::uint32_t>(c.width);
    cc.height = static_cast<std::uint32_t>(c.height);
    const PixelFormat wanted = c.format == "YUYV"    ? PixelFormat::kYuyv
                               : c.format == "MJPEG" ? PixelFormat::kMjpeg
                                                     : PixelFormat::kGrey8;
    std::erase(cc.formats, wanted);
    cc.formats.insert(cc.formats.begin(), wanted);
    cc.frame_interval = {1000, static_cast<std::uint32_t>(std::lround(c.fps * 1000.0))};
    cc.exposure = fromSeconds(c.exposure_ms * 1e-3);
    cc.readout = fromSeconds(c.readout_ms * 1e-3);
    return cc;
}

// Mean luma of every 64th pixel (GREY, or YUYV's Y bytes); -1 for compressed frames.
float meanLuma(const Image& img) {
    const int step = img.format == PixelFormat::kYuyv    ? 2
                     : img.format == PixelFormat::kGrey8 ? 1
                                                         : 0;
    if (step == 0 || img.data.empty()) return -1.0f;
    double sum = 0;
    std::size_t n = 0;
    for (std::size_t i = 0; i < img.data.size(); i += 64 * static_cast<std::size_t>(step), ++n)
        sum += img.data[i];
    return n ? static_cast<float>(sum / static_cast<double>(n)) : -1.0f;
}

class CameraSource final : public SensorSource {
public:
    CameraSource(const SourceContext& c, bool colour)
        : SensorSource(colour ? "colour-cam" : "tracking-cam",
                       static_cast<float>(colour ? c.config.colour_camera.fps
                                                 : c.config.tracking_camera.fps)),
          config_(colour ? c.config.colour_camera : c.config.tracking_camera),
          colour_(colour),
          c_(c) {}
    ~CameraSource() override { stop(); }

private:
    void run() override {
        runSessions(500 * kNsPerMs, 5 * kNsPerSec, "camera " + config_.device,
                    " (check the cable; retrying)", [this] { return session(); });
    }

    Status session() {
        std::unique_ptr<transport::V4l2Device> node = c_.links.camera(config_);
        camera::CameraDevice cam(*node, cameraConfig(config_));
        if (Status s = cam.start(); !s.isOk()) return s;
        health_.setConnected();
        health_.markAttempted();
        Status end = Status::ok();
        while (!stopping()) {
            auto frame = cam.grab(100 * kNsPerMs);
            if (!frame.isOk()) {
                end = frame.status();
                break;
            }
            if (!*frame) continue;
            health_.addSample((*frame)->t_host);
            if (colour_) {
                if (!c_.queues.colour_images.tryPush(std::move(**frame)))
                    c_.queues.dropped.fetch_add(1, std::memory_order_relaxed);
            } else {
                if (const float luma = meanLuma(**frame); luma >= 0)
                    c_.queues.camera_brightness.store(luma, std::memory_order_relaxed);
                if (!c_.queues.tracking_images.tryPush(std::move(**frame)))
                    c_.queues.dropped.fetch_add(1, std::memory_order_relaxed);
            }
        }
        (void)cam.stop();
        return stopping() ? Status::ok() : end;
    }

    CameraConfig config_;
    bool colour_;
    SourceContext c_;
};

}  // namespace

std::unique_ptr<SensorSource> makeCameraSource(const SourceContext& c, bool colour) {
    return std::make_unique<CameraSource>(c, colour);
}

}  // namespace handscan::pipeline_daemon
