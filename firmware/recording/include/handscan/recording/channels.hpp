// The channels of a handscan recording: topic names, message encodings and, for the records we
// define, their byte layouts with encode/decode functions. Every part of the project (drivers'
// recording taps, the simulator, replay, `handscan info` and `decode`) names channels through
// this header.
//
// Every message's MCAP log_time (and publish_time) is the host CLOCK_MONOTONIC receive time
// (TimeNs) of the bytes; sequence counts messages per channel from 0. No channel has an MCAP
// schema (schema_id 0): the message_encoding string names the layout documented here.
//
// Raw device streams (exact device bytes, replayed through the real drivers):
//   /hokuyo/raw     handscan.scip2_tcp      TCP payload bytes from the UTM-30LX-EW exactly as each
//                                           recv() returned them (SCIP 2.0; commands we sent are
//                                           not included). Frames may span messages.
//   /xsens/raw      handscan.xbus_bytes     bytes read from the MTi's serial/USB port (Xbus
//                                           MTData2 and replies), one message per read().
//   /motor/can      handscan.candump_line   one CAN frame per message as a `candump -l` log line
//                                           without newline, "(sec.usec) can0 181#11223344"
//                                           (layout owned by drivers/motor candump_format.hpp).
//   /camera/track   handscan.v4l2_buffer    one dequeued V4L2 buffer per message: metadata header
//   /camera/colour  handscan.v4l2_buffer    + image bytes (layout owned by the camera codec,
//                                           drivers/camera frame_record.hpp: record version 1
//                                           holds the buffer's bytes as they are; version 2 holds
//                                           GREY/YUYV buffers as lossless PNG that decodes back
//                                           to exactly those bytes; MJPEG is always stored as is).
//   /gpio/events    handscan.gpio_edge      one line event per message (layout below).
// Decoded channels (ours, little-endian, layouts below):
//   /imu/samples      handscan.imu_sample.v1
//   /laser/scans      handscan.laser_scan.v1
//   /encoder/angle    handscan.encoder_sample.v1
//   /pose/estimate    handscan.pose_estimate.v1
//   /groundtruth/pose handscan.groundtruth_pose.v1
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "handscan/core/samples.hpp"
#include "handscan/core/status.hpp"
#include "handscan/core/time.hpp"

namespace handscan::recording {

struct ChannelSpec {
    std::string_view topic;
    std::string_view message_encoding;
    bool raw = false;              // exact device bytes (replayable through a driver)
    std::string_view description;  // written as the channel's "description" metadata
};

namespace channels {
inline constexpr ChannelSpec kHokuyoRaw{
    "/hokuyo/raw", "handscan.scip2_tcp", true,
    "Hokuyo UTM-30LX-EW SCIP 2.0 TCP payload bytes as received"};
inline constexpr ChannelSpec kXsensRaw{"/xsens/raw", "handscan.xbus_bytes", true,
                                       "Xsens MTi Xbus bytes as read from the serial/USB port"};
inline constexpr ChannelSpec kMotorCan{"/motor/can", "handscan.candump_line", true,
                                       "one CAN frame per message as a candump -l log line"};
inline constexpr ChannelSpec kCameraTrack{
    "/camera/track", "handscan.v4l2_buffer", true,
    "tracking camera: one V4L2 buffer with its metadata per message (HSVF record: "
    "v1 raw bytes, v2 GREY/YUYV as lossless PNG of stride x height)"};
inline constexpr ChannelSpec kCameraColour{
    "/camera/colour", "handscan.v4l2_buffer", true,
    "colour camera: one V4L2 buffer with its metadata per message (HSVF record: "
    "v1 raw bytes, v2 GREY/YUYV as lossless PNG of stride x height)"};
inline constexpr ChannelSpec kGpioEvents{
    "/gpio/events", "handscan.gpio_edge", true,
    "GPIO line edges: i64 t_event_ns, u32 line, u8 edge (1 rising, 2 falling)"};
inline constexpr ChannelSpec kImuSamples{"/imu/samples", "handscan.imu_sample.v1", false,
                                         "decoded IMU samples (handscan/recording/channels.hpp)"};
inline constexpr ChannelSpec kLaserScans{
    "/laser/scans", "handscan.laser_scan.v1", false,
    "decoded 2D laser scans (handscan/recording/channels.hpp)"};
inline constexpr ChannelSpec kEncoderAngle{
    "/encoder/angle", "handscan.encoder_sample.v1", false,
    "decoded motor-encoder shaft angles (handscan/recording/channels.hpp)"};
inline constexpr ChannelSpec kPoseEstimate{
    "/pose/estimate", "handscan.pose_estimate.v1", false,
    "pipeline pose estimates T_world_body (handscan/recording/channels.hpp)"};
inline constexpr ChannelSpec kGroundTruthPose{
    "/groundtruth/pose", "handscan.groundtruth_pose.v1", false,
    "ground truth T_world_body: f64 t_s, x, y, z, qx, qy, qz, qw"};
}  // namespace channels

class McapWriter;

// Every channel above, raw streams first.
std::span<const ChannelSpec> knownChannels();
// The spec of a known topic, or nullptr.
const ChannelSpec* findChannel(std::string_view topic);
// Adds the channel to a writer (with its description as metadata); returns its id.
[[nodiscard]] Result<std::uint16_t> addChannel(McapWriter& writer, const ChannelSpec& spec);

// ---- handscan.gpio_edge (13 bytes) -------------------------------------------------------------
//   i64 t_event_ns   kernel event timestamp (CLOCK_MONOTONIC on kernel >= 5.7), in GpioEdge::t_host
//   u32 line         line offset on the chip
//   u8  edge         1 rising, 2 falling (libgpiod's GPIOD_LINE_EVENT_* values)
void encodeGpioEdge(const GpioEdge& e, std::vector<std::uint8_t>& out);
[[nodiscard]] Result<GpioEdge> decodeGpioEdge(std::span<const std::uint8_t> bytes);

// ---- handscan.imu_sample.v1 (70 bytes) ---------------------------------------------------------
//   i64 t_host_ns, i64 t_device_ticks, f64 accel_mps2_imu[3], f64 gyro_radps_imu[3],
//   u32 status_word, u16 packet_counter
void encodeImuSample(const ImuSample& s, std::vector<std::uint8_t>& out);
[[nodiscard]] Result<ImuSample> decodeImuSample(std::span<const std::uint8_t> bytes);

// ---- handscan.laser_scan.v1 (44 + 4 n + 4 + 2 ni + 4 + 2 ne bytes) -----------------------------
//   i64 t_host_ns (step 0), u32 t_device_ms, i64 step_period_ns, i32 first_step,
//   f64 angle_min_rad, f64 angle_increment_rad,
//   u32 n, f32 ranges_m[n] (NaN = no return), u32 ni, u16 intensities[ni], u32 ne, u16
//   error_codes[ne]
void encodeLaserScan(const LaserScan& s, std::vector<std::uint8_t>& out);
[[nodiscard]] Result<LaserScan> decodeLaserScan(std::span<const std::uint8_t> bytes);

// ---- handscan.encoder_sample.v1 (28 bytes) -----------------------------------------------------
//   i64 t_host_ns, u32 raw_position, f64 angle_rad (unwrapped), f64 speed_radps
void encodeEncoderSample(const EncoderSample& s, std::vector<std::uint8_t>& out);
[[nodiscard]] Result<EncoderSample> decodeEncoderSample(std::span<const std::uint8_t> bytes);

// ---- handscan.pose_estimate.v1 (354 bytes) -----------------------------------------------------
//   i64 t_host_ns, f64 p_world_body[3] (m), f64 q_world_body[4] (x, y, z, w),
//   f64 covariance[36] (row-major, order rx ry rz tx ty tz), u8 solved_dof_mask, u8 source
void encodePoseEstimate(const PoseEstimate& p, std::vector<std::uint8_t>& out);
[[nodiscard]] Result<PoseEstimate> decodePoseEstimate(std::span<const std::uint8_t> bytes);

// ---- handscan.groundtruth_pose.v1 (64 bytes) ---------------------------------------------------
//   f64 t_s (host clock, seconds), f64 x, y, z (m, world), f64 qx, qy, qz, qw (body -> world)
// The same fields, in the same order, as a line of a TUM trajectory file.
struct GroundTruthPose {
    TimeNs t = 0;
    Eigen::Vector3d p_world_body = Eigen::Vector3d::Zero();
    Eigen::Quaterniond q_world_body = Eigen::Quaterniond::Identity();
};
void encodeGroundTruthPose(const GroundTruthPose& p, std::vector<std::uint8_t>& out);
[[nodiscard]] Result<GroundTruthPose> decodeGroundTruthPose(std::span<const std::uint8_t> bytes);

}  // namespace handscan::recording
