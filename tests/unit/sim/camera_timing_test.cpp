// Camera frames replayed from a recording carry their mid-exposure time, as the live camera
// stamps them: the colour camera's end-of-frame (UVC) timestamps corrected by its readout
// (device.yaml readout_ms). The simulator writes the true mid-exposure time into each frame
// record's header; the recorded source must decode the same time from the V4L2 timestamp.
// Before readout_ms, every colour frame came 0.7 frame periods (140 ms at 5 Hz) late, and the
// cloud was coloured with the camera where it had been that long before.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>

#include "handscan/camera/frame_record.hpp"
#include "handscan/core/config.hpp"
#include "handscan/sim/mcap_sink.hpp"
#include "handscan/sim/simulator.hpp"
#include "handscan/sources/recorded_source.hpp"

namespace handscan::sim {
namespace {

TEST(CameraTiming, ReplayedFramesAreAtMidExposureAsTheCameraStampedThem) {
    const DeviceConfig device =
        loadDeviceConfig(std::string(HANDSCAN_SOURCE_DIR) + "/config/device.yaml");
    ASSERT_GT(device.colour_camera.readout_ms, 0.0);
    const Calibration cal =
        loadCalibration(std::string(HANDSCAN_SOURCE_DIR) + "/config/calibration.yaml");
    SimOptions o;
    o.duration_s = 2.5;
    Simulator sim(o, device, cal);
    sim.devices().tracking.fps = 10.0;  // fewer frames to render; still stamped at start
    auto sink = McapSink::create("", true);
    ASSERT_TRUE(sink.isOk());
    ASSERT_TRUE(sim.run(**sink).isOk());
    ASSERT_TRUE((*sink)->close().isOk());
    const std::filesystem::path path =
        std::filesystem::temp_directory_path() / "handscan_camera_timing_test.mcap";
    {
        const std::vector<std::uint8_t> bytes = (*sink)->takeBuffer();
        std::ofstream f(path, std::ios::binary);
        f.write(reinterpret_cast<const char*>(bytes.data()),
                static_cast<std::streamsize>(bytes.size()));
    }

    // The header's mid-exposure time of every frame record, by topic, as read.
    std::map<std::string, std::vector<TimeNs>> truth;
    sources::RecordedSourceOptions options;
    options.tracking = true;
    options.tap = [&](const recording::RecordedMessage& m) {
        auto rec = camera::decodeFrameRecord(m.data);
        if (rec) truth[m.channel->topic].push_back(rec->header.t_host_ns);
    };
    auto source = sources::RecordedSource::open(path.string(), device, options);
    ASSERT_TRUE(source.isOk()) << source.status().message();
    std::vector<TimeNs> colour, tracking;
    std::vector<sources::Sample> samples;
    for (;;) {
        samples.clear();
        auto clock = (*source)->next(samples);
        ASSERT_TRUE(clock.isOk()) << clock.status().message();
        if (!*clock) break;
        for (const sources::Sample& s : samples) {
            if (const auto* img = std::get_if<Image>(&s)) colour.push_back(img->t_host);
            if (const auto* f = std::get_if<sources::TrackingFrame>(&s))
                tracking.push_back(f->t_host);
        }
    }
    std::filesystem::remove(path);
    ASSERT_GE(colour.size(), 10u);
    ASSERT_GE(tracking.size(), 20u);
    ASSERT_EQ(colour.size(), truth[sources::kColourTopic].size());
    ASSERT_EQ(tracking.size(), truth[sources::kTrackingTopic].size());
    // The V4L2 timestamp is in whole microseconds of the header's host time.
    for (std::size_t i = 0; i < colour.size(); ++i)
        EXPECT_NEAR(colour[i], truth[sources::kColourTopic][i], 2 * kNsPerUs)
            << "colour frame " << i;
    for (std::size_t i = 0; i < tracking.size(); ++i)
        EXPECT_NEAR(tracking[i], truth[sources::kTrackingTopic][i], 2 * kNsPerUs)
            << "tracking frame " << i;
}

}  // namespace
}  // namespace handscan::sim
