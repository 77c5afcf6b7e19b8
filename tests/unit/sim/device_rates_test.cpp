// `handscan info` on simulated recordings: the raw channels decoded with the drivers' codecs
// (firmware/replay DeviceRateMeter) show each device at the rate the simulator was configured
// with, and the faults injected into the streams show up as lost samples and errors.
#include "handscan/replay/device_rates.hpp"

#include <gtest/gtest.h>

#include <map>
#include <sstream>
#include <string>

#include "handscan/core/config.hpp"
#include "handscan/recording/mcap_reader.hpp"
#include "handscan/recording/recording_summary.hpp"
#include "handscan/sim/mcap_sink.hpp"
#include "handscan/sim/simulator.hpp"

namespace handscan::sim {
namespace {

struct Info {
    recording::RecordingSummary summary;
    std::map<std::string, recording::DeviceSummary> devices;  // by topic
};

// Simulates, then summarises the recording as `handscan info` does (one pass, decoding the raw
// channels on the way).
Info simulateAndSummarise(const SimOptions& o, const DeviceConfig& device) {
    const Calibration cal =
        loadCalibration(std::string(HANDSCAN_SOURCE_DIR) + "/config/calibration.yaml");
    Simulator sim(o, device, cal);
    auto sink = McapSink::create("", o.cameras);
    EXPECT_TRUE(sink.isOk());
    EXPECT_TRUE(sim.run(**sink).isOk());
    EXPECT_TRUE((*sink)->close().isOk());
    auto reader = recording::McapReader::fromBuffer((*sink)->takeBuffer(), "sim.mcap");
    EXPECT_TRUE(reader.isOk());
    replay::DeviceRateMeter meter(device);
    auto summary =
        recording::summarizeRecording(**reader, {}, [&](const recording::RecordedMessage& m) {
            meter.feed(m.channel->topic, m.log_time, m.data);
        });
    EXPECT_TRUE(summary.isOk());
    Info info{*summary, {}};
    info.summary.devices = meter.summaries();
    for (const auto& d : info.summary.devices) info.devices[d.topic] = d;
    return info;
}

TEST(DeviceRatesTest, InfoShowsEveryDeviceAtItsConfiguredRate) {
    DeviceConfig device =
        loadDeviceConfig(std::string(HANDSCAN_SOURCE_DIR) + "/config/device.yaml");
    device.motor.tpdo_period_ms = 4;  // not the default, so the test sees the configured period
    SimOptions o;
    o.duration_s = 3.0;
    const Info info = simulateAndSummarise(o, device);
    ASSERT_EQ(info.devices.size(), 5u);
    const auto& laser = info.devices.at("/hokuyo/raw");
    const auto& imu = info.devices.at("/xsens/raw");
    const auto& encoder = info.devices.at("/motor/can");
    const auto& track = info.devices.at("/camera/track");
    const auto& colour = info.devices.at("/camera/colour");
    EXPECT_EQ(laser.unit, "scans/s");
    EXPECT_NEAR(laser.rate_hz, 40.0, 0.5);
    EXPECT_NEAR(imu.rate_hz, device.xsens.rate_hz, 1.0);
    EXPECT_NEAR(encoder.rate_hz, 1000.0 / device.motor.tpdo_period_ms, 1.0);
    EXPECT_NEAR(track.rate_hz, device.tracking_camera.fps, 0.1);
    EXPECT_NEAR(colour.rate_hz, device.colour_camera.fps, 0.05);
    EXPECT_GT(laser.samples, 100u);
    for (const auto& [topic, d] : info.devices) {
        EXPECT_EQ(d.lost, 0u) << topic;
        EXPECT_EQ(d.errors, 0u) << topic << ": " << d.last_error;
    }
    // The raw channels' message rates are transport reads, not the device rates.
    for (const auto& c : info.summary.channels) {
        if (c.topic == "/hokuyo/raw") {
            EXPECT_GT(c.rate_hz, 60.0);  // TCP segments
        }
        if (c.topic == "/motor/can") {
            EXPECT_GT(c.rate_hz, encoder.rate_hz + 5.0);  // + heartbeats
        }
    }
    std::ostringstream text;
    recording::printSummaryText(info.summary, text);
    EXPECT_NE(text.str().find("Hokuyo laser     /hokuyo/raw"), std::string::npos) << text.str();
    EXPECT_NE(text.str().find("scans/s"), std::string::npos);
    EXPECT_NE(text.str().find("tracking camera  /camera/track"), std::string::npos);
    std::ostringstream json;
    recording::printSummaryJson(info.summary, json);
    EXPECT_NE(json.str().find("\"devices\":[{\"device\":\"Hokuyo "
                              "laser\",\"topic\":\"/hokuyo/raw\",\"unit\":\"scans/s\""),
              std::string::npos)
        << json.str();
}

TEST(DeviceRatesTest, InjectedFaultsShowAsLostSamplesAndErrors) {
    const DeviceConfig device =
        loadDeviceConfig(std::string(HANDSCAN_SOURCE_DIR) + "/config/device.yaml");
    SimOptions o;
    o.duration_s = 2.0;
    o.colour_camera = false;
    o.faults.lost_frames = 2;
    o.faults.corrupt_scip_blocks = 1;
    o.faults.dropped_xbus_bytes = 1;
    const Info info = simulateAndSummarise(o, device);
    const auto& laser = info.devices.at("/hokuyo/raw");
    const auto& imu = info.devices.at("/xsens/raw");
    const auto& track = info.devices.at("/camera/track");
    EXPECT_EQ(track.lost, 2u);
    EXPECT_EQ(laser.lost, 1u);  // the scan whose checksum failed
    EXPECT_GE(laser.errors, 1u);
    EXPECT_FALSE(laser.last_error.empty());
    EXPECT_EQ(imu.lost, 1u);    // the frame that lost a byte
    EXPECT_GE(imu.errors, 1u);  // its checksum or the resync after it
    // A lost sample lowers the delivered rate by no more than its share.
    EXPECT_NEAR(track.rate_hz, 50.0 * (1.0 - 2.0 / 100.0), 1.0);
}

}  // namespace
}  // namespace handscan::sim
