#include "handscan/prior_map/feature_map_file.hpp"

#include <cstring>
#include <fstream>
#include <iterator>
#include <vector>

#include "handscan/export/safe_file.hpp"
#include "handscan/journal/journal_format.hpp"

namespace handscan::prior_map {
namespace {

constexpr char kMagic[4] = {'H', 'S', 'F', 'M'};
constexpr std::uint16_t kVersion = 1;
constexpr std::size_t kHeaderBytes = 16;

template <typename T>
void put(std::vector<std::uint8_t>& out, T v) {
    std::uint8_t b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));  // little-endian hosts only (x86-64, ARMv8)
    out.insert(out.end(), b, b + sizeof(T));
}

template <typename T>
T get(const std::uint8_t* p) {
    T v;
    std::memcpy(&v, p, sizeof(T));
    return v;
}

void putPoints(std::vector<std::uint8_t>& out, const std::vector<Eigen::Vector3f>& pts) {
    for (const Eigen::Vector3f& p : pts) {
        put(out, p.x());
        put(out, p.y());
        put(out, p.z());
    }
}

std::vector<Eigen::Vector3f> getPoints(const std::uint8_t*& p, std::uint32_t n) {
    std::vector<Eigen::Vector3f> pts(n);
    for (Eigen::Vector3f& q : pts) {
        q = {get<float>(p), get<float>(p + 4), get<float>(p + 8)};
        p += 12;
    }
    return pts;
}

}  // namespace

Status writeFeatureMap(const std::string& path, const scan::FeatureMapPoints& map) {
    if (map.planar_origins.size() != map.planars.size())
        return Status(StatusCode::kInvalidArgument,
                      path + ": planar origins do not match the planar points");
    std::vector<std::uint8_t> bytes;
    bytes.reserve(kHeaderBytes + 12 * (map.edges.size() + 2 * map.planars.size()) + 4);
    bytes.insert(bytes.end(), kMagic, kMagic + 4);
    put(bytes, kVersion);
    put(bytes, std::uint16_t{0});
    put(bytes, static_cast<std::uint32_t>(map.edges.size()));
    put(bytes, static_cast<std::uint32_t>(map.planars.size()));
    putPoints(bytes, map.edges);
    putPoints(bytes, map.planars);
    putPoints(bytes, map.planar_origins);
    put(bytes, journal::crc32(bytes));
    exporter::SafeFileWriter f(path);
    if (Status s = f.open(); !s.isOk()) return s;
    if (Status s = f.write(bytes); !s.isOk()) return s;
    return f.commit();
}

Result<scan::FeatureMapPoints> readFeatureMap(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in)
        return Status(StatusCode::kNotFound,
                      path +
                          ": cannot open the feature map (written by `handscan replay` and the "
                          "daemon at the end of a scan)");
    const std::vector<std::uint8_t> b((std::istreambuf_iterator<char>(in)),
                                      std::istreambuf_iterator<char>());
    auto bad = [&](const std::string& what) {
        return Status(StatusCode::kInvalidArgument, path + ": " + what);
    };
    if (b.size() < kHeaderBytes + 4) return bad("truncated (shorter than its header)");
    if (std::memcmp(b.data(), kMagic, 4) != 0) return bad("not a feature map (bad magic)");
    if (get<std::uint16_t>(&b[4]) != kVersion)
        return bad("feature map version " + std::to_string(get<std::uint16_t>(&b[4])) +
                   ", this build reads version 1");
    const std::uint32_t edges = get<std::uint32_t>(&b[8]);
    const std::uint32_t planars = get<std::uint32_t>(&b[12]);
    const std::uint64_t expected =
        kHeaderBytes + 12ull * (std::uint64_t{edges} + 2ull * planars) + 4;
    if (b.size() != expected)
        return bad("size " + std::to_string(b.size()) + " bytes, expected " +
                   std::to_string(expected) + " for its point counts (truncated?)");
    const std::uint32_t crc = get<std::uint32_t>(&b[b.size() - 4]);
    if (journal::crc32(std::span(b.data(), b.size() - 4)) != crc)
        return bad("CRC mismatch (damaged file)");
    scan::FeatureMapPoints map;
    const std::uint8_t* p = b.data() + kHeaderBytes;
    map.edges = getPoints(p, edges);
    map.planars = getPoints(p, planars);
    map.planar_origins = getPoints(p, planars);
    return map;
}

}  // namespace handscan::prior_map
