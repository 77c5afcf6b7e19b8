// "Continue scan" on the touch screen, end to end (section 9, issue 14): handscan-pipeline (in
// this process, its devices faked behind their real transports: the rig's laser in a 6 x 4 m
// room, the IMU at rest) scans and stops; handscan-ui (a child process under Xvfb + Mesa) is
// driven by X pointer events from xdotool as a finger would. CONTINUE SCAN opens the placement
// on the earlier map (CANCEL closes it); a continue command with a start 30 m off begins a scan
// that finds no place and says so; PLACE ME, a press and a drag 1 m and 15 deg off where the
// earlier scan started (as an operator might), I AM HERE: locked. The status block says
// searching, not locked, locked, and the UI shows it; the new scan's journal holds its poses in
// the earlier scan's frame, names the earlier scan as its prior map, and its points lie on the
// earlier map.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <set>
#include <sstream>
#include <thread>
#include <tuple>

#include "child_process.hpp"
#include "daemon_rig.hpp"
#include "handscan/core/json.hpp"
#include "handscan/journal/journal_reader.hpp"
#include "handscan/pipeline_daemon/pipeline_daemon.hpp"
#include "handscan/prior_map/feature_map_file.hpp"
#include "handscan/prior_map/prior_map_loader.hpp"

namespace handscan::pipeline_daemon::test {
namespace {

const std::string kUi = std::string(HANDSCAN_BINARY_DIR) + "/ui/handscan-ui";

// Button centres in a 1280 x 800 window (ui/src/screen_layout.hpp: 110 px status bar, 260 px
// button column; the first button 83 px high, the next ones 64 px, 4 px apart): START SCAN (and
// START HERE while placing), then EXPORT, NEW SCAN, CONTINUE SCAN.
constexpr int kButtonX = 1150;
constexpr int kFirstButtonY = 159;
constexpr int kExportY = 237;
constexpr int kContinueY = kExportY + 2 * (64 + 4);
// While placing: START HERE (83 px, where START SCAN is), FROM ITS START, CANCEL.
constexpr int kCancelY = kFirstButtonY + 2 * (83 + 4);

Json readJson(const fs::path& path) {
    std::ifstream in(path);
    std::stringstream ss;
    ss << in.rdbuf();
    return Json::parse(ss.str(), nullptr, false);
}

bool waitFor(const std::function<bool()>& condition, double seconds) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < end) {
        if (condition()) return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return condition();
}

Eigen::Isometry3d firstPose(const fs::path& scan_dir) {
    auto j = journal::JournalReader::open((scan_dir / "journal.hsj").string());
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    if (!j.isOk() || j->summary().trajectory.empty()) return T;
    const journal::TrajectoryPose& p = j->summary().trajectory.front();
    T.linear() = Eigen::Quaterniond(p.qw, p.qx, p.qy, p.qz).normalized().toRotationMatrix();
    T.translation() = Eigen::Vector3d(p.x, p.y, p.z);
    return T;
}

// Window pixel of map point p under the UI's camera as its status JSON reports it.
std::optional<Eigen::Vector2d> pixelOf(const Json& ui, const Eigen::Vector3d& p) {
    if (!ui.is_object() || !ui.contains("view")) return std::nullopt;
    const Json& v = ui["view"];
    Eigen::Matrix4f vp;
    for (int i = 0; i < 16; ++i) vp.data()[i] = v["view_proj_col_major"][i].get<float>();
    const Eigen::Vector4f c = vp * p.cast<float>().homogeneous();
    if (c.w() <= 0) return std::nullopt;
    const double x = v["viewport"][0], y = v["viewport"][1], w = v["viewport"][2],
                 h = v["viewport"][3];
    return Eigen::Vector2d(x + (c.x() / c.w() + 1.0) / 2.0 * w,
                           y + (1.0 - c.y() / c.w()) / 2.0 * h);
}

// The share of `later`'s points (every 10th) with a point of `earlier` in their 5 cm voxel or a
// neighbouring one: the two maps coincide where they see the same walls.
double shareOnEarlier(const journal::JournalReader& earlier, const journal::JournalReader& later) {
    const auto key = [](float x, float y, float z) {
        const auto c = [](float v) { return static_cast<std::int64_t>(std::floor(v / 0.05f)); };
        return std::tuple{c(x), c(y), c(z)};
    };
    std::set<std::tuple<std::int64_t, std::int64_t, std::int64_t>> cells;
    (void)earlier.forEachPoints([&](std::span<const journal::MapPoint> pts) {
        for (const journal::MapPoint& p : pts) cells.insert(key(p.x, p.y, p.z));
    });
    std::uint64_t n = 0, on = 0, i = 0;
    (void)later.forEachPoints([&](std::span<const journal::MapPoint> pts) {
        for (const journal::MapPoint& p : pts) {
            if (i++ % 10 != 0) continue;
            ++n;
            const auto [x, y, z] = key(p.x, p.y, p.z);
            bool hit = false;
            for (int dx = -1; dx <= 1 && !hit; ++dx)
                for (int dy = -1; dy <= 1 && !hit; ++dy)
                    for (int dz = -1; dz <= 1 && !hit; ++dz)
                        hit = cells.count({x + dx, y + dy, z + dz}) > 0;
            on += hit ? 1 : 0;
        }
    });
    return n > 0 ? static_cast<double>(on) / static_cast<double>(n) : 0.0;
}

double headingOf(const Eigen::Matrix3d& R) { return std::atan2(R(1, 0), R(0, 0)); }

TEST(ContinueScan, OperatorPlacesTheStartOnTheEarlierMapAndTheNewScanLocksOnIt) {
    if (const std::string why = e2e::ensureDisplay(); !why.empty()) GTEST_SKIP() << why;
    if (!fs::exists("/usr/bin/xdotool"))
        GTEST_SKIP() << "xdotool not installed (apt install xdotool)";
    if (!fs::exists(kUi)) GTEST_SKIP() << kUi << " not built";
    DaemonRig rig("continue");
    DaemonOptions o;
    o.device_config = rig.deviceYaml();
    o.calibration = DaemonRig::calibrationYaml();
    o.shm_name = rig.shmName();
    o.map_capacity_points = 1 << 18;
    PipelineDaemon daemon(o);
    ASSERT_TRUE(daemon.open().isOk());
    DaemonThread running(daemon);
    ASSERT_TRUE(rig.waitStatus(
        [](const shm::StatusBlock& s) {
            return sensorConnected(s, "hokuyo") && sensorConnected(s, "xsens") &&
                   sensorConnected(s, "encoder");
        },
        10.0))
        << "devices did not come up";

    // 1. The earlier scan: a few seconds of sweeps, stopped (its feature map written).
    ASSERT_EQ(rig.command(shm::CommandType::kStartScan).state,
              static_cast<std::uint32_t>(shm::CommandState::kDone));
    ASSERT_TRUE(
        rig.waitStatus([](const shm::StatusBlock& s) { return s.point_count > 20000; }, 30.0))
        << "the first scan registered too few points";
    std::this_thread::sleep_for(std::chrono::seconds(3));
    ASSERT_EQ(rig.command(shm::CommandType::kStopScan).state,
              static_cast<std::uint32_t>(shm::CommandState::kDone));
    ASSERT_EQ(rig.scanDirs().size(), 1u);
    const fs::path scan1 = rig.scanDirs()[0];
    ASSERT_TRUE(fs::exists(scan1 / prior_map::kFeatureMapFile));
    ASSERT_TRUE(rig.waitStatus([](const shm::StatusBlock& s) { return s.can_continue == 1; }, 5.0));
    const Eigen::Isometry3d start1 = firstPose(scan1);

    // 2. The UI, its status JSON rewritten while it runs.
    const fs::path ui_json = rig.dir() / "ui.json";
    e2e::ChildProcess ui({kUi, "--shm-name", rig.shmName(), "--width", "1280", "--height", "800",
                          "--status-json", ui_json.string(), "--max-seconds", "150"},
                         (rig.dir() / "ui.log").string());
    const e2e::ChildResult found =
        e2e::runChild({"xdotool", "search", "--sync", "--name", "^handscan$"}, 20);
    ASSERT_EQ(found.exit_code, 0) << found.output;
    const std::string window = found.output.substr(0, found.output.find('\n'));
    const auto xdo = [&](std::vector<std::string> args) {
        args.insert(args.begin(), "xdotool");
        const e2e::ChildResult r = e2e::runChild(args, 10);
        ASSERT_EQ(r.exit_code, 0) << r.output;
    };
    const auto moveTo = [&](double x, double y) {
        xdo({"mousemove", "--window", window, std::to_string(std::lround(x)),
             std::to_string(std::lround(y))});
        std::this_thread::sleep_for(std::chrono::milliseconds(300));  // hover, as a finger lands
    };
    ASSERT_TRUE(waitFor(
        [&] {
            const Json j = readJson(ui_json);
            return j.is_object() && j["map"]["track_points"].get<int>() > 0 &&
                   j["can_continue"].get<bool>();
        },
        20))
        << "the UI did not show the stopped scan";

    // Opens the placement with the button at `button_y`, presses at map point `place` and
    // drags 1.5 m along `heading` (the view's camera from the UI's status JSON), releases;
    // checks the pose placed against them and returns it.
    const double heading1 = headingOf(start1.linear());
    const auto placeOnMap = [&](int button_y, const Eigen::Vector3d& place, double heading) {
        moveTo(kButtonX, button_y);
        xdo({"click", "1"});
        Json shown;
        EXPECT_TRUE(waitFor(
            [&] {
                shown = readJson(ui_json);
                return shown.is_object() && shown["placement"]["active"].get<bool>() &&
                       shown["view"]["camera"] == "top-down";
            },
            10))
            << "the button did not open the placement";
        std::this_thread::sleep_for(std::chrono::milliseconds(500));
        shown = readJson(ui_json);
        const Eigen::Vector3d ahead =
            place + 1.5 * Eigen::Vector3d(std::cos(heading), std::sin(heading), 0);
        const auto at = pixelOf(shown, place);
        const auto to = pixelOf(shown, ahead);
        EXPECT_TRUE(at && to);
        if (!at || !to) return;
        moveTo(at->x(), at->y());
        xdo({"mousedown", "1"});
        std::this_thread::sleep_for(std::chrono::milliseconds(300));
        moveTo((at->x() + to->x()) / 2, (at->y() + to->y()) / 2);
        moveTo(to->x(), to->y());
        xdo({"mouseup", "1"});
        EXPECT_TRUE(
            waitFor([&] { return readJson(ui_json)["placement"]["placed"].get<bool>(); }, 5))
            << "the press placed nothing";
        const std::string placed = readJson(ui_json)["placement"]["pose"].get<std::string>();
        auto placed_pose = prior_map::parsePose(placed);  // as the daemon reads it
        EXPECT_TRUE(placed_pose.isOk()) << placed_pose.status().message();
        if (!placed_pose.isOk()) return;
        // A pixel of the top-down view is a few centimetres: the tap lands within 10 cm, the
        // heading within 3 degrees, the height that of the earlier path.
        const Eigen::Vector3d placed_at = placed_pose->translation();
        EXPECT_LT((placed_at - place).head<2>().norm(), 0.1) << placed;
        EXPECT_NEAR(placed_at.z(), start1.translation().z(), 0.05) << placed;
        EXPECT_LT(std::abs(std::remainder(headingOf(placed_pose->linear()) - heading, 2 * M_PI)),
                  3.0 * M_PI / 180)
            << placed;
        moveTo(kButtonX, kFirstButtonY);  // START HERE / I AM HERE
        xdo({"click", "1"});
    };

    // 3. CONTINUE SCAN opens the placement (CANCEL closes it); the continue command then comes
    // with a pose 30 m off, where the earlier map has nothing (this box of a room matches itself
    // shifted along its walls, so a start a few metres off can lock wrongly - a real limit of
    // the search): the continued scan searches, finds no place, and says so.
    moveTo(kButtonX, kContinueY);
    xdo({"click", "1"});
    ASSERT_TRUE(waitFor([&] { return readJson(ui_json)["placement"]["active"].get<bool>(); }, 10))
        << "CONTINUE SCAN did not open the placement";
    moveTo(kButtonX, kCancelY);
    xdo({"click", "1"});
    ASSERT_TRUE(waitFor([&] { return !readJson(ui_json)["placement"]["active"].get<bool>(); }, 5))
        << "CANCEL did not close the placement";
    const Eigen::Quaterniond q1(start1.linear());
    char far[160];
    std::snprintf(far, sizeof far, "pose=%.3f,%.3f,%.3f,%.6f,%.6f,%.6f,%.6f",
                  start1.translation().x() + 30.0, start1.translation().y(),
                  start1.translation().z(), q1.x(), q1.y(), q1.z(), q1.w());
    ASSERT_EQ(rig.command(shm::CommandType::kContinueScan, far).state,
              static_cast<std::uint32_t>(shm::CommandState::kDone));
    ASSERT_TRUE(rig.waitStatus(
        [](const shm::StatusBlock& s) {
            return s.scan_state == static_cast<std::uint8_t>(shm::ScanState::kScanning) &&
                   s.localization != static_cast<std::uint8_t>(shm::LocalizationState::kNone);
        },
        15.0))
        << "the continue command did not start a continued scan";
    ASSERT_TRUE(rig.waitStatus(
        [](const shm::StatusBlock& s) {
            return s.localization == static_cast<std::uint8_t>(shm::LocalizationState::kNotLocked);
        },
        30.0))
        << "placed 30 m off, the scan did not say it found no place: "
        << readJson(ui_json)["localization"].dump() << " " << readJson(ui_json)["message"].dump();
    EXPECT_TRUE(waitFor(
        [&] {
            return readJson(ui_json)["localization"]["text"].get<std::string>() ==
                   "NOT LOCKED: walk to where the earlier scan started";
        },
        5))
        << "the UI does not say it is not locked";

    // 4. PLACE ME, roughly right this time: 1 m and 15 deg off where the earlier scan started
    // (the target); I AM HERE; the lock takes the rest out.
    placeOnMap(kContinueY, start1.translation() + Eigen::Vector3d(0.8, 0.6, 0.0),
               heading1 + 15.0 * M_PI / 180.0);
    ASSERT_FALSE(::testing::Test::HasFailure());
    const auto sent = std::chrono::steady_clock::now();
    auto locked = rig.waitStatus(
        [](const shm::StatusBlock& s) {
            return s.localization == static_cast<std::uint8_t>(shm::LocalizationState::kLocked);
        },
        40.0);
    const double lock_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - sent).count();
    ASSERT_TRUE(locked) << "the continued scan did not lock on the earlier one";
    std::cout << "continue scan: locked " << lock_s << " s after I AM HERE\n";
    EXPECT_TRUE(waitFor(
        [&] {
            return readJson(ui_json)["localization"]["text"].get<std::string>() ==
                   "LOCKED ON THE EARLIER SCAN";
        },
        5))
        << "the UI does not say it locked";
    ASSERT_TRUE(
        rig.waitStatus([](const shm::StatusBlock& s) { return s.point_count > 20000; }, 20.0))
        << "nothing merged after the lock";
    ASSERT_EQ(rig.command(shm::CommandType::kStopScan).state,
              static_cast<std::uint32_t>(shm::CommandState::kDone));
    ui.terminate();
    const Status stopped = running.stop();
    EXPECT_TRUE(stopped.isOk()) << stopped.message();

    // 5. The new scan is in the earlier one's frame: at rest where the earlier one stood, its
    // poses where the earlier one's are (not where the rough placement put them); its metadata
    // names the earlier scan; and its points lie on the earlier scan's points (the same walls,
    // not a copy turned or shifted).
    ASSERT_EQ(rig.scanDirs().size(), 2u);
    const fs::path scan2 = rig.scanDirs()[1];
    auto j2 = journal::JournalReader::open((scan2 / "journal.hsj").string());
    ASSERT_TRUE(j2.isOk()) << j2.status().message();
    const Json meta = Json::parse(j2->summary().metadata_json, nullptr, false);
    ASSERT_TRUE(meta.is_object() && meta.contains("prior_map")) << j2->summary().metadata_json;
    EXPECT_EQ(fs::path(meta["prior_map"].get<std::string>()), scan1);
    const Eigen::Isometry3d start2 = firstPose(scan2);
    EXPECT_LT((start2.translation() - start1.translation()).norm(), 0.03)
        << start2.translation().transpose() << " vs " << start1.translation().transpose();
    EXPECT_LT(Eigen::AngleAxisd(start1.linear().transpose() * start2.linear()).angle(),
              0.5 * M_PI / 180);
    EXPECT_GT(j2->summary().points, 20000u);
    auto j1 = journal::JournalReader::open((scan1 / "journal.hsj").string());
    ASSERT_TRUE(j1.isOk());
    const double on = shareOnEarlier(*j1, *j2);
    std::cout << "continue scan: " << 100 * on
              << " % of the new points within 5 cm of the earlier\n";
    EXPECT_GT(on, 0.9) << "the new scan's points are not on the earlier map";
}

}  // namespace
}  // namespace handscan::pipeline_daemon::test
