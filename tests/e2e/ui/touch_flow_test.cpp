// The operator's flow by touch: taps (X pointer events from xdotool, which is what a touch screen
// without multi-touch delivers through GLFW) on handscan-ui's START / STOP / EXPORT buttons drive
// `handscan shm-demo` (standing in for the pipeline) through the command channel.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <thread>

#include "child_process.hpp"
#include "handscan/shm/export_preview.hpp"
#include "handscan/shm/live_map_reader.hpp"

namespace handscan::e2e {
namespace {

namespace fs = std::filesystem;

const std::string kCli = std::string(HANDSCAN_BINARY_DIR) + "/firmware/cli/handscan";
const std::string kUi = std::string(HANDSCAN_BINARY_DIR) + "/ui/handscan-ui";

// Button centres in a 1280 x 800 window (ui/src/screen_layout.hpp: 110 px status bar, 260 px
// button column; START/STOP is 83 px high, then EXPORT, NEW SCAN, CONTINUE SCAN and CALIBRATE,
// each 64 px high, 4 px apart).
constexpr int kButtonX = 1150;
constexpr int kStartStopY = 159;
constexpr int kExportY = 237;
constexpr int kCalibrateY = 441;

bool waitFor(const std::function<bool()>& condition, double seconds) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < end) {
        if (condition()) return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return condition();
}

TEST(TouchFlow, OperatorTapsStartStopExport) {
    if (const std::string why = ensureDisplay(); !why.empty()) GTEST_SKIP() << why;
    if (!fs::exists("/usr/bin/xdotool"))
        GTEST_SKIP() << "xdotool not installed (apt install xdotool)";
    if (!fs::exists(kUi) || !fs::exists(kCli)) GTEST_SKIP() << "handscan-ui or handscan not built";
    const fs::path dir =
        fs::temp_directory_path() / ("handscan-touch-" + std::to_string(::getpid()));
    fs::create_directories(dir / "usb");
    const std::string name = "/handscan-e2e-touch-" + std::to_string(::getpid());
    ChildProcess pipeline({kCli, "shm-demo", "--shm-name", name, "--export-root",
                           (dir / "internal").string(), "--samples-per-second", "20000"},
                          (dir / "pipeline.log").string());
    ChildProcess ui({kUi, "--shm-name", name, "--width", "1280", "--height", "800",
                     "--export-target", (dir / "usb").string(), "--max-seconds", "90"},
                    (dir / "ui.log").string());

    shm::ReaderOptions ro;
    ro.name = name;
    ro.recheck_interval_ns = 10 * kNsPerMs;
    shm::LiveMapReader observer(ro);
    const auto state = [&] {
        observer.poll();
        auto s = observer.readStatus();
        return s ? std::optional<shm::ScanState>(static_cast<shm::ScanState>(s->scan_state))
                 : std::nullopt;
    };
    ASSERT_TRUE(waitFor([&] { return state() == shm::ScanState::kIdle; }, 10))
        << "pipeline did not come up";

    const ChildResult found = runChild({"xdotool", "search", "--sync", "--name", "^handscan$"}, 20);
    ASSERT_EQ(found.exit_code, 0) << found.output;
    const std::string window = found.output.substr(0, found.output.find('\n'));
    const auto tap = [&](int x, int y) {
        ASSERT_EQ(runChild({"xdotool", "mousemove", "--window", window, std::to_string(x),
                            std::to_string(y)},
                           10)
                      .exit_code,
                  0);
        std::this_thread::sleep_for(
            std::chrono::milliseconds(300));  // hover first, as a finger lands
        ASSERT_EQ(runChild({"xdotool", "click", "1"}, 10).exit_code, 0);
    };
    std::this_thread::sleep_for(
        std::chrono::milliseconds(500));  // first frames drawn, buttons enabled

    tap(kButtonX, kStartStopY);  // START SCAN
    ASSERT_TRUE(waitFor([&] { return state() == shm::ScanState::kScanning; }, 10))
        << "START tap had no effect";
    std::this_thread::sleep_for(std::chrono::milliseconds(1500));
    tap(kButtonX, kStartStopY);  // the same place now says STOP SCAN
    ASSERT_TRUE(waitFor([&] { return state() == shm::ScanState::kStopped; }, 10))
        << "STOP tap had no effect";
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    tap(kButtonX, kExportY);  // EXPORT TO USB (enabled once stopped)
    ASSERT_TRUE(waitFor(
        [&] {
            observer.poll();
            auto s = observer.readStatus();
            return s && s->export_status.safe_to_remove == 1;
        },
        20))
        << "EXPORT tap did not lead to a safe-to-remove export";
    EXPECT_TRUE(fs::exists(dir / "usb" / "scan-1" / "map.ply"));
    EXPECT_GT(fs::file_size(dir / "usb" / "scan-1" / "map.ply"), 1000u);
    // CALIBRATE on the stopped screen sends the calibrate command (the demo, which has no raw
    // recording, refuses it; the daemon's calibration is e2e.hil.calibrate).
    tap(kButtonX, kCalibrateY);
    EXPECT_TRUE(waitFor(
        [&] {
            std::ifstream log(dir / "pipeline.log");
            const std::string text((std::istreambuf_iterator<char>(log)),
                                   std::istreambuf_iterator<char>());
            return text.find(" calibrate ''") != std::string::npos;
        },
        10))
        << "CALIBRATE tap sent no calibrate command";

    ui.terminate();
    pipeline.terminate();
    std::error_code ec;
    fs::remove(shm::exportPreviewPath(name), ec);  // the export's picture, left by shm-demo
    if (!::testing::Test::HasFailure()) fs::remove_all(dir, ec);
}

}  // namespace
}  // namespace handscan::e2e
