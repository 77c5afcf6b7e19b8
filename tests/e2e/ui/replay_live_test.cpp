// `handscan replay --live --hold` publishes a simulated scan to the live map exactly as the
// daemon would, and handscan-ui renders it: the screenshot is not blank and the status texts the
// UI drew are the replay's (its sensors at their rates, its message).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "child_process.hpp"
#include "screenshot_checks.hpp"

namespace handscan::e2e {
namespace {

namespace fs = std::filesystem;

const std::string kUi = std::string(HANDSCAN_BINARY_DIR) + "/ui/handscan-ui";
const std::string kCli = std::string(HANDSCAN_BINARY_DIR) + "/firmware/cli/handscan";

TEST(ReplayLive, UiRendersAReplayedScan) {
    if (const std::string why = ensureDisplay(); !why.empty()) GTEST_SKIP() << why;
    if (!fs::exists(kUi) || !fs::exists(kCli)) GTEST_SKIP() << "handscan-ui or handscan not built";
    const fs::path dir = fs::path(HANDSCAN_BINARY_DIR) / "replay_live_test";
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::string rec = (dir / "office.mcap").string();
    ASSERT_EQ(runChild({kCli, "-q", "sim", "--scene", "office", "--duration", "8", "--seed", "2",
                        "--no-camera", "--out", rec},
                       120)
                  .exit_code,
              0);
    const std::string name = "/handscan-e2e-replay-" + std::to_string(::getpid());
    ChildProcess replay({kCli, "-q", "replay", rec, "--out", (dir / "out").string(), "--fast",
                         "--live", "--hold", "--shm-name", name},
                        (dir / "replay.log").string());
    const fs::path png = dir / "shot.png";
    const ChildResult ui =
        runChild({kUi, "--shm-name", name, "--screenshot", png.string(), "--wait-points", "2000",
                  "--timeout", "90", "--width", "1024", "--height", "640"},
                 150);
    replay.terminate();
    ASSERT_EQ(ui.exit_code, 0) << ui.output;
    const cv::Mat img = cv::imread(png.string(), cv::IMREAD_GRAYSCALE);
    ASSERT_FALSE(img.empty());
    // Not blank: many pixels differ from the background (the most common grey level).
    EXPECT_GT(::handscan::test::nonBackgroundFraction(img), 0.05)
        << "the screenshot is nearly uniform";
    std::ifstream in(dir / "shot.json");
    std::stringstream ss;
    ss << in.rdbuf();
    const std::string json = ss.str();
    EXPECT_NE(json.find("hokuyo 40.0 Hz"), std::string::npos) << json;
    EXPECT_NE(json.find("xsens 200.0 Hz"), std::string::npos) << json;
    EXPECT_TRUE(json.find("replaying") != std::string::npos ||
                json.find("replay finished") != std::string::npos)
        << json;
    EXPECT_EQ(json.find("Camera dark"), std::string::npos)
        << "no camera in this replay, so no dark-camera warning";
    EXPECT_EQ(json.find("free 0 KiB"), std::string::npos) << "the replay's storage is not reported";
}

}  // namespace
}  // namespace handscan::e2e
