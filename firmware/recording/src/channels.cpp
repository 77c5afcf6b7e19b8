#include "handscan/recording/channels.hpp"

#include <array>
#include <string>

#include "byte_io.hpp"
#include "handscan/recording/mcap_writer.hpp"

namespace handscan::recording {
namespace {

using detail::ByteReader;
using detail::ByteWriter;

constexpr std::array<ChannelSpec, 11> kAll = {
    channels::kHokuyoRaw,    channels::kXsensRaw,       channels::kMotorCan,
    channels::kCameraTrack,  channels::kCameraColour,   channels::kGpioEvents,
    channels::kImuSamples,   channels::kLaserScans,     channels::kEncoderAngle,
    channels::kPoseEstimate, channels::kGroundTruthPose};

Status malformed(std::string_view encoding, std::size_t size, std::string_view why) {
    return {StatusCode::kProtocolError, std::string(encoding) + " message of " +
                                            std::to_string(size) + " bytes: " + std::string(why)};
}

// The fixed-size records must match their size exactly: a different size means another layout.
Status expectSize(std::string_view encoding, std::span<const std::uint8_t> bytes,
                  std::size_t size) {
    if (bytes.size() == size) return Status::ok();
    return malformed(encoding, bytes.size(), "expected exactly " + std::to_string(size));
}

void writeVec3(ByteWriter& w, const Eigen::Vector3d& v) {
    for (int i = 0; i < 3; ++i) w.f64(v[i]);
}
bool readVec3(ByteReader& r, Eigen::Vector3d& v) {
    return r.f64(v[0]) && r.f64(v[1]) && r.f64(v[2]);
}

void writeQuat(ByteWriter& w, const Eigen::Quaterniond& q) {
    w.f64(q.x());
    w.f64(q.y());
    w.f64(q.z());
    w.f64(q.w());
}
bool readQuat(ByteReader& r, Eigen::Quaterniond& q) {
    return r.f64(q.x()) && r.f64(q.y()) && r.f64(q.z()) && r.f64(q.w());
}

}  // namespace

std::span<const ChannelSpec> knownChannels() { return kAll; }

const ChannelSpec* findChannel(std::string_view topic) {
    for (const auto& c : kAll) {
        if (c.topic == topic) return &c;
    }
    return nullptr;
}

Result<std::uint16_t> addChannel(McapWriter& writer, const ChannelSpec& spec) {
    return writer.addChannel(std::string(spec.topic), std::string(spec.message_encoding), 0,
                             {{"description", std::string(spec.description)}});
}

void encodeGpioEdge(const GpioEdge& e, std::vector<std::uint8_t>& out) {
    out.clear();
    ByteWriter w(out);
    w.i64(e.t_host);
    w.u32(e.line);
    w.u8(static_cast<std::uint8_t>(e.edge));
}

Result<GpioEdge> decodeGpioEdge(std::span<const std::uint8_t> bytes) {
    const auto enc = channels::kGpioEvents.message_encoding;
    if (Status s = expectSize(enc, bytes, 13); !s) return s;
    ByteReader r(bytes);
    GpioEdge e;
    std::uint32_t line = 0;
    std::uint8_t edge = 0;
    (void)(r.i64(e.t_host) && r.u32(line) && r.u8(edge));
    if (edge != 1 && edge != 2)
        return malformed(enc, bytes.size(), "edge " + std::to_string(edge) + " is not 1 or 2");
    e.line = line;
    e.edge = static_cast<GpioEdgeType>(edge);
    return e;
}

void encodeImuSample(const ImuSample& s, std::vector<std::uint8_t>& out) {
    out.clear();
    ByteWriter w(out);
    w.i64(s.t_host);
    w.i64(s.t_device_ticks);
    writeVec3(w, s.accel_mps2_imu);
    writeVec3(w, s.gyro_radps_imu);
    w.u32(s.status_word);
    w.u16(s.packet_counter);
}

Result<ImuSample> decodeImuSample(std::span<const std::uint8_t> bytes) {
    if (Status s = expectSize(channels::kImuSamples.message_encoding, bytes, 70); !s) return s;
    ByteReader r(bytes);
    ImuSample s;
    (void)(r.i64(s.t_host) && r.i64(s.t_device_ticks) && readVec3(r, s.accel_mps2_imu) &&
           readVec3(r, s.gyro_radps_imu) && r.u32(s.status_word) && r.u16(s.packet_counter));
    return s;
}

void encodeLaserScan(const LaserScan& s, std::vector<std::uint8_t>& out) {
    out.clear();
    out.reserve(60 + 4 * s.ranges_m.size() + 2 * (s.intensities.size() + s.error_codes.size()));
    ByteWriter w(out);
    w.i64(s.t_host);
    w.u32(s.t_device_ms);
    w.i64(s.step_period_ns);
    w.i32(s.first_step);
    w.f64(s.angle_min_rad);
    w.f64(s.angle_increment_rad);
    w.u32(static_cast<std::uint32_t>(s.ranges_m.size()));
    for (float v : s.ranges_m) w.f32(v);
    w.u32(static_cast<std::uint32_t>(s.intensities.size()));
    for (std::uint16_t v : s.intensities) w.u16(v);
    w.u32(static_cast<std::uint32_t>(s.error_codes.size()));
    for (std::uint16_t v : s.error_codes) w.u16(v);
}

Result<LaserScan> decodeLaserScan(std::span<const std::uint8_t> bytes) {
    const auto enc = channels::kLaserScans.message_encoding;
    ByteReader r(bytes);
    LaserScan s;
    std::uint32_t n = 0;
    if (!(r.i64(s.t_host) && r.u32(s.t_device_ms) && r.i64(s.step_period_ns) &&
          r.i32(s.first_step) && r.f64(s.angle_min_rad) && r.f64(s.angle_increment_rad) &&
          r.u32(n))) {
        return malformed(enc, bytes.size(), "shorter than the 44-byte header");
    }
    if (r.remaining() / 4 < n)
        return malformed(enc, bytes.size(), std::to_string(n) + " ranges do not fit");
    s.ranges_m.resize(n);
    for (float& v : s.ranges_m) (void)r.f32(v);
    for (auto* list : {&s.intensities, &s.error_codes}) {
        std::uint32_t m = 0;
        if (!r.u32(m) || r.remaining() / 2 < m)
            return malformed(enc, bytes.size(), "intensity/error list cut short");
        list->resize(m);
        for (std::uint16_t& v : *list) (void)r.u16(v);
    }
    if (r.remaining() != 0)
        return malformed(enc, bytes.size(), std::to_string(r.remaining()) + " trailing bytes");
    return s;
}

void encodeEncoderSample(const EncoderSample& s, std::vector<std::uint8_t>& out) {
    out.clear();
    ByteWriter w(out);
    w.i64(s.t_host);
    w.u32(s.raw_position);
    w.f64(s.angle_rad);
    w.f64(s.speed_radps);
}

Result<EncoderSample> decodeEncoderSample(std::span<const std::uint8_t> bytes) {
    if (Status s = expectSize(channels::kEncoderAngle.message_encoding, bytes, 28); !s) return s;
    ByteReader r(bytes);
    EncoderSample s;
    (void)(r.i64(s.t_host) && r.u32(s.raw_position) && r.f64(s.angle_rad) && r.f64(s.speed_radps));
    return s;
}

void encodePoseEstimate(const PoseEstimate& p, std::vector<std::uint8_t>& out) {
    out.clear();
    ByteWriter w(out);
    w.i64(p.t_host);
    writeVec3(w, p.T_world_body.translation());
    writeQuat(w, Eigen::Quaterniond(p.T_world_body.rotation()));
    for (int i = 0; i < 6; ++i) {
        for (int j = 0; j < 6; ++j) w.f64(p.covariance(i, j));
    }
    w.u8(p.solved_dof_mask);
    w.u8(static_cast<std::uint8_t>(p.source));
}

Result<PoseEstimate> decodePoseEstimate(std::span<const std::uint8_t> bytes) {
    const auto enc = channels::kPoseEstimate.message_encoding;
    if (Status s = expectSize(enc, bytes, 8 + 24 + 32 + 288 + 2); !s) return s;
    ByteReader r(bytes);
    PoseEstimate p;
    Eigen::Vector3d t;
    Eigen::Quaterniond q;
    (void)(r.i64(p.t_host) && readVec3(r, t) && readQuat(r, q));
    for (int i = 0; i < 6; ++i) {
        for (int j = 0; j < 6; ++j) (void)r.f64(p.covariance(i, j));
    }
    std::uint8_t source = 0;
    (void)(r.u8(p.solved_dof_mask) && r.u8(source));
    if (source > static_cast<std::uint8_t>(PoseSource::kIntegrated)) {
        return malformed(enc, bytes.size(), "unknown pose source " + std::to_string(source));
    }
    p.source = static_cast<PoseSource>(source);
    p.T_world_body = Eigen::Isometry3d::Identity();
    p.T_world_body.linear() = q.normalized().toRotationMatrix();
    p.T_world_body.translation() = t;
    return p;
}

void encodeGroundTruthPose(const GroundTruthPose& p, std::vector<std::uint8_t>& out) {
    out.clear();
    ByteWriter w(out);
    w.f64(toSeconds(p.t));
    writeVec3(w, p.p_world_body);
    writeQuat(w, p.q_world_body);
}

Result<GroundTruthPose> decodeGroundTruthPose(std::span<const std::uint8_t> bytes) {
    if (Status s = expectSize(channels::kGroundTruthPose.message_encoding, bytes, 64); !s) return s;
    ByteReader r(bytes);
    GroundTruthPose p;
    double t = 0;
    (void)(r.f64(t) && readVec3(r, p.p_world_body) && readQuat(r, p.q_world_body));
    p.t = fromSeconds(t);
    return p;
}

}  // namespace handscan::recording
