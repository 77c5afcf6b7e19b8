// The whole simulator: a short office recording holds every channel at its device rate, in
// host-time order, decodes through the drivers' codecs, matches the ground truth, and is
// byte-for-byte reproducible from its seed.
#include "handscan/sim/simulator.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>

#include "handscan/camera/frame_record.hpp"
#include "handscan/core/config.hpp"
#include "handscan/hokuyo/scip_stream_parser.hpp"
#include "handscan/motor/candump_format.hpp"
#include "handscan/motor/canopen.hpp"
#include "handscan/recording/channels.hpp"
#include "handscan/recording/mcap_reader.hpp"
#include "handscan/sim/mcap_sink.hpp"
#include "handscan/xsens/xbus_parser.hpp"

namespace handscan::sim {
namespace {

struct Loaded {
    DeviceConfig device;
    Calibration cal;
};

const Loaded& config() {
    static const Loaded l{
        loadDeviceConfig(std::string(HANDSCAN_SOURCE_DIR) + "/config/device.yaml"),
        loadCalibration(std::string(HANDSCAN_SOURCE_DIR) + "/config/calibration.yaml")};
    return l;
}

std::vector<std::uint8_t> simulate(const SimOptions& o, SimStats* stats = nullptr) {
    Simulator sim(o, config().device, config().cal);
    auto sink = McapSink::create("", o.cameras);
    EXPECT_TRUE(sink.isOk());
    EXPECT_TRUE(sim.run(**sink).isOk());
    EXPECT_TRUE((*sink)->close().isOk());
    if (stats) *stats = sim.stats();
    return (*sink)->takeBuffer();
}

// A recording's laser stream through the SCIP parser and its IMU stream through the Xbus parser,
// with the log time of every MTData2 frame.
struct LaserAndImu {
    hokuyo::ScipStreamParser scip;
    std::vector<hokuyo::ScipEvent> events;
    xsens::XbusParser xbus;
    std::vector<TimeNs> mtdata2_times;
};

void decodeLaserAndImu(std::vector<std::uint8_t> recording, LaserAndImu& d) {
    auto reader = recording::McapReader::fromBuffer(std::move(recording));
    ASSERT_TRUE(reader.isOk());
    ASSERT_TRUE((*reader)
                    ->forEachMessage({},
                                     [&](const recording::RecordedMessage& m) {
                                         if (m.channel->topic == "/hokuyo/raw")
                                             d.scip.feed(m.data, d.events);
                                         if (m.channel->topic != "/xsens/raw") return;
                                         d.xbus.feed(m.data);
                                         while (auto f = d.xbus.next())
                                             if (f->mid == 0x36)
                                                 d.mtdata2_times.push_back(m.log_time);
                                     })
                    .isOk());
}

TEST(SimulatorTest, RecordingHoldsEveryChannelAtItsDeviceRate) {
    SimOptions o;
    o.duration_s = 3.0;
    o.colour_camera = false;
    SimStats stats;
    auto bytes = simulate(o, &stats);
    auto reader = recording::McapReader::fromBuffer(std::move(bytes));
    ASSERT_TRUE(reader.isOk()) << reader.status().message();
    std::map<std::string, std::vector<TimeNs>> times;
    hokuyo::ScipStreamParser scip;
    std::vector<hokuyo::ScipEvent> scip_events;
    xsens::XbusParser xbus;
    int mtdata2 = 0, tpdo = 0, frames = 0, gt = 0;
    TimeNs prev = 0;
    const Status s = (*reader)->forEachMessage({}, [&](const recording::RecordedMessage& m) {
        EXPECT_GE(m.log_time, prev);
        prev = m.log_time;
        const std::string topic = m.channel->topic;
        times[topic].push_back(m.log_time);
        if (topic == recording::channels::kHokuyoRaw.topic) {
            scip.feed(m.data, scip_events);
        } else if (topic == recording::channels::kXsensRaw.topic) {
            xbus.feed(m.data);
            while (auto f = xbus.next()) mtdata2 += f->mid == 0x36;
        } else if (topic == recording::channels::kMotorCan.topic) {
            auto rec = motor::parseCandumpLogLine(std::string(m.data.begin(), m.data.end()));
            ASSERT_TRUE(rec.isOk());
            tpdo += motor::classifyCobId(rec->frame).function == motor::CanOpenFunction::kTpdo;
        } else if (topic == recording::channels::kCameraTrack.topic) {
            ASSERT_TRUE(camera::decodeFrameRecord(m.data).isOk());
            ++frames;
        } else if (topic == recording::channels::kGroundTruthPose.topic) {
            ASSERT_TRUE(recording::decodeGroundTruthPose(m.data).isOk());
            ++gt;
        }
    });
    ASSERT_TRUE(s.isOk()) << s.message();
    int scans = 0;
    for (const auto& e : scip_events) {
        ASSERT_TRUE(std::holds_alternative<hokuyo::ScipFrame>(e));
        scans += std::get<hokuyo::ScipFrame>(e).scan.has_value();
    }
    // Rates: 40 scans/s from 0.1 s, 200 IMU samples/s from ~0.05 s, TPDO every 5 ms after the
    // CANopen start-up, 50 frames/s from 0.03 s, ground truth at 200 Hz.
    EXPECT_NEAR(scans, 2.9 / 0.025, 2);
    EXPECT_NEAR(mtdata2, 200 * 2.95, 2);
    EXPECT_NEAR(tpdo, 2.95 / 0.005, 4);
    EXPECT_NEAR(frames, 50 * 2.97, 2);
    EXPECT_EQ(gt, 600);
    EXPECT_EQ(static_cast<std::uint64_t>(scans), stats.laser_scans);
    EXPECT_EQ(xbus.stats().checksum_failures, 0u);
    for (const char* t :
         {"/hokuyo/raw", "/xsens/raw", "/motor/can", "/camera/track", "/groundtruth/pose"}) {
        EXPECT_FALSE(times[t].empty()) << t;
    }
}

TEST(SimulatorTest, SameSeedSameBytesOtherSeedOtherBytes) {
    SimOptions o;
    o.duration_s = 1.0;
    o.colour_camera = false;
    o.trajectory = "aggressive";
    const auto a = simulate(o), b = simulate(o);
    o.seed = 2;
    const auto c = simulate(o);
    ASSERT_GT(a.size(), 100000u);
    EXPECT_TRUE(a == b);
    EXPECT_FALSE(a == c);
}

TEST(SimulatorTest, FaultsShowUpInTheStreams) {
    SimOptions o;
    o.duration_s = 4.0;
    o.cameras = false;
    o.faults.corrupt_scip_blocks = 2;
    o.faults.dropped_xbus_bytes = 3;
    o.faults.tcp_reconnects = 1;
    LaserAndImu d;
    ASSERT_NO_FATAL_FAILURE(decodeLaserAndImu(simulate(o), d));
    int scans = 0, handshakes = 0;
    for (const auto& e : d.events) {
        if (!std::holds_alternative<hokuyo::ScipFrame>(e)) continue;
        const auto& f = std::get<hokuyo::ScipFrame>(e);
        scans += f.scan.has_value();
        handshakes += f.command == "PP";
    }
    EXPECT_EQ(handshakes, 2);                     // the reconnect repeats the handshake
    EXPECT_NEAR(scans, 3.9 / 0.025 - 40 - 2, 2);  // 1 s lost to the reconnect, 2 corrupted
    EXPECT_GE(d.scip.stats().checksum_failures, 2u);
    EXPECT_NEAR(static_cast<double>(d.mtdata2_times.size()), 200 * 3.95 - 3, 2);
    EXPECT_GE(d.xbus.stats().checksum_failures + d.xbus.stats().resyncs, 3u);
}

TEST(SimulatorTest, IncidentsShowUpInTheStreams) {
    SimOptions o;
    o.duration_s = 4.0;
    o.cameras = false;
    o.incidents.blind_laser_at_s = 1.0;
    o.incidents.blind_laser_for_s = 1.0;
    o.incidents.imu_gap_at_s = 2.5;
    o.incidents.imu_gap_for_s = 0.5;
    LaserAndImu d;
    ASSERT_NO_FATAL_FAILURE(decodeLaserAndImu(simulate(o), d));
    // Blind: every step of ~40 scans an error code (below DMIN), the others mostly ranges.
    const std::uint32_t dmin = LaserConfig{}.dmin_mm;
    int blind = 0, seeing = 0;
    for (const auto& e : d.events) {
        if (!std::holds_alternative<hokuyo::ScipFrame>(e)) continue;
        const auto& f = std::get<hokuyo::ScipFrame>(e);
        if (!f.scan) continue;
        std::size_t valid = 0;
        for (std::uint32_t r : f.scan->ranges) valid += r >= dmin;
        if (valid == 0) ++blind;
        if (valid > f.scan->ranges.size() / 2) ++seeing;
    }
    EXPECT_NEAR(blind, 40, 1);
    EXPECT_NEAR(seeing, 3.9 / 0.025 - 40, 2);
    // The IMU gap: 0.5 s without a frame, the rest at 200 Hz.
    const std::vector<TimeNs>& imu = d.mtdata2_times;
    EXPECT_NEAR(static_cast<double>(imu.size()), 200 * (3.95 - 0.5), 3);
    TimeNs longest = 0;
    for (std::size_t i = 1; i < imu.size(); ++i) longest = std::max(longest, imu[i] - imu[i - 1]);
    EXPECT_NEAR(toSeconds(longest), 0.5, 0.02);
    EXPECT_EQ(d.xbus.stats().checksum_failures, 0u);
}

TEST(SimulatorTest, GroundTruthFileMatchesTheTrajectory) {
    SimOptions o;
    o.duration_s = 2.0;
    o.cameras = false;
    Simulator sim(o, config().device, config().cal);
    const auto path = std::filesystem::temp_directory_path() / "handscan_sim_gt.tum";
    ASSERT_TRUE(sim.writeGroundTruthTum(path.string()).isOk());
    std::ifstream in(path);
    std::string line;
    int n = 0;
    while (std::getline(in, line)) {
        if (line[0] == '#') continue;
        double t, x, y, z, qx, qy, qz, qw;
        ASSERT_EQ(std::sscanf(line.c_str(), "%lf %lf %lf %lf %lf %lf %lf %lf", &t, &x, &y, &z, &qx,
                              &qy, &qz, &qw),
                  8);
        EXPECT_NEAR(t, 1000.0 + n * 0.005, 1e-9);
        const Eigen::Vector3d p = sim.trajectory().at(n * 0.005).T_world_body.translation();
        EXPECT_NEAR(x, p.x(), 1e-8);
        EXPECT_NEAR(qx * qx + qy * qy + qz * qz + qw * qw, 1.0, 1e-8);
        ++n;
    }
    EXPECT_EQ(n, 401);
    std::filesystem::remove(path);
}

}  // namespace
}  // namespace handscan::sim
