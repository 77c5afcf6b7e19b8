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

}  // namespace handscan::journal
