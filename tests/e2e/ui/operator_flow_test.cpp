// The operator's flow through the command channel: start -> scan -> stop -> export -> "safe to
// remove", against `handscan shm-demo` in its own process standing in for the pipeline, with the
// test in the UI's role (the same LiveMapReader calls the UI's buttons make); then handscan-ui
// shows the result.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <thread>

#include "child_process.hpp"
#include "handscan/core/json.hpp"
#include "handscan/export/point_formats.hpp"
#include "handscan/shm/export_preview.hpp"
#include "handscan/shm/live_map_reader.hpp"
#include "handscan/shm/text_field.hpp"

namespace handscan::e2e {
namespace {

namespace fs = std::filesystem;
using shm::CommandState;
using shm::CommandType;

const std::string kCli = std::string(HANDSCAN_BINARY_DIR) + "/firmware/cli/handscan";
const std::string kUi = std::string(HANDSCAN_BINARY_DIR) + "/ui/handscan-ui";

// Sends a command and waits for its final answer.
shm::CommandAck command(shm::LiveMapReader& ui, CommandType type, const std::string& arg = {}) {
    auto seq = ui.sendCommand(type, arg);
    EXPECT_TRUE(seq.isOk()) << seq.status().message();
    shm::CommandAck last;
    if (!seq) return last;
    for (int i = 0; i < 500; ++i) {
        ui.poll();
        auto r = ui.commandResult(*seq);
        if (r) {
            last = *r;
            const auto s = static_cast<CommandState>(r->state);
            if (s != CommandState::kPending && s != CommandState::kAccepted &&
                s != CommandState::kInProgress)
                return last;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    ADD_FAILURE() << shm::toString(type) << " never answered";
    return last;
}

std::optional<shm::StatusBlock> waitForState(shm::LiveMapReader& ui, shm::ScanState state) {
    for (int i = 0; i < 300; ++i) {
        ui.poll();
        auto s = ui.readStatus();
        if (s && static_cast<shm::ScanState>(s->scan_state) == state) return s;
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return std::nullopt;
}

TEST(OperatorFlow, StartScanStopExportSafeToRemove) {
    if (!fs::exists(kCli)) GTEST_SKIP() << kCli << " not built";
    const fs::path dir =
        fs::temp_directory_path() / ("handscan-flow-" + std::to_string(::getpid()));
    fs::create_directories(dir / "usb");
    const std::string name = "/handscan-e2e-flow-" + std::to_string(::getpid());
    ChildProcess pipeline({kCli, "shm-demo", "--shm-name", name, "--export-root",
                           (dir / "internal").string(), "--samples-per-second", "30000"},
                          (dir / "pipeline.log").string());

    shm::ReaderOptions ro;
    ro.name = name;
    ro.recheck_interval_ns = 10 * kNsPerMs;
    shm::LiveMapReader ui(ro);
    for (int i = 0; i < 500 && ui.poll() != shm::Connection::kConnected; ++i) {
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    ASSERT_EQ(ui.poll(), shm::Connection::kConnected) << ui.message();
    ASSERT_TRUE(waitForState(ui, shm::ScanState::kIdle).has_value());

    // Start: the scan runs, the map and the trajectory grow.
    shm::CommandAck a = command(ui, CommandType::kStartScan);
    EXPECT_EQ(static_cast<CommandState>(a.state), CommandState::kDone) << shm::getText(a.message);
    ASSERT_TRUE(waitForState(ui, shm::ScanState::kScanning).has_value());
    shm::MapCursor cursor;
    shm::MapDelta delta;
    std::uint64_t points = 0, track = 0;
    for (int i = 0; i < 300 && points < 3000; ++i) {
        if (ui.readMap(cursor, delta)) {
            points += delta.points.size();
            track += delta.track.size();
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    EXPECT_GE(points, 3000u);
    EXPECT_GT(track, 0u);
    EXPECT_EQ(static_cast<CommandState>(command(ui, CommandType::kStartScan).state),
              CommandState::kRejected);

    // Export is refused while scanning: the map is not final.
    a = command(ui, CommandType::kExport, (dir / "usb").string());
    EXPECT_EQ(static_cast<CommandState>(a.state), CommandState::kRejected);
    EXPECT_EQ(shm::getText(a.message), "stop the scan before exporting");

    // Stop: the scan state and the map freeze.
    a = command(ui, CommandType::kStopScan);
    EXPECT_EQ(static_cast<CommandState>(a.state), CommandState::kDone);
    auto stopped = waitForState(ui, shm::ScanState::kStopped);
    ASSERT_TRUE(stopped.has_value());
    EXPECT_GT(stopped->elapsed_s, 0.0);
    EXPECT_GT(stopped->distance_m, 0.0);
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    ASSERT_TRUE(ui.readMap(cursor, delta));
    points += delta.points.size();
    ASSERT_TRUE(ui.readMap(cursor, delta));
    EXPECT_TRUE(delta.points.empty()) << "map still growing after stop";

    // Export to the "USB stick": done, verified, safe to remove; the file holds every point.
    a = command(ui, CommandType::kExport, (dir / "usb").string());
    EXPECT_EQ(static_cast<CommandState>(a.state), CommandState::kDone) << shm::getText(a.message);
    EXPECT_EQ(std::string(shm::getText(a.message)).rfind("safe to remove", 0), 0u)
        << shm::getText(a.message);
    EXPECT_FLOAT_EQ(a.progress, 1.0f);
    auto after = ui.readStatus();
    ASSERT_TRUE(after.has_value());
    EXPECT_EQ(static_cast<shm::ExportState>(after->export_status.state), shm::ExportState::kDone);
    EXPECT_EQ(after->export_status.safe_to_remove, 1);
    const fs::path ply = dir / "usb" / "scan-1" / "map.ply";
    ASSERT_TRUE(fs::exists(ply));
    std::ifstream in(ply, std::ios::binary);
    std::string header, line;
    while (std::getline(in, line)) {
        header += line + "\n";
        if (line == "end_header") break;
    }
    EXPECT_NE(header.find("element vertex " + std::to_string(points) + "\n"), std::string::npos)
        << header;
    EXPECT_EQ(fs::file_size(ply), header.size() + points * exporter::kPlyPointRecordBytes);
    // ... and left the map's picture (the report's view from above) for the export screen.
    const std::string preview = shm::exportPreviewPath(name);
    const cv::Mat preview_png = cv::imread(preview, cv::IMREAD_COLOR);
    ASSERT_FALSE(preview_png.empty()) << preview;

    // The UI shows the finished export and the whole map.
    if (ensureDisplay().empty() && fs::exists(kUi)) {
        const fs::path png = dir / "ui.png";
        const ChildResult r =
            runChild({kUi, "--shm-name", name, "--screenshot", png.string(), "--wait-points",
                      std::to_string(points), "--timeout", "20", "--camera", "top-down"},
                     60);
        ASSERT_EQ(r.exit_code, 0) << r.output;
        std::ifstream js((dir / "ui.json").string());
        std::stringstream ss;
        ss << js.rdbuf();
        const std::string json = ss.str();
        const Json doc = Json::parse(json, nullptr, false);
        ASSERT_TRUE(doc.is_object()) << json;
        EXPECT_EQ(doc["export"],
                  Json({{"text", "Export done: SAFE TO REMOVE the USB stick"}, {"health", "ok"}}))
            << json;
        EXPECT_EQ(doc["scan_state"], "STOPPED") << json;
        EXPECT_EQ(doc["map"]["points_drawn"], points) << json;
        // The export screen shows that picture: drawn where the status says, and the screenshot
        // there is the PNG scaled down (both blurred a little: the GPU's and OpenCV's filters
        // differ pixel by pixel).
        EXPECT_EQ(doc["export_preview"]["path"], preview) << json;
        EXPECT_EQ(doc["export_preview"]["size"], Json::array({preview_png.cols, preview_png.rows}));
        const auto& d = doc["export_preview"]["drawn"];
        const cv::Rect at(static_cast<int>(std::lround(d[0].get<double>())),
                          static_cast<int>(std::lround(d[1].get<double>())),
                          static_cast<int>(d[2].get<double>()),
                          static_cast<int>(d[3].get<double>()));
        const cv::Mat shot = cv::imread(png.string(), cv::IMREAD_COLOR);
        ASSERT_GT(at.width, 100) << json;
        ASSERT_TRUE((cv::Rect(0, 0, shot.cols, shot.rows) & at) == at) << json;
        cv::Mat expected, diff;
        cv::resize(preview_png, expected, at.size(), 0, 0, cv::INTER_AREA);
        cv::Mat shown;
        cv::GaussianBlur(shot(at), shown, cv::Size(5, 5), 0);
        cv::GaussianBlur(expected, expected, cv::Size(5, 5), 0);
        cv::absdiff(shown, expected, diff);
        const cv::Scalar mean = cv::mean(diff);
        EXPECT_LT((mean[0] + mean[1] + mean[2]) / 3, 12.0)
            << "the export screen's picture is not " << preview;
    }

    // Shutdown ends the pipeline process cleanly.
    EXPECT_EQ(static_cast<CommandState>(command(ui, CommandType::kShutdown).state),
              CommandState::kDone);
    const ChildResult r = pipeline.wait(10);
    EXPECT_EQ(r.exit_code, 0) << r.output;
    std::error_code ec;
    fs::remove(shm::exportPreviewPath(name), ec);
    if (!::testing::Test::HasFailure()) fs::remove_all(dir, ec);
}

}  // namespace
}  // namespace handscan::e2e
