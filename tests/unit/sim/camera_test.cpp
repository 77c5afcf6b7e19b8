// Camera rendering: the coarse-grid renderer equals per-pixel ray tracing, images hold enough
// corners to track, --dark removes them, the equidistant model round-trips, pixel packing.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <opencv2/imgproc.hpp>

#include "handscan/camera/frame_record.hpp"
#include "handscan/camera/frame_timing.hpp"
#include "handscan/core/config.hpp"
#include "handscan/sim/camera_model.hpp"
#include "handscan/sim/camera_stream.hpp"
#include "handscan/sim/scenes.hpp"
#include "handscan/sim/trajectory.hpp"

namespace handscan::sim {
namespace {

Calibration calibration() {
    return loadCalibration(std::string(HANDSCAN_SOURCE_DIR) + "/config/calibration.yaml");
}

// The office's corridor, looking west along it from the start of the walking loop.
Eigen::Isometry3d corridorView() {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    const Eigen::Matrix3d R_wf =
        Eigen::AngleAxisd(std::numbers::pi * 0.9, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    T.linear() = R_wf * Trajectory::deviceFromCamera();
    T.translation() = Eigen::Vector3d(6.0, 6.0, 1.3);
    return T;
}

std::vector<std::uint8_t> render(const Scene& scene, const CameraIntrinsics& cam,
                                 CameraRenderConfig cfg) {
    Raycaster rc(scene.world);
    CameraRenderer r(cam, cfg, rc, Rng(1, "render"));
    std::vector<std::uint8_t> img;
    r.render(
        0.0, [](double) { return corridorView(); }, img);
    return img;
}

TEST(CameraModelTest, EquidistantRaysReprojectToTheirPixels) {
    const Calibration cal = calibration();
    const auto rays = cameraRays(cal.tracking);
    const auto& k = cal.tracking.distortion_coeffs;
    const double fu = cal.tracking.intrinsics[0], cu = cal.tracking.intrinsics[2],
                 fv = cal.tracking.intrinsics[1], cv = cal.tracking.intrinsics[3];
    for (int v : {0, 100, 256, 511}) {
        for (int u : {0, 77, 320, 639}) {
            const Eigen::Vector3d d = rays[static_cast<std::size_t>(v) * 640 + u].cast<double>();
            const double th = std::atan2(d.head<2>().norm(), d.z()), t2 = th * th;
            const double thd = th * (1 + k[0] * t2 + k[1] * t2 * t2 + k[2] * t2 * t2 * t2 +
                                     k[3] * t2 * t2 * t2 * t2);
            const Eigen::Vector2d dir = d.head<2>().normalized();
            EXPECT_NEAR(fu * thd * dir.x() + cu, u, 1e-3);
            EXPECT_NEAR(fv * thd * dir.y() + cv, v, 1e-3);
        }
    }
    // Wide angle: the corner pixels look more than 60 deg off axis.
    EXPECT_LT(rays[0].z(), std::cos(60.0 * std::numbers::pi / 180.0));
}

TEST(CameraModelTest, CoarseGridRendererEqualsPerPixelRayTracing) {
    const Scene scene = buildScene("office");
    const Calibration cal = calibration();
    CameraRenderConfig fast, exact;
    fast.read_noise_dn = exact.read_noise_dn = 0.0;
    fast.shot_noise_gain = exact.shot_noise_gain = 0.0;
    exact.coarse = 1;
    const auto a = render(scene, cal.tracking, fast), b = render(scene, cal.tracking, exact);
    ASSERT_EQ(a.size(), b.size());
    std::size_t differ = 0, far = 0;
    double sum = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        const int e = std::abs(int(a[i]) - int(b[i]));
        differ += e > 2;
        far += e > 24;
        sum += e;
    }
    const double n = static_cast<double>(a.size());
    // Sub-texel differences (interpolated texture coordinates) on high-contrast texture edges and
    // sub-grid details (thin chair legs seen from afar) are all that may differ.
    EXPECT_LT(sum / n, 0.1);
    EXPECT_LT(static_cast<double>(differ) / n, 0.01);
    EXPECT_LT(static_cast<double>(far) / n, 0.002);
    std::printf("mean |diff| %.4f DN, >2 DN %.4f %%, >24 DN %.4f %%\n", sum / n,
                100.0 * static_cast<double>(differ) / n, 100.0 * static_cast<double>(far) / n);
}

TEST(CameraModelTest, OfficeImagesHaveCornersAndDarkImagesDoNot) {
    const Scene scene = buildScene("office");
    const Calibration cal = calibration();
    CameraRenderConfig cfg;
    const auto lit = render(scene, cal.tracking, cfg);
    cfg.illumination = 0.02;
    const auto dark = render(scene, cal.tracking, cfg);
    auto corners = [](const std::vector<std::uint8_t>& img) {
        cv::Mat m(512, 640, CV_8UC1, const_cast<std::uint8_t*>(img.data()));
        std::vector<cv::Point2f> pts;
        cv::goodFeaturesToTrack(m, pts, 1000, 0.01, 8);
        return pts.size();
    };
    double mean_lit = 0, mean_dark = 0;
    for (std::size_t i = 0; i < lit.size(); ++i) {
        mean_lit += lit[i];
        mean_dark += dark[i];
    }
    mean_lit /= static_cast<double>(lit.size());
    mean_dark /= static_cast<double>(dark.size());
    EXPECT_GT(mean_lit, 60.0);
    EXPECT_LT(mean_lit, 200.0);
    EXPECT_LT(mean_dark, 8.0);
    EXPECT_GT(corners(lit), 150u);
}

TEST(CameraModelTest, ColourCameraPacksYuyvAndMjpeg) {
    const Scene scene = buildScene("office");
    const Calibration cal = calibration();
    CameraRenderConfig cfg;
    cfg.colour = true;
    const auto rgb = render(scene, cal.colour, cfg);
    ASSERT_EQ(rgb.size(), 1600u * 1200u * 3u);
    std::vector<std::uint8_t> yuyv, jpeg;
    rgbToYuyv(rgb, 1600, 1200, yuyv);
    ASSERT_EQ(yuyv.size(), 1600u * 1200u * 2u);
    // Luma of a pixel pair matches BT.601 limited range.
    const std::size_t p = (600u * 1600u + 800u);
    const double y = 16 + 0.257 * rgb[3 * p] + 0.504 * rgb[3 * p + 1] + 0.098 * rgb[3 * p + 2];
    EXPECT_NEAR(yuyv[2 * p], y, 1.0);
    rgbToMjpeg(rgb, 1600, 1200, 85, jpeg);
    ASSERT_GT(jpeg.size(), 1000u);
    EXPECT_EQ(jpeg[0], 0xFF);
    EXPECT_EQ(jpeg[1], 0xD8);  // SOI
    EXPECT_EQ(jpeg[jpeg.size() - 2], 0xFF);
    EXPECT_EQ(jpeg[jpeg.size() - 1], 0xD9);  // EOI
}

}  // namespace
}  // namespace handscan::sim

namespace handscan::sim {
namespace {

TEST(CameraStreamTest, BufferRecordsDecodeWithMetadataRateAndSequenceGaps) {
    CameraStreamConfig cfg;  // tracking camera: GREY 640x512 at 50 Hz, SOE timestamps
    cfg.width = 64;
    cfg.height = 32;
    CameraStream stream(cfg, 1000 * kNsPerSec, Rng(1, "v4l2"));
    std::vector<StreamMessage> msgs;
    std::vector<std::vector<std::uint8_t>> sent;
    for (int k = 0; k < 500; ++k) {
        std::vector<std::uint8_t> img(64 * 32);
        for (std::size_t i = 0; i < img.size(); ++i) img[i] = static_cast<std::uint8_t>(i * 7 + k);
        stream.frame(k, img, k == 100 || k == 101, msgs);
        if (k != 100 && k != 101) sent.push_back(img);
    }
    ASSERT_EQ(msgs.size(), sent.size());
    camera::SequenceTracker seq;
    std::vector<TimeNs> stamps;
    for (std::size_t i = 0; i < msgs.size(); ++i) {
        auto r = camera::decodeFrameRecord(msgs[i].bytes);
        ASSERT_TRUE(r.isOk()) << r.status().message();
        const auto& h = r->header;
        EXPECT_EQ(std::vector<std::uint8_t>(r->payload.begin(), r->payload.end()), sent[i]);
        EXPECT_EQ(h.width, 64u);
        EXPECT_EQ(h.stride, 64u);
        EXPECT_EQ(h.flags & 0xE000u, 0x2000u);    // CLOCK_MONOTONIC
        EXPECT_EQ(h.flags & 0x70000u, 0x10000u);  // start of exposure
        EXPECT_EQ(h.exposure_us, 5000u);
        EXPECT_EQ(h.t_host_ns, h.timestamp_ns + 2'500'000);  // mid-exposure by the codec's rule
        EXPECT_GT(msgs[i].t_host_rx, h.timestamp_ns);        // dequeued after the exposure
        seq.update(h.sequence);
        stamps.push_back(h.timestamp_ns);
    }
    EXPECT_EQ(seq.dropped(), 2u);
    // 50 Hz of the camera's oscillator, 25 ppm fast against the host.
    const double period = toSeconds(stamps.back() - stamps.front()) / 499.0;
    EXPECT_NEAR(period, 0.02 / (1 + 25e-6), 3e-8);
}

}  // namespace
}  // namespace handscan::sim

namespace handscan::sim {
namespace {

TEST(CameraModelTest, MotionBlurSmearsAFastTurn) {
    const Scene scene = buildScene("office");
    Raycaster rc(scene.world);
    const Calibration cal = calibration();
    CameraRenderConfig cfg;
    cfg.read_noise_dn = 0.0;
    cfg.shot_noise_gain = 0.0;
    cfg.exposure_s = cfg.reference_exposure_s = 0.01;
    // Turning at 6 rad/s about the vertical: 0.06 rad (~17 px) during the exposure.
    const auto pose = [](double t) {
        Eigen::Isometry3d T = corridorView();
        T.linear() = Eigen::AngleAxisd(6.0 * t, Eigen::Vector3d::UnitZ()) * T.linear();
        return T;
    };
    auto gradient = [](const std::vector<std::uint8_t>& img) {
        double g = 0;
        for (int y = 0; y < 512; ++y)
            for (int x = 1; x < 640; ++x)
                g += std::abs(int(img[y * 640 + x]) - int(img[y * 640 + x - 1]));
        return g;
    };
    std::vector<std::uint8_t> sharp, blurred;
    CameraRenderer(cal.tracking, cfg, rc, Rng(1, "r")).render(0.0, pose, sharp);
    cfg.motion_blur = true;
    cfg.blur_samples = 6;
    CameraRenderer(cal.tracking, cfg, rc, Rng(1, "r")).render(0.0, pose, blurred);
    EXPECT_LT(gradient(blurred), 0.8 * gradient(sharp));  // horizontal detail smeared out
}

}  // namespace
}  // namespace handscan::sim
