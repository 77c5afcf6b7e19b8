// The touch screen on the live daemon: handscan-pipeline (here in the test's process, its devices
// faked behind their real transports) scans, and handscan-ui renders the map it publishes and
// the status the daemon writes: the sensors with their measured rates, the motor's encoder, the
// absent buttons as lost, the pipeline's message.
#include <gtest/gtest.h>

#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <thread>

#include "../ui/screenshot_checks.hpp"
#include "child_process.hpp"
#include "daemon_rig.hpp"
#include "handscan/pipeline_daemon/pipeline_daemon.hpp"

namespace handscan::pipeline_daemon::test {
namespace {

const std::string kUi = std::string(HANDSCAN_BINARY_DIR) + "/ui/handscan-ui";

TEST(PipelineDaemonUi, UiRendersTheLiveScan) {
    if (const std::string why = e2e::ensureDisplay(); !why.empty()) GTEST_SKIP() << why;
    if (!fs::exists(kUi)) GTEST_SKIP() << kUi << " not built";
    DaemonRig rig("ui");
    DaemonOptions o;
    o.device_config = rig.deviceYaml();
    o.calibration = DaemonRig::calibrationYaml();
    o.shm_name = rig.shmName();
    o.map_capacity_points = 1 << 18;
    PipelineDaemon daemon(o);
    const fs::path keep = fs::path(HANDSCAN_BINARY_DIR) / "daemon_ui_shot.png";
    ASSERT_TRUE(daemon.open().isOk());
    DaemonThread running(daemon);

    const bool up = rig.waitStatus(
                           [](const shm::StatusBlock& s) {
                               return sensorConnected(s, "hokuyo") && sensorConnected(s, "xsens") &&
                                      sensorConnected(s, "encoder");
                           },
                           10.0)
                        .has_value();
    const auto ack = rig.command(shm::CommandType::kStartScan);
    const bool scanned =
        up && rig.waitStatus([](const shm::StatusBlock& s) { return s.point_count > 0; }, 15.0)
                  .has_value();
    const fs::path png = rig.dir() / "shot.png";
    const e2e::ChildResult ui =
        scanned ? e2e::runChild({kUi, "--shm-name", rig.shmName(), "--screenshot", png.string(),
                                 "--wait-points", "3000", "--timeout", "60", "--width", "1024",
                                 "--height", "640"},
                                90)
                : e2e::ChildResult{};
    const Status result = running.stop();
    ASSERT_TRUE(up) << "devices did not come up";
    EXPECT_EQ(ack.state, static_cast<std::uint32_t>(shm::CommandState::kDone));
    ASSERT_TRUE(scanned) << "no points registered";
    EXPECT_TRUE(result.isOk()) << result.message();
    ASSERT_EQ(ui.exit_code, 0) << ui.output;

    const cv::Mat img = cv::imread(png.string(), cv::IMREAD_GRAYSCALE);
    ASSERT_FALSE(img.empty());
    fs::copy_file(png, keep, fs::copy_options::overwrite_existing);  // for a look after the run
    EXPECT_GT(::handscan::test::nonBackgroundFraction(img), 0.05)
        << "the screenshot is nearly uniform";

    std::ifstream in(png.string().substr(0, png.string().size() - 4) + ".json");
    std::stringstream ss;
    ss << in.rdbuf();
    const std::string json = ss.str();
    EXPECT_NE(json.find("hokuyo"), std::string::npos) << json;
    EXPECT_NE(json.find("encoder"), std::string::npos) << json;
    EXPECT_NE(json.find("buttons"), std::string::npos) << json;
    EXPECT_NE(json.find("scanning"), std::string::npos) << json;
    EXPECT_EQ(json.find(" 0 points"), std::string::npos) << json;
}

}  // namespace
}  // namespace handscan::pipeline_daemon::test
