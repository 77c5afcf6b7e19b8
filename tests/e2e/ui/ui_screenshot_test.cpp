// handscan-ui under Xvfb + Mesa against a published live map: the screenshot is not blank, bright
// points land on the pixels that an independent projection predicts, the status texts it drew
// (sidecar JSON written with the screenshot: the very strings passed to ImGui) match the status
// block, and the UI copes with no pipeline and with a pipeline restart.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <thread>

#include "child_process.hpp"
#include "handscan/core/json.hpp"
#include "handscan/shm/live_map_writer.hpp"
#include "handscan/shm/text_field.hpp"

namespace handscan::e2e {
namespace {

namespace fs = std::filesystem;

const std::string kUi = std::string(HANDSCAN_BINARY_DIR) + "/ui/handscan-ui";

std::string regionName(const std::string& tag) {
    return "/handscan-e2e-" + tag + "-" + std::to_string(::getpid());
}

std::string readText(const fs::path& p) {
    std::ifstream in(p);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

class UiScreenshot : public ::testing::Test {
protected:
    void SetUp() override {
        if (const std::string why = ensureDisplay(); !why.empty()) GTEST_SKIP() << why;
        if (!fs::exists(kUi)) GTEST_SKIP() << kUi << " not built (HANDSCAN_WITH_UI=OFF)";
        dir_ = fs::temp_directory_path() /
               ("handscan-ui-e2e-" + std::to_string(::getpid()) + "-" +
                ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::create_directories(dir_);
    }
    void TearDown() override {
        std::error_code ec;
        if (!HasFailure()) fs::remove_all(dir_, ec);  // keep the evidence of a failure
    }
    fs::path dir_;
};

// A projection computed here, independently of the UI's code: gluLookAt + gluPerspective.
struct Projector {
    Eigen::Vector3d eye, target;
    double fov_y_deg;
    double vx, vy, vw, vh;  // viewport, pixels from the top-left

    // Continuous pixel coordinates (column, row) of a world point.
    Eigen::Vector2d pixel(const Eigen::Vector3d& p) const {
        const Eigen::Vector3d f = (target - eye).normalized();
        const Eigen::Vector3d s = f.cross(Eigen::Vector3d::UnitZ()).normalized();
        const Eigen::Vector3d u = s.cross(f);
        const Eigen::Vector3d d = p - eye;
        const double xe = s.dot(d), ye = u.dot(d), depth = f.dot(d);
        const double t = std::tan(fov_y_deg * M_PI / 360.0);
        const double aspect = vw / vh;
        const double ndc_x = xe / (depth * t * aspect), ndc_y = ye / (depth * t);
        return {vx + (ndc_x + 1) / 2 * vw, vy + (1 - ndc_y) / 2 * vh};
    }
};

// The tests' camera (--camera-eye 0,-10,0 --camera-target 0,0,0 --fov 60) in the viewport the
// UI reported.
Projector fromTenMetresSouth(const Json& viewport) {
    return {{0, -10, 0},
            {0, 0, 0},
            60.0,
            viewport[0].get<double>(),
            viewport[1].get<double>(),
            viewport[2].get<double>(),
            viewport[3].get<double>()};
}

struct Bright {
    Eigen::Vector3d p;
    cv::Vec3b bgr;
};

shm::StatusBlock knownStatus() {
    shm::StatusBlock s;
    s.t_ns = 1;
    s.sensor_count = 3;
    shm::setText(s.sensors[0].name, "hokuyo");
    s.sensors[0].connected = 1;
    s.sensors[0].rate_hz = 40.0f;
    s.sensors[0].expected_rate_hz = 40.0f;
    shm::setText(s.sensors[1].name, "xsens");
    s.sensors[1].connected = 1;
    s.sensors[1].rate_hz = 200.0f;
    s.sensors[1].expected_rate_hz = 200.0f;
    shm::setText(s.sensors[2].name, "colour-cam");
    s.sensors[2].connected = 0;
    shm::setText(s.sensors[2].last_error, "/dev/video2: No such device");
    s.module_count = 2;
    shm::setText(s.modules[0].name, "vio");
    s.modules[0].state = static_cast<std::uint8_t>(shm::ModuleState::kActive);
    shm::setText(s.modules[1].name, "scan-match");
    s.modules[1].state = static_cast<std::uint8_t>(shm::ModuleState::kActive);
    s.modules[1].degenerate_dof_mask = 0b001000;
    s.scan_state = static_cast<std::uint8_t>(shm::ScanState::kScanning);
    s.elapsed_s = 125.4;
    s.distance_m = 12.34;
    s.point_count = 1234567;
    s.free_storage_bytes = 12ull << 30;
    s.total_storage_bytes = 58ull << 30;
    s.linear_speed_mps = 0.5f;
    s.camera_brightness = 110.0f;
    shm::setText(s.message, "e2e test");
    return s;
}

TEST_F(UiScreenshot, PointsLandWhereTheProjectionSaysAndStatusMatchesTheBlock) {
    const std::string name = regionName("proj");
    shm::WriterOptions wo;
    wo.name = name;
    wo.map_capacity_points = 1000;
    auto writer = shm::LiveMapWriter::create(wo);
    ASSERT_TRUE(writer.isOk()) << writer.status().message();
    // Five bright points on the plane y = 0, in pure colours the map's dark background lacks.
    const std::vector<Bright> bright = {
        {{0, 0, 0}, {0, 0, 255}},    {{2, 0, 1}, {0, 255, 0}},    {{-2, 0, -1}, {255, 0, 0}},
        {{3, 0, -2}, {0, 255, 255}}, {{-3, 0, 2}, {255, 255, 0}},
    };
    std::vector<shm::DisplayPoint> pts;
    for (const Bright& b : bright) {
        shm::DisplayPoint d;
        d.x_m = static_cast<float>(b.p.x());
        d.y_m = static_cast<float>(b.p.y());
        d.z_m = static_cast<float>(b.p.z());
        d.r = b.bgr[2];
        d.g = b.bgr[1];
        d.b = b.bgr[0];
        pts.push_back(d);
    }
    ASSERT_TRUE((*writer)->appendPoints(pts).isOk());
    (*writer)->setStatus(knownStatus());
    shm::PoseRecord pose;  // behind the camera: the device marker stays out of the picture
    pose.position_m[1] = -30;
    pose.vio_dof_mask = 0b000111;
    pose.scan_dof_mask = 0b110110;
    (*writer)->publishPose(pose);

    const fs::path png = dir_ / "out.png";
    const ChildResult r = runChild(
        {kUi,   "--shm-name",   name,      "--screenshot",    png.string(), "--wait-points",
         "5",   "--timeout",    "20",      "--width",         "1280",       "--height",
         "800", "--camera-eye", "0,-10,0", "--camera-target", "0,0,0",      "--fov",
         "60",  "--point-size", "9"},
        60, [&] { (*writer)->heartbeat(); });
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const cv::Mat img = cv::imread(png.string(), cv::IMREAD_COLOR);
    ASSERT_FALSE(img.empty());
    ASSERT_EQ(img.cols, 1280);
    ASSERT_EQ(img.rows, 800);
    const std::string json = readText(dir_ / "out.json");
    const Json doc = Json::parse(json, nullptr, false);
    ASSERT_TRUE(doc.is_object()) << json;

    // The viewport the UI used (the layout: status bar on top, buttons on the right).
    ASSERT_TRUE(doc["view"]["viewport"].is_array() && doc["view"]["viewport"].size() == 4) << json;
    const Projector proj = fromTenMetresSouth(doc["view"]["viewport"]);
    EXPECT_GT(proj.vw, 600);
    EXPECT_GT(proj.vh, 400);

    // Not blank: the status bar and the buttons drew text and shapes; the view has the points.
    const cv::Vec3b background = img.at<cv::Vec3b>(static_cast<int>(proj.vy + proj.vh / 2) + 100,
                                                   static_cast<int>(proj.vx + 40));
    int differing = 0;
    for (int y = 0; y < img.rows; ++y) {
        for (int x = 0; x < img.cols; ++x)
            differing += cv::norm(img.at<cv::Vec3b>(y, x), background, cv::NORM_L1) > 30;
    }
    EXPECT_GT(differing, 20000) << "screenshot is (almost) blank";

    // Each bright point: the centroid of its colour near the predicted pixel is within a pixel.
    for (const Bright& b : bright) {
        const Eigen::Vector2d px = proj.pixel(b.p);
        SCOPED_TRACE("point (" + std::to_string(b.p.x()) + ", " + std::to_string(b.p.z()) +
                     ") predicted at (" + std::to_string(px.x()) + ", " + std::to_string(px.y()) +
                     ")");
        double sx = 0, sy = 0;
        int n = 0;
        for (int y = static_cast<int>(px.y()) - 20; y <= static_cast<int>(px.y()) + 20; ++y) {
            for (int x = static_cast<int>(px.x()) - 20; x <= static_cast<int>(px.x()) + 20; ++x) {
                if (x < 0 || y < 0 || x >= img.cols || y >= img.rows) continue;
                if (cv::norm(img.at<cv::Vec3b>(y, x), b.bgr, cv::NORM_L1) < 30) {
                    sx += x + 0.5;
                    sy += y + 0.5;
                    ++n;
                }
            }
        }
        EXPECT_GE(n, 49);  // a 9 px point sprite
        EXPECT_LE(n, 100);
        if (n > 0) {
            EXPECT_NEAR(sx / n, px.x(), 1.0);
            EXPECT_NEAR(sy / n, px.y(), 1.0);
        }
    }
    // Halfway between two points there is nothing.
    const Eigen::Vector2d mid = proj.pixel({1, 0, 0.5});
    EXPECT_LT(cv::norm(img.at<cv::Vec3b>(static_cast<int>(mid.y()), static_cast<int>(mid.x())),
                       background, cv::NORM_L1),
              30);

    // The status texts shown are the published block's values.
    const auto line = [](const char* text, const char* health) {
        return Json{{"text", text}, {"health", health}};
    };
    const auto listed = [&](const Json& l) {  // in the sensors, modules or warnings
        for (const char* list : {"sensors", "modules", "warnings"}) {
            for (const Json& e : doc[list])
                if (e == l) return true;
        }
        return false;
    };
    EXPECT_EQ(doc["scan_state"], "SCANNING") << json;
    EXPECT_EQ(doc["elapsed"], "02:05") << json;
    EXPECT_EQ(doc["distance"], "12.3 m") << json;
    EXPECT_EQ(doc["points"], "1,234,567 points") << json;
    EXPECT_EQ(doc["storage"], line("free 12.0 GiB of 58.0 GiB", "ok")) << json;
    EXPECT_EQ(doc["connection"], line("connected", "ok")) << json;
    EXPECT_EQ(doc["message"], "e2e test") << json;
    EXPECT_EQ(doc["dof"], Json({"vio", "vio", "vio", "imu", "scan", "scan"})) << json;
    EXPECT_EQ(doc["map"]["points_drawn"], 5) << json;
    for (const Json& expected :
         {line("hokuyo 40.0 Hz", "ok"), line("xsens 200.0 Hz", "ok"),
          line("colour-cam LOST", "error"),
          line("Sensor lost: colour-cam (/dev/video2: No such device)", "error"),
          line("scan-match degenerate tx", "warning")}) {
        EXPECT_TRUE(listed(expected)) << "missing " << expected.dump() << " in\n" << json;
    }
    EXPECT_NE(json.find("Laser degenerate along tx"), std::string::npos);
}

// A continued scan's change cells (shm::ChangeReport) over the map: each cube where an
// independent projection puts it, tinted with its kind's colour (appeared orange, vanished light
// blue) and its edges in that colour, nothing between them, and the legend's counts in the
// status texts. Without the cells drawn, the tints and the edges are not there.
TEST_F(UiScreenshot, ChangeCellsAreDrawnInTheirKindsColoursWithTheirCounts) {
    const std::string name = regionName("changes");
    shm::WriterOptions wo;
    wo.name = name;
    wo.map_capacity_points = 100;
    auto writer = shm::LiveMapWriter::create(wo);
    ASSERT_TRUE(writer.isOk()) << writer.status().message();
    std::vector<shm::DisplayPoint> pts;  // a row of grey points above the cells
    for (int i = 0; i < 9; ++i)
        pts.push_back({static_cast<float>(i - 4), 0.0f, 2.5f, 150, 150, 150, 150});
    ASSERT_TRUE((*writer)->appendPoints(pts).isOk());
    shm::StatusBlock status = knownStatus();
    status.localization = static_cast<std::uint8_t>(shm::LocalizationState::kLocked);
    (*writer)->setStatus(status);
    shm::PoseRecord pose;  // behind the camera
    pose.position_m[1] = -30;
    (*writer)->publishPose(pose);
    shm::ChangeReport report;
    report.cell_m = 1.0f;
    report.appeared = 1;
    report.vanished = 1;
    report.count = 2;
    report.cells[0] = {-2.0f, 0.0f, 0.0f, 40,
                       static_cast<std::uint8_t>(shm::ChangeKind::kAppeared)};
    report.cells[1] = {2.0f, 0.0f, 0.0f, 25, static_cast<std::uint8_t>(shm::ChangeKind::kVanished)};
    (*writer)->setChanges(report);

    const fs::path png = dir_ / "changes.png";
    const ChildResult r =
        runChild({kUi, "--shm-name", name, "--screenshot", png.string(), "--wait-points", "9",
                  "--timeout", "20", "--width", "1280", "--height", "800", "--camera-eye",
                  "0,-10,0", "--camera-target", "0,0,0", "--fov", "60"},
                 60, [&] { (*writer)->heartbeat(); });
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const cv::Mat img = cv::imread(png.string(), cv::IMREAD_COLOR);
    ASSERT_FALSE(img.empty());
    const std::string json = readText(dir_ / "changes.json");
    const Json doc = Json::parse(json, nullptr, false);
    ASSERT_TRUE(doc.is_object()) << json;
    ASSERT_TRUE(doc["view"]["viewport"].is_array() && doc["view"]["viewport"].size() == 4) << json;
    const Projector proj = fromTenMetresSouth(doc["view"]["viewport"]);

    struct Expected {
        Eigen::Vector3d centre;
        cv::Vec3b bgr;  // the kind's colour
        bool appeared;
    };
    for (const Expected& e :
         {Expected{{-2, 0, 0}, {0, 140, 255}, true}, Expected{{2, 0, 0}, {255, 190, 0}, false}}) {
        SCOPED_TRACE(e.appeared ? "appeared cell" : "vanished cell");
        // Inside the cube's picture (its front face spans +-0.5 m at 9.5 m: about +-30 px), every
        // pixel is tinted: the kind's dominant channel well above the background's and above
        // the other kind's.
        const Eigen::Vector2d c = proj.pixel(e.centre);
        int tinted = 0, n = 0;
        for (int dy = -12; dy <= 12; ++dy) {
            for (int dx = -12; dx <= 12; ++dx) {
                const cv::Vec3b p =
                    img.at<cv::Vec3b>(static_cast<int>(c.y()) + dy, static_cast<int>(c.x()) + dx);
                const int red = p[2], blue = p[0];
                tinted +=
                    e.appeared ? (red > 100 && red > blue + 60) : (blue > 100 && blue > red + 60);
                ++n;
            }
        }
        EXPECT_EQ(tinted, n) << "at (" << c.x() << ", " << c.y() << ")";
        // The edges in the kind's own colour: the cube's outline around its picture.
        const Eigen::Vector2d lo = proj.pixel(e.centre + Eigen::Vector3d(-0.5, -0.5, 0.5));
        const Eigen::Vector2d hi = proj.pixel(e.centre + Eigen::Vector3d(0.5, -0.5, -0.5));
        int edge = 0;
        for (int y = static_cast<int>(lo.y()) - 3; y <= static_cast<int>(hi.y()) + 3; ++y) {
            for (int x = static_cast<int>(lo.x()) - 3; x <= static_cast<int>(hi.x()) + 3; ++x)
                edge += cv::norm(img.at<cv::Vec3b>(y, x), e.bgr, cv::NORM_L1) < 40;
        }
        EXPECT_GT(edge, 100) << "outline of " << hi.x() - lo.x() << " px";
    }
    // Between the two cells the map's background only.
    const Eigen::Vector2d mid = proj.pixel({0, 0, 0});
    const cv::Vec3b between =
        img.at<cv::Vec3b>(static_cast<int>(mid.y()), static_cast<int>(mid.x()));
    EXPECT_LT(std::max({between[0], between[1], between[2]}), 60) << between;

    EXPECT_EQ(doc["changes"]["cells_drawn"], 2) << json;
    EXPECT_EQ(doc["changes"]["appeared"], 1) << json;
    EXPECT_EQ(doc["changes"]["vanished"], 1) << json;
    EXPECT_EQ(doc["changes"]["text"],
              "CHANGED SINCE THE EARLIER SCAN: 1 appeared (orange), 1 vanished (blue)")
        << json;
}

TEST_F(UiScreenshot, NoPipelineExitsNonZeroWithAClearMessage) {
    const fs::path png = dir_ / "none.png";
    const ChildResult r = runChild(
        {kUi, "--shm-name", regionName("absent"), "--screenshot", png.string(), "--timeout", "1.5"},
        30);
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.output.find("no live map appeared in shared memory"), std::string::npos)
        << r.output;
    EXPECT_NE(r.output.find("waiting for pipeline"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(png));
}

TEST_F(UiScreenshot, FollowsAPipelineThatRestarts) {
    // The UI starts first (pipeline absent), sees a first pipeline's map, then a second pipeline
    // replaces it: the screenshot must show the second map only.
    const std::string name = regionName("restart");
    const fs::path png = dir_ / "restart.png";
    ChildProcess ui({kUi, "--shm-name", name, "--screenshot", png.string(), "--wait-points", "40",
                     "--timeout", "20", "--camera", "top-down"},
                    (dir_ / "ui.log").string());
    std::this_thread::sleep_for(std::chrono::milliseconds(700));
    ASSERT_TRUE(ui.running()) << readText(dir_ / "ui.log");
    const auto grid = [](int n, float z) {
        std::vector<shm::DisplayPoint> v;
        for (int i = 0; i < n; ++i)
            v.push_back(
                {static_cast<float>(i % 8), static_cast<float>(i / 8), z, 255, 255, 255, 255});
        return v;
    };
    shm::WriterOptions wo;
    wo.name = name;
    wo.map_capacity_points = 100;
    {
        auto first = shm::LiveMapWriter::create(wo);
        ASSERT_TRUE(first.isOk());
        ASSERT_TRUE((*first)->appendPoints(grid(30, 0)).isOk());
        (*first)->setStatus(knownStatus());
        std::this_thread::sleep_for(std::chrono::milliseconds(800));  // the UI reads the first map
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    auto second = shm::LiveMapWriter::create(wo);
    ASSERT_TRUE(second.isOk());
    (*second)->setStatus(knownStatus());
    ASSERT_TRUE((*second)->appendPoints(grid(40, 1)).isOk());
    const ChildResult r = ui.wait(30, [&] { (*second)->heartbeat(); });
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const std::string json = readText(dir_ / "restart.json");
    EXPECT_EQ(Json::parse(json, nullptr, false)["map"]["points_drawn"], 40) << json;  // not 70
}

}  // namespace
}  // namespace handscan::e2e
