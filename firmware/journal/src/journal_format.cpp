#include "handscan/journal/journal_format.hpp"

#include <zlib.h>

#include <algorithm>
#include <bit>
#include <cstring>

namespace handscan::journal {
namespace {

// Little-endian field access (the firmware runs on little-endian CPUs, but the format must not
// depend on it).
template <typename T>
void put(std::vector<std::uint8_t>& out, T v) {
    std::uint8_t raw[sizeof(T)];
    std::memcpy(raw, &v, sizeof(T));
    if constexpr (std::endian::native == std::endian::big) std::reverse(raw, raw + sizeof(T));
    out.insert(out.end(), raw, raw + sizeof(T));
}

template <typename T>
T get(const std::uint8_t* p) {
    std::uint8_t raw[sizeof(T)];
    std::memcpy(raw, p, sizeof(T));
    if constexpr (std::endian::native == std::endian::big) std::reverse(raw, raw + sizeof(T));
    T v;
    std::memcpy(&v, raw, sizeof(T));
    return v;
}

}  // namespace

std::uint32_t crc32(std::span<const std::uint8_t> bytes, std::uint32_t seed) {
    uLong c = seed;
    const std::uint8_t* p = bytes.data();
    std::size_t n = bytes.size();
    while (n > 0) {  // zlib takes uInt lengths
        const uInt step = static_cast<uInt>(std::min<std::size_t>(n, 1u << 30));
        c = ::crc32(c, p, step);
        p += step;
        n -= step;
    }
    return static_cast<std::uint32_t>(c);
}

std::vector<std::uint8_t> encodeHeader(const ChunkHeader& h) {
    std::vector<std::uint8_t> out;
    out.reserve(kChunkHeaderBytes);
    put(out, h.magic);
    put(out, h.version);
    put(out, static_cast<std::uint16_t>(h.kind));
    put(out, h.sequence);
    put(out, h.record_count);
    put(out, h.payload_bytes);
    put(out, h.t_last_s);
    put(out, h.payload_crc);
    put(out, crc32(std::span(out.data(), out.size())));
    return out;
}

bool decodeHeader(std::span<const std::uint8_t> bytes, ChunkHeader& h) {
    if (bytes.size() < kChunkHeaderBytes) return false;
    const std::uint8_t* p = bytes.data();
    h.magic = get<std::uint32_t>(p);
    h.version = get<std::uint16_t>(p + 4);
    h.kind = static_cast<ChunkKind>(get<std::uint16_t>(p + 6));
    h.sequence = get<std::uint64_t>(p + 8);
    h.record_count = get<std::uint32_t>(p + 16);
    h.payload_bytes = get<std::uint32_t>(p + 20);
    h.t_last_s = get<double>(p + 24);
    h.payload_crc = get<std::uint32_t>(p + 32);
    h.header_crc = get<std::uint32_t>(p + 36);
    return h.magic == kChunkMagic && h.version == kFormatVersion &&
           h.header_crc == crc32(bytes.subspan(0, kChunkHeaderBytes - 4));
}

void encodePoints(std::span<const MapPoint> points, std::vector<std::uint8_t>& out) {
    out.reserve(out.size() + points.size() * kPointRecordBytes);
    for (const MapPoint& p : points) {
        put(out, p.t_s);
        put(out, p.x);
        put(out, p.y);
        put(out, p.z);
        out.push_back(p.r);
        out.push_back(p.g);
        out.push_back(p.b);
        out.push_back(0);  // reserved
        put(out, p.intensity);
        put(out, std::uint16_t{0});  // reserved
    }
}

void decodePoints(std::span<const std::uint8_t> payload, std::span<MapPoint> out) {
    const std::size_t n = std::min(out.size(), payload.size() / kPointRecordBytes);
    for (std::size_t i = 0; i < n; ++i) {
        const std::uint8_t* p = payload.data() + i * kPointRecordBytes;
        MapPoint& m = out[i];
        m.t_s = get<double>(p);
        m.x = get<float>(p + 8);
        m.y = get<float>(p + 12);
        m.z = get<float>(p + 16);
        m.r = p[20];
        m.g = p[21];
        m.b = p[22];
        m.intensity = get<std::uint16_t>(p + 24);
    }
}

void decodePoints(std::span<const std::uint8_t> payload, std::vector<MapPoint>& out) {
    const std::size_t first = out.size();
    out.resize(first + payload.size() / kPointRecordBytes);
    decodePoints(payload, std::span<MapPoint>(out).subspan(first));
}

void encodePoses(std::span<const TrajectoryPose> poses, std::vector<std::uint8_t>& out) {
    for (const TrajectoryPose& p : poses) {
        for (double v : {p.t_s, p.x, p.y, p.z, p.qx, p.qy, p.qz, p.qw}) put(out, v);
    }
}

void decodePoses(std::span<const std::uint8_t> payload, std::vector<TrajectoryPose>& out) {
    const std::size_t n = payload.size() / kPoseRecordBytes;
    for (std::size_t i = 0; i < n; ++i) {
        const std::uint8_t* p = payload.data() + i * kPoseRecordBytes;
        TrajectoryPose t;
        double* fields[] = {&t.t_s, &t.x, &t.y, &t.z, &t.qx, &t.qy, &t.qz, &t.qw};
        for (int k = 0; k < 8; ++k) *fields[k] = get<double>(p + 8 * k);
        out.push_back(t);
    }
}

namespace {

std::size_t putSweep(const SweepRecord& r, std::vector<std::uint8_t>& out) {
    const std::size_t start = out.size();
    const std::size_t reason = std::min<std::size_t>(r.tracking_reason.size(), 255);
    put(out, static_cast<std::uint16_t>(kSweepRecordBytes + reason));
    put(out, kSweepRecordLayout);
    put(out, r.t_start_s);
    put(out, r.index);
    out.push_back(r.solved_mask);
    out.push_back(r.vio_mask);
    out.push_back(static_cast<std::uint8_t>(r.tracking));
    out.push_back(r.in_map ? 1 : 0);
    out.push_back(static_cast<std::uint8_t>(r.vio));
    out.push_back(static_cast<std::uint8_t>(reason));
    put(out, std::uint16_t{0});  // reserved
    for (std::uint32_t v : {r.points, r.edges, r.planars}) put(out, v);
    put(out, r.associations);
    put(out, r.rms_m);
    put(out, r.total_ms);
    for (double v : r.pose) put(out, v);
    for (double v : r.prior_xyz) put(out, v);
    const DeviceCounts& d = r.devices;
    put(out, d.window_s);
    for (std::uint32_t v :
         {d.laser_scans, d.imu_samples, d.encoder_samples, d.colour_frames, d.tracking_frames})
        put(out, v);
    out.insert(out.end(), r.tracking_reason.begin(),
               r.tracking_reason.begin() + static_cast<std::ptrdiff_t>(reason));
    return out.size() - start;
}

// A record is the fixed fields, what a later layout appends, then the reason's text (the last
// bytes, so a reader finds it whatever was appended).
SweepRecord getSweep(const std::uint8_t* p, std::size_t record_bytes, std::size_t reason_bytes) {
    SweepRecord r;
    r.t_start_s = get<double>(p + 4);
    r.index = get<std::uint64_t>(p + 12);
    r.solved_mask = p[20];
    r.vio_mask = p[21];
    r.tracking = static_cast<SweepTracking>(std::min<std::uint8_t>(p[22], 2));
    r.in_map = p[23] != 0;
    r.vio = static_cast<SweepVio>(std::min<std::uint8_t>(p[24], 2));
    std::size_t o = 28;
    for (std::uint32_t* v : {&r.points, &r.edges, &r.planars}) {
        *v = get<std::uint32_t>(p + o);
        o += 4;
    }
    r.associations = get<std::int32_t>(p + o);
    o += 4;
    r.rms_m = get<double>(p + o);
    r.total_ms = get<double>(p + o + 8);
    o += 16;
    for (double& v : r.pose) {
        v = get<double>(p + o);
        o += 8;
    }
    for (double& v : r.prior_xyz) {
        v = get<double>(p + o);
        o += 8;
    }
    DeviceCounts& d = r.devices;
    d.window_s = get<double>(p + o);
    o += 8;
    for (std::uint32_t* v : {&d.laser_scans, &d.imu_samples, &d.encoder_samples, &d.colour_frames,
                             &d.tracking_frames}) {
        *v = get<std::uint32_t>(p + o);
        o += 4;
    }
    r.tracking_reason.assign(reinterpret_cast<const char*>(p + record_bytes - reason_bytes),
                             reason_bytes);
    return r;
}

}  // namespace

void encodeSweeps(std::span<const SweepRecord> sweeps, std::vector<std::uint8_t>& out) {
    for (const SweepRecord& r : sweeps) putSweep(r, out);
}

std::string decodeSweeps(std::span<const std::uint8_t> payload, std::vector<SweepRecord>& out) {
    std::size_t offset = 0;
    for (std::size_t k = 0; offset < payload.size(); ++k) {
        const std::string where =
            "record " + std::to_string(k) + " at payload byte " + std::to_string(offset) + ": ";
        const std::size_t left = payload.size() - offset;
        if (left < 4) return where + "truncated (" + std::to_string(left) + " bytes left)";
        const std::uint8_t* p = payload.data() + offset;
        const std::size_t bytes = get<std::uint16_t>(p);
        const std::uint16_t layout = get<std::uint16_t>(p + 2);
        if (layout == 0 || bytes < kSweepRecordBytes)
            return where + "not a sweep record (layout " + std::to_string(layout) + ", " +
                   std::to_string(bytes) + " bytes)";
        if (bytes > left)
            return where + "truncated (" + std::to_string(bytes) + " bytes, " +
                   std::to_string(left) + " left)";
        const std::size_t reason = p[25];
        if (kSweepRecordBytes + reason > bytes) return where + "reason text runs past the record";
        out.push_back(getSweep(p, bytes, reason));
        offset += bytes;
    }
    return {};
}

int SweepRecord::degenerateDirections() const {
    return 6 - std::popcount(static_cast<unsigned>(solved_mask & 0x3F));
}

const char* sweepTrackingName(SweepTracking t) {
    switch (t) {
        case SweepTracking::kRejected:
            return "rejected";
        case SweepTracking::kLost:
            return "lost";
        default:
            return "ok";
    }
}

}  // namespace handscan::journal
