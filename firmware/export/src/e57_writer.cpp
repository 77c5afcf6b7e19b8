// ASTM E2807 (E57) writer: page 0 holds the file header (patched at the end), then the trajectory's
// compressed vector section, the points' section (its size follows from the point count, so its
// header goes first and the points stream through once), and the XML section. Each section ends
// in its index packets.
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "crc32c.hpp"
#include "e57_format.hpp"
#include "e57_packets.hpp"
#include "e57_page_check.hpp"
#include "e57_pages.hpp"
#include "e57_xml.hpp"
#include "handscan/export/point_formats.hpp"

namespace handscan::exporter {
namespace {

using namespace e57;

// cartesianX/Y/Z (double, or 32-bit scaled integers), intensity (16 bit), colorRed/Green/Blue
// (8 bit), isColorInvalid (1 bit), timeStamp (double): the prototype's order (e57_xml.cpp).
constexpr std::array<unsigned, 9> kPointBits = {64, 64, 64, 16, 8, 8, 8, 1, 64};
constexpr std::array<unsigned, 9> kScaledPointBits = {32, 32, 32, 16, 8, 8, 8, 1, 64};
// The scaled integers' raw range: a fixed 32 bits, because the bounds are only known once the
// points have streamed through and the section's size must be known before (±214 km at 0.1 mm).
constexpr std::int64_t kRawMin = std::numeric_limits<std::int32_t>::min();
constexpr std::int64_t kRawMax = std::numeric_limits<std::int32_t>::max();
constexpr std::size_t kPointsPerPacket = 1024;  // 37 KiB packets: under the 64 KiB limit
// timeStamp, x, y, z, qw, qx, qy, qz: all double.
constexpr std::array<unsigned, 8> kPoseBits = {64, 64, 64, 64, 64, 64, 64, 64};
constexpr std::size_t kPosesPerPacket = 512;

static_assert(packetBytes(std::span(kPointBits), kPointsPerPacket) <= kMaxPacketBytes);
static_assert(packetBytes(std::span(kPoseBits), kPosesPerPacket) <= kMaxPacketBytes);

double gpsSecondsNow() {  // E57 DateTime: GPS seconds (from 1980-01-06, 18 leap seconds ahead)
    const double unix_s =
        std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
    return unix_s - 315964800.0 + 18.0;
}

template <typename T>
void column(std::uint8_t* out, std::size_t i, T v) {
    std::memcpy(out + i * sizeof(T), &v, sizeof(T));
}

class E57Writer final : public PointFileWriter {
public:
    E57Writer(SafeFileWriter& file, E57Options options)
        : file_(file),
          opt_(std::move(options)),
          pages_(file),
          point_bits_(opt_.coordinate_scale > 0 ? kScaledPointBits : kPointBits) {
        file_.setReadBackCheck(
            [checker = std::make_shared<PageChecker>()](std::span<const std::uint8_t> bytes) {
                return checker->feed(bytes);
            });
    }

    Status begin(std::uint64_t count) override {
        expected_ = count;
        if (Status s = file_.reserveHeader(kPageBytes); !s.isOk()) return s;
        if (!opt_.trajectory.empty()) {
            if (Status s = writeTrajectory(); !s.isOk()) return s;
        }
        points_logical_ = pages_.logicalOffset();
        const auto header = sectionHeader(points_logical_, point_bits_, count, kPointsPerPacket);
        pending_.reserve(kPointsPerPacket);
        return pages_.append(header);
    }

    Status write(std::span<const journal::MapPoint> points) override {
        written_ += points.size();
        while (!points.empty()) {
            const std::size_t n = std::min(points.size(), kPointsPerPacket - pending_.size());
            pending_.insert(pending_.end(), points.begin(), points.begin() + n);
            points = points.subspan(n);
            if (pending_.size() == kPointsPerPacket) {
                if (Status s = flushPacket(); !s.isOk()) return s;
            }
        }
        return Status::ok();
    }

    Status end() override {
        if (written_ != expected_) {
            return Status(StatusCode::kInvalidArgument,
                          "export " + file_.finalPath() + ": wrote " + std::to_string(written_) +
                              " points, expected " + std::to_string(expected_));
        }
        if (!pending_.empty()) {
            if (Status s = flushPacket(); !s.isOk()) return s;
        }
        if (Status s = writeIndex(std::move(index_)); !s.isOk()) return s;
        const std::uint64_t xml_logical = pages_.logicalOffset();
        const std::string xml = scanXml(xmlInputs());
        if (Status s =
                pages_.append({reinterpret_cast<const std::uint8_t*>(xml.data()), xml.size()});
            !s.isOk())
            return s;
        if (Status s = pages_.finish(); !s.isOk()) return s;
        std::vector<std::uint8_t> page0(kPageBytes, 0);
        std::memcpy(page0.data(), kSignature, 8);
        putLe<std::uint32_t>(page0.data() + 8, 1);   // major version
        putLe<std::uint32_t>(page0.data() + 12, 0);  // minor version
        putLe<std::uint64_t>(page0.data() + 16, pages_.physicalLength());
        putLe<std::uint64_t>(page0.data() + 24, physicalOf(xml_logical));
        putLe<std::uint64_t>(page0.data() + 32, xml.size());
        putLe<std::uint64_t>(page0.data() + 40, kPageBytes);
        putCrcBigEndian(page0.data() + kPagePayload, crc32c({page0.data(), kPagePayload}));
        if (Status s = file_.patchHeader(page0); !s.isOk()) return s;
        return file_.commit();
    }

private:
    ScanXml xmlInputs() const {
        ScanXml x;
        x.file_guid = randomGuid();
        x.scan_guid = randomGuid();
        x.name = opt_.scan_name;
        x.description = opt_.description;
        x.sensor_vendor = opt_.sensor_vendor;
        x.sensor_model = opt_.sensor_model;
        x.sensor_serial = opt_.sensor_serial;
        x.software_version = opt_.software_version;
        x.creation_gps_s = gpsSecondsNow();
        x.points = written_;
        x.points_offset = physicalOf(points_logical_);
        x.bounds = bounds_;
        x.trajectory_poses = opt_.trajectory.size();
        x.trajectory_offset = physicalOf(trajectory_logical_);
        x.coordinate_scale = opt_.coordinate_scale;
        x.coordinate_raw_min = kRawMin;
        x.coordinate_raw_max = kRawMax;
        return x;
    }

    // One packet of the pending points; bounds gathered on the way.
    Status flushPacket() {
        const std::size_t n = pending_.size();
        index_.emplace_back(written_packets_records_, physicalOf(pages_.logicalOffset()));
        written_packets_records_ += n;
        const auto s = layOutPacket(packet_, point_bits_, n);
        std::memset(s[7], 0, streamBytes(1, n));
        for (std::size_t i = 0; i < n; ++i) {
            const journal::MapPoint& p = pending_[i];
            bounds_.add(p.x, p.y, p.z);
            if (opt_.coordinate_scale > 0) {
                if (Status st = scaledCoordinates(p, s, i); !st.isOk()) return st;
            } else {
                column<double>(s[0], i, p.x);
                column<double>(s[1], i, p.y);
                column<double>(s[2], i, p.z);
            }
            column<std::uint16_t>(s[3], i, p.intensity);
            s[4][i] = p.r;
            s[5][i] = p.g;
            s[6][i] = p.b;
            // A point no camera frame saw carries its laser grey: its colour is invalid.
            const bool invalid = !journal::hasColour(p);
            s[7][i / 8] = static_cast<std::uint8_t>(s[7][i / 8] | (invalid << (i % 8)));
            column<double>(s[8], i, p.t_s);
        }
        pending_.clear();
        return pages_.append(packet_);
    }

    // x, y, z as raw integers of the scale (E57 ScaledInteger: value = raw * scale), stored as
    // raw - minimum in 32 bits.
    Status scaledCoordinates(const journal::MapPoint& p, const std::array<std::uint8_t*, 9>& s,
                             std::size_t i) const {
        const double v[3] = {p.x, p.y, p.z};
        for (int a = 0; a < 3; ++a) {
            const double raw = std::round(v[a] / opt_.coordinate_scale);
            if (!(raw >= double(kRawMin) && raw <= double(kRawMax))) {
                return Status(StatusCode::kInvalidArgument,
                              "export " + file_.finalPath() + ": a point at " +
                                  std::to_string(v[a]) + " m is beyond the 32-bit range of " +
                                  std::to_string(opt_.coordinate_scale) +
                                  " m scaled integers; export with double coordinates");
            }
            column<std::uint32_t>(
                s[a], i, static_cast<std::uint32_t>(static_cast<std::int64_t>(raw) - kRawMin));
        }
        return Status::ok();
    }

    // The index packets of one section's data packets (first record, physical offset), level
    // by level until one packet indexes the level below (e57_packets.hpp).
    Status writeIndex(std::vector<std::pair<std::uint64_t, std::uint64_t>> entries) {
        for (std::uint8_t level = 0; !entries.empty(); ++level) {
            std::vector<std::pair<std::uint64_t, std::uint64_t>> up;
            for (std::size_t first = 0; first < entries.size(); first += kMaxIndexEntries) {
                const std::size_t n = std::min(kMaxIndexEntries, entries.size() - first);
                up.emplace_back(entries[first].first, physicalOf(pages_.logicalOffset()));
                indexPacket(packet_, std::span(entries).subspan(first, n), level);
                if (Status st = pages_.append(packet_); !st.isOk()) return st;
            }
            if (entries.size() <= kMaxIndexEntries) break;
            entries = std::move(up);
        }
        return Status::ok();
    }

    Status writeTrajectory() {
        trajectory_logical_ = pages_.logicalOffset();
        const auto& poses = opt_.trajectory;
        const auto header =
            sectionHeader(trajectory_logical_, kPoseBits, poses.size(), kPosesPerPacket);
        if (Status st = pages_.append(header); !st.isOk()) return st;
        std::vector<std::pair<std::uint64_t, std::uint64_t>> index;
        for (std::size_t first = 0; first < poses.size(); first += kPosesPerPacket) {
            const std::size_t n = std::min(kPosesPerPacket, poses.size() - first);
            index.emplace_back(first, physicalOf(pages_.logicalOffset()));
            const auto s = layOutPacket(packet_, kPoseBits, n);
            for (std::size_t i = 0; i < n; ++i) {
                const journal::TrajectoryPose& p = poses[first + i];
                const double v[8] = {p.t_s, p.x, p.y, p.z, p.qw, p.qx, p.qy, p.qz};
                for (std::size_t k = 0; k < 8; ++k) column<double>(s[k], i, v[k]);
            }
            if (Status st = pages_.append(packet_); !st.isOk()) return st;
        }
        return writeIndex(std::move(index));
    }

    SafeFileWriter& file_;
    E57Options opt_;
    PageFramer pages_;
    std::vector<journal::MapPoint> pending_;  // the next packet's points
    std::vector<std::uint8_t> packet_;
    std::uint64_t points_logical_ = 0;
    std::uint64_t trajectory_logical_ = 0;
    std::uint64_t expected_ = 0;
    std::uint64_t written_ = 0;
    std::array<unsigned, 9> point_bits_;
    std::vector<std::pair<std::uint64_t, std::uint64_t>> index_;  // the points' data packets
    std::uint64_t written_packets_records_ = 0;                   // records in them
};

}  // namespace

std::unique_ptr<PointFileWriter> makeE57Writer(SafeFileWriter& file, E57Options options) {
    return std::make_unique<E57Writer>(file, std::move(options));
}

std::uint64_t e57Bytes(std::uint64_t points, std::uint64_t poses, bool scaled) {
    const std::uint64_t logical =
        kPagePayload + (poses ? sectionBytes(kPoseBits, poses, kPosesPerPacket) : 0) +
        sectionBytes(scaled ? kScaledPointBits : kPointBits, points, kPointsPerPacket) + 8192;
    return physicalOf(logical) + kPageBytes;  // XML of a few KiB, the last page's padding
}

}  // namespace handscan::exporter
