// The channel table and our record layouts: exact sizes, golden bytes, round trips, and clear
// errors for messages of the wrong size.
#include "handscan/recording/channels.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "handscan/recording/mcap_reader.hpp"
#include "handscan/recording/mcap_writer.hpp"

namespace handscan::recording {
namespace {

TEST(Channels, TopicsAreUniqueAndRawStreamsAreTheDeviceStreams) {
    std::set<std::string_view> topics;
    std::set<std::string_view> raw;
    for (const auto& c : knownChannels()) {
        EXPECT_TRUE(topics.insert(c.topic).second) << c.topic;
        EXPECT_FALSE(c.message_encoding.empty());
        if (c.raw) raw.insert(c.topic);
    }
    EXPECT_EQ(raw, (std::set<std::string_view>{"/hokuyo/raw", "/xsens/raw", "/motor/can",
                                               "/camera/track", "/camera/colour", "/gpio/events"}));
    ASSERT_NE(findChannel("/groundtruth/pose"), nullptr);
    EXPECT_EQ(findChannel("/groundtruth/pose")->message_encoding, "handscan.groundtruth_pose.v1");
    EXPECT_EQ(findChannel("/motor/can")->message_encoding, "handscan.candump_line");
    EXPECT_EQ(findChannel("/camera/colour")->message_encoding, "handscan.v4l2_buffer");
    EXPECT_EQ(findChannel("/nope"), nullptr);
}

TEST(Channels, GroundTruthPoseGoldenBytes) {
    GroundTruthPose p;
    p.t = 1'500'000'000;  // 1.5 s
    p.p_world_body = {1.0, -2.0, 0.5};
    p.q_world_body = Eigen::Quaterniond(1.0, 0.0, 0.0, 0.0);  // w, x, y, z
    std::vector<std::uint8_t> b;
    encodeGroundTruthPose(p, b);
    ASSERT_EQ(b.size(), 64u);
    // f64 little-endian: 1.5 = 0x3FF8000000000000, 1.0 = 0x3FF0..., -2.0 = 0xC000..., 0.5 =
    // 0x3FE0...
    const std::vector<std::uint8_t> head = {0,    0,    0, 0,    0,    0, 0xF8, 0x3F, 0,    0,   0,
                                            0,    0,    0, 0xF0, 0x3F, 0, 0,    0,    0,    0,   0,
                                            0x00, 0xC0, 0, 0,    0,    0, 0,    0,    0xE0, 0x3F};
    EXPECT_TRUE(std::equal(head.begin(), head.end(), b.begin()));
    // qx qy qz = 0, qw = 1 last.
    EXPECT_EQ(b[62], 0xF0);
    EXPECT_EQ(b[63], 0x3F);
    auto d = decodeGroundTruthPose(b);
    ASSERT_TRUE(d);
    EXPECT_EQ(d->t, p.t);
    EXPECT_EQ(d->p_world_body, p.p_world_body);
    EXPECT_EQ(d->q_world_body.coeffs(), p.q_world_body.coeffs());

    b.pop_back();
    auto bad = decodeGroundTruthPose(b);
    ASSERT_FALSE(bad);
    EXPECT_EQ(bad.status().message(),
              "handscan.groundtruth_pose.v1 message of 63 bytes: expected exactly 64");
}

TEST(Channels, ImuSampleRoundTrip) {
    ImuSample s;
    s.t_host = 123456789012345;
    s.t_device_ticks = -5;
    s.accel_mps2_imu = {0.1, -9.81, 3.0};
    s.gyro_radps_imu = {1e-3, 2e-3, -6.4};
    s.status_word = 0xDEADBEEF;
    s.packet_counter = 65535;
    std::vector<std::uint8_t> b;
    encodeImuSample(s, b);
    ASSERT_EQ(b.size(), 70u);
    EXPECT_EQ(b[0], 0x79);  // 123456789012345 = 0x7048860DDF79, little-endian
    auto d = decodeImuSample(b);
    ASSERT_TRUE(d);
    EXPECT_EQ(d->t_host, s.t_host);
    EXPECT_EQ(d->t_device_ticks, s.t_device_ticks);
    EXPECT_EQ(d->accel_mps2_imu, s.accel_mps2_imu);
    EXPECT_EQ(d->gyro_radps_imu, s.gyro_radps_imu);
    EXPECT_EQ(d->status_word, s.status_word);
    EXPECT_EQ(d->packet_counter, s.packet_counter);
}

TEST(Channels, LaserScanRoundTripKeepsNaNsAndLists) {
    LaserScan s;
    s.t_host = 42;
    s.t_device_ms = 0xFFFFFF;
    s.step_period_ns = 17'361;
    s.first_step = 0;
    s.angle_min_rad = -2.356194490192345;
    s.angle_increment_rad = 0.004363323129985824;
    for (int i = 0; i < 1081; ++i)
        s.ranges_m.push_back(i % 100 == 0 ? NAN : 0.023f + 0.01f * static_cast<float>(i));
    s.intensities.assign(1081, 1234);
    s.error_codes.assign(1081, 0);
    s.error_codes[500] = 7;
    std::vector<std::uint8_t> b;
    encodeLaserScan(s, b);
    EXPECT_EQ(b.size(), 44u + 4 * 1081 + 4 + 2 * 1081 + 4 + 2 * 1081);
    auto d = decodeLaserScan(b);
    ASSERT_TRUE(d) << d.status().message();
    ASSERT_EQ(d->ranges_m.size(), 1081u);
    for (std::size_t i = 0; i < 1081; ++i) {
        if (std::isnan(s.ranges_m[i])) {
            EXPECT_TRUE(std::isnan(d->ranges_m[i]));
        } else {
            EXPECT_EQ(d->ranges_m[i], s.ranges_m[i]);
        }
    }
    EXPECT_EQ(d->intensities, s.intensities);
    EXPECT_EQ(d->error_codes, s.error_codes);
    EXPECT_EQ(d->angle_min_rad, s.angle_min_rad);
    EXPECT_EQ(d->step_period_ns, s.step_period_ns);
    EXPECT_EQ(d->t_device_ms, s.t_device_ms);

    b.resize(b.size() - 1);
    EXPECT_FALSE(decodeLaserScan(b));
    b.resize(40);
    auto bad = decodeLaserScan(b);
    ASSERT_FALSE(bad);
    EXPECT_EQ(bad.status().message(),
              "handscan.laser_scan.v1 message of 40 bytes: shorter than the 44-byte header");
}

TEST(Channels, EncoderGpioAndPoseRoundTrip) {
    std::vector<std::uint8_t> b;
    EncoderSample e{77, 0x12345678, 12.5, -3.25};
    encodeEncoderSample(e, b);
    ASSERT_EQ(b.size(), 28u);
    auto de = decodeEncoderSample(b);
    ASSERT_TRUE(de);
    EXPECT_EQ(de->raw_position, e.raw_position);
    EXPECT_EQ(de->angle_rad, e.angle_rad);
    EXPECT_EQ(de->speed_radps, e.speed_radps);

    GpioEdge g{99, 17, GpioEdgeType::kFalling};
    encodeGpioEdge(g, b);
    EXPECT_EQ(b, (std::vector<std::uint8_t>{99, 0, 0, 0, 0, 0, 0, 0, 17, 0, 0, 0, 2}));
    auto dg = decodeGpioEdge(b);
    ASSERT_TRUE(dg);
    EXPECT_EQ(dg->edge, GpioEdgeType::kFalling);
    b[12] = 3;
    EXPECT_EQ(decodeGpioEdge(b).status().message(),
              "handscan.gpio_edge message of 13 bytes: edge 3 is not 1 or 2");

    PoseEstimate p;
    p.t_host = 5;
    p.T_world_body.linear() =
        Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
    p.T_world_body.translation() = Eigen::Vector3d(1, 2, 3);
    p.covariance(2, 4) = 0.25;
    p.solved_dof_mask = 0x2B;
    p.source = PoseSource::kScanMatching;
    encodePoseEstimate(p, b);
    ASSERT_EQ(b.size(), 354u);
    auto dp = decodePoseEstimate(b);
    ASSERT_TRUE(dp);
    EXPECT_TRUE(dp->T_world_body.isApprox(p.T_world_body, 1e-12));
    EXPECT_EQ(dp->covariance, p.covariance);
    EXPECT_EQ(dp->solved_dof_mask, 0x2B);
    EXPECT_EQ(dp->source, PoseSource::kScanMatching);
}

TEST(Channels, AddChannelWritesEncodingAndDescription) {
    auto w = McapWriter::inMemory();
    ASSERT_TRUE(w);
    auto id = addChannel(**w, channels::kMotorCan);
    ASSERT_TRUE(id);
    const std::string line = "(1700000000.123456) can0 181#11223344";
    ASSERT_TRUE((*w)->write(
        *id, 1000, std::span(reinterpret_cast<const std::uint8_t*>(line.data()), line.size())));
    ASSERT_TRUE((*w)->close());
    auto r = McapReader::fromBuffer((*w)->takeBuffer());
    ASSERT_TRUE(r);
    const Channel* c = (*r)->findTopic("/motor/can");
    ASSERT_NE(c, nullptr);
    EXPECT_EQ(c->message_encoding, "handscan.candump_line");
    EXPECT_EQ(c->metadata.at("description"), channels::kMotorCan.description);
}

}  // namespace
}  // namespace handscan::recording
