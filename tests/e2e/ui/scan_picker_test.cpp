// Continue scan, choosing which: with several scans on the device (the list the pipeline
// publishes, shm::ScanList), CONTINUE SCAN opens the picker; a tap on one sends continue-scan for
// that scan, and once the pipeline has started it (its map on the screen) the UI asks where the
// operator stands on it (the placement, I AM HERE). Taps are X pointer events from xdotool; the
// test stands in for the pipeline (its writer publishes the status and the list and answers).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
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
// CONTINUE SCAN's centre in a 1280 x 800 window (see touch_flow_test.cpp).
constexpr int kButtonX = 1150;
constexpr int kContinueY = 237 + 2 * (64 + 4);

Json readJson(const fs::path& path) {
    std::ifstream in(path);
    std::stringstream ss;
    ss << in.rdbuf();
    return Json::parse(ss.str(), nullptr, false);
}

TEST(ScanPicker, OperatorPicksAnEarlierScanThenPlacesThemselvesOnIt) {
    if (const std::string why = ensureDisplay(); !why.empty()) GTEST_SKIP() << why;
    if (!fs::exists("/usr/bin/xdotool"))
        GTEST_SKIP() << "xdotool not installed (apt install xdotool)";
    if (!fs::exists(kUi)) GTEST_SKIP() << kUi << " not built";
    const fs::path dir =
        fs::temp_directory_path() / ("handscan-picker-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    shm::WriterOptions wo;
    wo.name = "/handscan-e2e-picker-" + std::to_string(::getpid());
    wo.map_capacity_points = 1000;
    auto created = shm::LiveMapWriter::create(wo);
    ASSERT_TRUE(created.isOk()) << created.status().message();
    shm::LiveMapWriter& writer = **created;
    shm::StatusBlock idle;
    idle.t_ns = 1;
    idle.can_continue = 1;
    writer.setStatus(idle);
    const char* names[] = {"scan-20261125-090000", "scan-20261124-170000", "scan-20261120-080000"};
    shm::ScanList list;
    list.count = list.total = 3;
    for (int i = 0; i < 3; ++i) {
        shm::setText(list.scans[i].name, names[i]);
        list.scans[i].modified_unix_s = 1'795'000'000 - 86'400 * i;
        list.scans[i].journal_bytes = 12'000'000u >> i;
    }
    writer.setScanList(list);

    const fs::path json = dir / "ui.json";
    ChildProcess ui({kUi, "--shm-name", wo.name, "--width", "1280", "--height", "800",
                     "--status-json", json.string(), "--max-seconds", "60"},
                    (dir / "ui.log").string());
    // As a pipeline would: heartbeats, and the commands that come.
    std::vector<shm::Command> commands;
    const auto waitFor = [&](const std::function<bool()>& condition, double seconds) {
        const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
        while (true) {
            writer.heartbeat();
            while (auto c = writer.pollCommand()) commands.push_back(*c);
            if (condition()) return true;
            if (std::chrono::steady_clock::now() > end) return false;
            std::this_thread::sleep_for(std::chrono::milliseconds(50));
        }
    };
    const ChildResult found = runChild({"xdotool", "search", "--sync", "--name", "^handscan$"}, 20);
    ASSERT_EQ(found.exit_code, 0) << found.output;
    const std::string window = found.output.substr(0, found.output.find('\n'));
    const auto tap = [&](double x, double y) {
        ASSERT_EQ(runChild({"xdotool", "mousemove", "--window", window,
                            std::to_string(std::lround(x)), std::to_string(std::lround(y))},
                           10)
                      .exit_code,
                  0);
        waitFor([] { return false; }, 0.3);  // hover, as a finger lands
        ASSERT_EQ(runChild({"xdotool", "click", "1"}, 10).exit_code, 0);
    };
    ASSERT_TRUE(waitFor([&] { return readJson(json)["can_continue"] == true; }, 20))
        << "the UI did not come up";

    tap(kButtonX, kContinueY);  // CONTINUE SCAN
    Json shown;
    ASSERT_TRUE(waitFor(
        [&] {
            shown = readJson(json);
            return shown.is_object() && shown["picker"]["active"] == true &&
                   shown["picker"]["scans"].size() == 3 &&
                   shown["picker"]["scans"][1]["button"][3].get<double>() > 0;
        },
        10))
        << "CONTINUE SCAN did not list the three scans:\n"
        << shown.dump();
    for (int i = 0; i < 3; ++i) EXPECT_EQ(shown["picker"]["scans"][i]["name"], names[i]);
    EXPECT_TRUE(commands.empty()) << "a command before anything was picked";

    // The second (yesterday's) scan.
    const Json& b = shown["picker"]["scans"][1]["button"];
    tap(b[0].get<double>() + b[2].get<double>() / 2, b[1].get<double>() + b[3].get<double>() / 2);
    ASSERT_TRUE(waitFor([&] { return !commands.empty(); }, 10)) << "the tap sent no command";
    ASSERT_EQ(commands.size(), 1u);
    EXPECT_EQ(commands[0].type, shm::CommandType::kContinueScan);
    EXPECT_EQ(commands[0].argument, "scan=scan-20261124-170000");
    EXPECT_FALSE(readJson(json)["placement"]["active"].get<bool>()) << "placing before it started";

    // The pipeline starts it: its map and path on the screen, searching; then answers.
    writer.newScan();
    std::vector<shm::DisplayPoint> floor;
    for (int i = 0; i < 50; ++i)
        floor.push_back(
            {static_cast<float>(i % 10), static_cast<float>(i / 10), 0.0f, 200, 200, 200, 200});
    ASSERT_TRUE(writer.appendPoints(floor).isOk());
    for (int i = 0; i < 10; ++i) {
        shm::PoseRecord p;
        p.t_ns = static_cast<std::int64_t>(i) * kNsPerSec;
        p.position_m[0] = i;
        p.position_m[1] = 2;
        p.position_m[2] = 1.3;
        writer.appendTrack(p);
    }
    shm::StatusBlock searching = idle;
    searching.scan_state = static_cast<std::uint8_t>(shm::ScanState::kScanning);
    searching.localization = static_cast<std::uint8_t>(shm::LocalizationState::kSearching);
    writer.setStatus(searching);
    writer.ack(commands[0].seq, shm::CommandState::kDone, "continuing scan-20261124-170000");
    EXPECT_TRUE(waitFor(
        [&] {
            shown = readJson(json);
            return shown["placement"]["active"] == true && shown["picker"]["active"] == false &&
                   shown["view"]["camera"] == "top-down";
        },
        10))
        << "no placement on the picked scan's map:\n"
        << shown.dump();

    ui.terminate();
    std::error_code ec;
    if (!::testing::Test::HasFailure()) fs::remove_all(dir, ec);
}

}  // namespace
}  // namespace handscan::e2e
