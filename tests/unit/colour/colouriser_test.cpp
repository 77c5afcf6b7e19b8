// Colouriser on synthetic scenes: textured planes rendered through cam1 (synthetic_scene.hpp),
// points sampled on the planes, known poses.
#include "handscan/colour/colouriser.hpp"

#include <gtest/gtest.h>

#include <cstdio>

#include "handscan/camera/image_convert.hpp"
#include "handscan/core/se3.hpp"
#include "synthetic_scene.hpp"

namespace handscan::colour {
namespace {

using test::Rgb;
using test::TexturedPlane;

constexpr TimeNs kMs = kNsPerMs;

class ColouriserTest : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        cal_ = new Calibration();
        loadCamchain(std::string(HANDSCAN_SOURCE_DIR) + "/config/camchain.yaml", *cal_);
        rays_ = new std::vector<Eigen::Vector3d>(test::pixelRays(cal_->colour));
    }
    static void TearDownTestSuite() {
        delete cal_;
        delete rays_;
    }

    // Colour camera pose for a body (tracking camera) pose.
    static Eigen::Isometry3d colourPose(const Eigen::Isometry3d& T_world_body) {
        return T_world_body * cal_->T_colour_tracking.inverse();
    }

    static Image render(const std::vector<TexturedPlane>& planes,
                        const Eigen::Isometry3d& T_world_body, TimeNs t, std::uint32_t seq) {
        return test::renderBgr(cal_->colour, *rays_, planes, colourPose(T_world_body), t, seq);
    }

    // Points where every `step`-th pixel ray of the camera at T_world_body meets the planes.
    static void samplePoints(const std::vector<TexturedPlane>& planes,
                             const Eigen::Isometry3d& T_world_body, int step,
                             std::vector<Eigen::Vector3f>& pts,
                             std::vector<std::size_t>& plane_of) {
        const Eigen::Isometry3d T = colourPose(T_world_body);
        const int w = cal_->colour.resolution[0], h = cal_->colour.resolution[1];
        for (int v = 3; v < h - 3; v += step) {
            for (int u = 3; u < w - 3; u += step) {
                const auto hit =
                    test::castRay(planes, T.translation(),
                                  T.linear() * (*rays_)[static_cast<std::size_t>(v * w + u)]);
                if (!hit) continue;
                pts.push_back(hit->second.cast<float>());
                plane_of.push_back(hit->first);
            }
        }
    }

    // Largest per-channel difference between the assigned colour and the plane's true colour.
    static double colourError(const std::array<std::uint8_t, 3>& got, const Rgb& want) {
        double e = 0;
        for (std::size_t c = 0; c < 3; ++c)
            e = std::max(e,
                         std::abs(static_cast<double>(got[c]) - std::clamp(want[c], 0.0, 255.0)));
        return e;
    }

    static inline Calibration* cal_ = nullptr;
    static inline std::vector<Eigen::Vector3d>* rays_ = nullptr;
};

Eigen::Isometry3d pose(double yaw_deg, const Eigen::Vector3d& t) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() =
        Eigen::AngleAxisd(yaw_deg * M_PI / 180.0, Eigen::Vector3d::UnitY()).toRotationMatrix();
    T.translation() = t;
    return T;
}

TEST_F(ColouriserTest, PlaneColoursComeBackRight) {
    const std::vector<TexturedPlane> planes{{3.0, -100, 100, -100, 100, test::wavePattern}};
    const Eigen::Isometry3d T = pose(5, {0.1, -0.05, 0.0});
    Colouriser col(*cal_);
    ASSERT_TRUE(col.addImage(render(planes, T, 1000 * kMs, 7)));
    std::vector<Eigen::Vector3f> pts;
    std::vector<std::size_t> plane_of;
    samplePoints(planes, T, 13, pts, plane_of);
    ASSERT_GT(pts.size(), 10000u);
    const std::vector<TimeNs> times(pts.size(), 1010 * kMs);
    const ColourResult r = col.colourise(pts, times, [&](TimeNs) { return T; });
    ASSERT_EQ(r.size(), pts.size());
    EXPECT_EQ(r.coloured, pts.size());
    double worst = 0, sum = 0;
    for (std::size_t i = 0; i < pts.size(); ++i) {
        ASSERT_TRUE(r.valid(i)) << i << " " << toString(r.status[i]);
        EXPECT_EQ(r.image_sequence[i], 7u);
        const double e = colourError(r.rgb[i], test::wavePattern(pts[i].x(), pts[i].y()));
        worst = std::max(worst, e);
        sum += e;
    }
    std::printf("[ measured ] static plane: %zu points, colour error mean %.2f, max %.2f levels\n",
                pts.size(), sum / static_cast<double>(pts.size()), worst);
    EXPECT_LE(worst, 2.5);  // bilinear interpolation of the smooth pattern plus 8-bit rounding
}

TEST_F(ColouriserTest, MovingDeviceUsesThePoseAtTheImageTime) {
    const std::vector<TexturedPlane> planes{{3.0, -100, 100, -100, 100, test::wavePattern}};
    // The laser caught the points at 1.00 s; the frame was exposed at 1.08 s after the device
    // moved 12 cm and turned 4 degrees.
    const TimeNs t_point = 1000 * kMs, t_image = 1080 * kMs;
    const Eigen::Isometry3d T_point = pose(0, {0, 0, 0});
    const Eigen::Isometry3d T_image = pose(4, {0.12, 0.03, 0.02});
    const auto pose_at = [&](TimeNs t) {
        return interpolate(T_point, T_image, toSeconds(t - t_point) / toSeconds(t_image - t_point));
    };
    Colouriser col(*cal_);
    ASSERT_TRUE(col.addImage(render(planes, T_image, t_image, 1)));
    std::vector<Eigen::Vector3f> pts;
    std::vector<std::size_t> plane_of;
    samplePoints(planes, T_point, 17, pts, plane_of);
    const std::vector<TimeNs> times(pts.size(), t_point);
    const ColourResult r = col.colourise(pts, times, pose_at);
    EXPECT_GT(r.coloured, pts.size() * 8 / 10);
    std::size_t bad = 0;
    for (std::size_t i = 0; i < pts.size(); ++i)
        if (r.valid(i) && colourError(r.rgb[i], test::wavePattern(pts[i].x(), pts[i].y())) > 2.5)
            ++bad;
    EXPECT_EQ(bad, 0u);
    // The test can fail: projecting with the point's pose instead puts colours 12 cm off.
    const ColourResult wrong = col.colourise(pts, times, [&](TimeNs) { return T_point; });
    std::size_t bad_wrong = 0;
    for (std::size_t i = 0; i < pts.size(); ++i)
        if (wrong.valid(i) &&
            colourError(wrong.rgb[i], test::wavePattern(pts[i].x(), pts[i].y())) > 2.5)
            ++bad_wrong;
    EXPECT_GT(bad_wrong, wrong.coloured / 2);
}

TEST_F(ColouriserTest, FallsBackToTheOtherBracketingImage) {
    const std::vector<TexturedPlane> planes{{3.0, -100, 100, -100, 100, test::wavePattern}};
    const Eigen::Isometry3d T0 = pose(0, {0, 0, 0});
    const Eigen::Isometry3d T1 = pose(30, {0, 0, 0});  // turned away by 30 degrees
    const auto pose_at = [&](TimeNs t) { return t < 150 * kMs ? T0 : T1; };
    Colouriser col(*cal_);
    ASSERT_TRUE(col.addImage(render(planes, T1, 200 * kMs, 2)));
    ASSERT_TRUE(col.addImage(render(planes, T0, 0, 1)));  // out of order is fine within the buffer
    // A point at the left edge of the first view is closest in time to frame 2, which no longer
    // sees it: it takes frame 1's colour. A point in both views takes frame 2's (closest).
    const Eigen::Vector3f left(-1.5f, 0.3f, 3.0f), centre(0.5f, 0.1f, 3.0f);
    const std::vector<Eigen::Vector3f> pts{left, centre};
    const std::vector<TimeNs> times{150 * kMs, 150 * kMs};
    const ColourResult r = col.colourise(pts, times, pose_at);
    ASSERT_TRUE(r.valid(0)) << toString(r.status[0]);
    ASSERT_TRUE(r.valid(1)) << toString(r.status[1]);
    EXPECT_EQ(r.image_sequence[0], 1u);
    EXPECT_EQ(r.image_sequence[1], 2u);
    EXPECT_LE(colourError(r.rgb[0], test::wavePattern(left.x(), left.y())), 2.5);
    EXPECT_LE(colourError(r.rgb[1], test::wavePattern(centre.x(), centre.y())), 2.5);
}

TEST_F(ColouriserTest, OccludedFarPlaneKeepsNoColour) {
    // A red-ish near board covers the left part of the view of a blue-green far wall.
    const auto red = [](double, double) { return Rgb{220, 40, 30}; };
    const auto far_col = [](double x, double y) {
        return Rgb{30, 120 + 60 * std::sin(x * 3), 200 + 30 * std::cos(y * 2)};
    };
    const std::vector<TexturedPlane> planes{{1.8, -3, 0.0, -3, 3, red},
                                            {4.0, -100, 100, -100, 100, far_col}};
    const Eigen::Isometry3d T = pose(0, {0, 0, 0});
    Colouriser col(*cal_);
    ASSERT_TRUE(col.addImage(render(planes, T, 0, 1)));
    // Visible points of both planes, plus the far wall's points hidden behind the board (a laser
    // from another position would have seen them).
    std::vector<Eigen::Vector3f> pts;
    std::vector<std::size_t> plane_of;
    samplePoints(planes, T, 11, pts, plane_of);
    std::size_t hidden = 0;
    for (double x = -1.8; x < -0.3; x += 0.02) {
        for (double y = -1.0; y < 1.0; y += 0.02) {
            pts.emplace_back(static_cast<float>(x), static_cast<float>(y), 4.0f);
            plane_of.push_back(1);
            ++hidden;
        }
    }
    const std::vector<TimeNs> times(pts.size(), 0);
    const ColourResult r = col.colourise(pts, times, [&](TimeNs) { return T; });
    std::size_t far_wrong = 0, near_wrong = 0, far_ok = 0, hidden_occluded = 0;
    for (std::size_t i = 0; i < pts.size(); ++i) {
        const Rgb want = planes[plane_of[i]].colour(pts[i].x(), pts[i].y());
        if (r.valid(i)) {
            const bool ok = colourError(r.rgb[i], want) <= 2.5;
            if (plane_of[i] == 1) (ok ? far_ok : far_wrong)++;
            if (plane_of[i] == 0 && !ok) ++near_wrong;
        }
        if (i >= pts.size() - hidden && r.status[i] == ColourStatus::kOccluded) ++hidden_occluded;
    }
    std::printf(
        "[ measured ] occlusion: far points coloured right %zu, wrong %zu; hidden %zu of which "
        "occluded %zu\n",
        far_ok, far_wrong, hidden, hidden_occluded);
    EXPECT_EQ(far_wrong, 0u) << "far wall points took the near board's colour";
    EXPECT_EQ(near_wrong, 0u);
    EXPECT_EQ(hidden_occluded, hidden);
    EXPECT_GT(far_ok, 5000u);
    EXPECT_GT(r.count(ColourStatus::kColoured),
              pts.size() - hidden - pts.size() / 20);  // few visible points lost at the silhouette
}

TEST_F(ColouriserTest, BehindOutsideTooFarAndUntimedStayUncoloured) {
    const std::vector<TexturedPlane> planes{{3.0, -100, 100, -100, 100, test::wavePattern}};
    const Eigen::Isometry3d T = pose(0, {0, 0, 0});
    ColouriserConfig cfg;
    cfg.max_range_m = 10.0;
    Colouriser col(*cal_, cfg);
    ASSERT_TRUE(col.addImage(render(planes, T, 1000 * kMs, 1)));
    const std::vector<Eigen::Vector3f> pts{
        {0.2f, 0.1f, 3.0f},   // fine
        {0.2f, 0.1f, -3.0f},  // behind
        {9.0f, 0.0f, 3.0f},   // beside: outside the image
        {0.3f, 0.2f, 10.5f},  // beyond max_range_m
        {0.2f, 0.1f, 3.0f},   // no frame within max_time_offset_ns
        {std::nanf(""), 0.0f, 3.0f},
    };
    const std::vector<TimeNs> times{1000 * kMs, 1000 * kMs, 1000 * kMs,
                                    1000 * kMs, 2000 * kMs, 1000 * kMs};
    const ColourResult r = col.colourise(pts, times, [&](TimeNs) { return T; });
    EXPECT_EQ(r.status[0], ColourStatus::kColoured);
    EXPECT_EQ(r.status[1], ColourStatus::kBehind);
    EXPECT_EQ(r.status[2], ColourStatus::kOutside);
    EXPECT_EQ(r.status[3], ColourStatus::kTooFar);
    EXPECT_EQ(r.status[4], ColourStatus::kNoImage);
    EXPECT_FALSE(r.valid(5));
    EXPECT_EQ(r.coloured, 1u);
    for (std::size_t i = 1; i < pts.size(); ++i)
        EXPECT_EQ(r.rgb[i], (std::array<std::uint8_t, 3>{0, 0, 0}));
    // Mismatched spans: nothing coloured, no crash.
    const ColourResult m =
        col.colourise(pts, std::span<const TimeNs>(times).first(2), [&](TimeNs) { return T; });
    EXPECT_EQ(m.coloured, 0u);
    EXPECT_EQ(m.size(), pts.size());
}

TEST_F(ColouriserTest, BufferKeepsTheNewestFramesAndRejectsBadOnes) {
    ColouriserConfig cfg;
    cfg.max_images = 3;
    Colouriser col(*cal_, cfg);
    Image yuyv;
    yuyv.format = PixelFormat::kYuyv;
    yuyv.width = 1600;
    yuyv.height = 1200;
    yuyv.stride_bytes = 3200;
    for (int k = 0; k < 5; ++k) {
        yuyv.t_host = k * 200 * kMs;
        yuyv.sequence = static_cast<std::uint32_t>(k);
        yuyv.data.assign(3200u * 1200u, 128);  // mid grey: Y = U = V = 128
        // The colouriser takes decoded frames only; the camera driver decodes.
        EXPECT_FALSE(col.addImage(yuyv).isOk());
        Result<Image> bgr = camera::toBgr(yuyv);
        ASSERT_TRUE(bgr.isOk()) << bgr.status().message();
        ASSERT_TRUE(col.addImage(*bgr));
    }
    EXPECT_EQ(col.imageCount(), 3u);
    EXPECT_EQ(col.oldestImageTime(), 400 * kMs);
    EXPECT_EQ(col.newestImageTime(), 800 * kMs);
    // YUYV decoded once to BGR: a point sees mid grey.
    const std::vector<Eigen::Vector3f> pts{{0.0f, 0.0f, 2.0f}};
    const std::vector<TimeNs> times{800 * kMs};
    const ColourResult r =
        col.colourise(pts, times, [](TimeNs) { return Eigen::Isometry3d::Identity(); });
    ASSERT_TRUE(r.valid(0));
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(r.rgb[0][static_cast<std::size_t>(c)], 128, 3);

    Image grey = *camera::toBgr(yuyv);
    grey.t_host = 100 * kMs;  // older than the full buffer
    Status s = col.addImage(grey);
    EXPECT_FALSE(s.isOk());
    EXPECT_NE(s.message().find("older"), std::string::npos) << s.message();
    grey.t_host = 900 * kMs;
    grey.width = 640;
    grey.stride_bytes = 640 * 3;
    s = col.addImage(grey);
    EXPECT_FALSE(s.isOk());
    EXPECT_NE(s.message().find("1600x1200"), std::string::npos) << s.message();
    Image jpeg;
    jpeg.format = PixelFormat::kMjpeg;
    jpeg.width = 1600;
    jpeg.height = 1200;
    jpeg.t_host = 1000 * kMs;
    jpeg.data = {0xFF, 0xD8, 0x00, 0x01, 0x02};
    s = col.addImage(jpeg);
    EXPECT_FALSE(s.isOk());
    EXPECT_NE(s.message().find("colour frame"), std::string::npos) << s.message();
    EXPECT_NE(s.message().find("camera::toBgr"), std::string::npos) << s.message();
    EXPECT_FALSE(camera::toBgr(jpeg).isOk());  // and the driver's decoder names the bad JPEG
    EXPECT_EQ(col.imageCount(), 3u);
    EXPECT_EQ(col.newestImageTime(), 800 * kMs);
}

}  // namespace
}  // namespace handscan::colour
