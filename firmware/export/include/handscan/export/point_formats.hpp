// Point-cloud file formats surveyors' tools open: PLY (binary little-endian: x y z as float,
// red green blue as uchar, intensity as ushort, time as double, optionally session as ushort),
// LAS 1.4 with point data record format 7 (RGB + GPS time, 36 bytes; the point source ID is the
// session) and ASTM E57 (one Data3D: x y z as double or scaled integers, intensity,
// RGB with isColorInvalid, timeStamp; the trajectory as extension data). The points stream through
// once: the count is known up front (from the journal), the bounds are gathered while writing and
// patched into the header at the end.
#pragma once

#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "handscan/core/status.hpp"
#include "handscan/export/safe_file.hpp"
#include "handscan/journal/map_point.hpp"

namespace handscan::exporter {

struct Bounds {
    double min[3] = {std::numeric_limits<double>::max(), std::numeric_limits<double>::max(),
                     std::numeric_limits<double>::max()};
    double max[3] = {std::numeric_limits<double>::lowest(), std::numeric_limits<double>::lowest(),
                     std::numeric_limits<double>::lowest()};
    void add(double x, double y, double z) {
        const double v[3] = {x, y, z};
        for (int i = 0; i < 3; ++i) {
            min[i] = v[i] < min[i] ? v[i] : min[i];
            max[i] = v[i] > max[i] ? v[i] : max[i];
        }
    }
};

class PointFileWriter {
public:
    virtual ~PointFileWriter() = default;
    virtual Status begin(std::uint64_t count) = 0;
    virtual Status write(std::span<const journal::MapPoint> points) = 0;
    virtual Status end() = 0;  // header with the final bounds, then commit (verify + rename)
    const Bounds& bounds() const { return bounds_; }

protected:
    Bounds bounds_;
};

struct LasOptions {
    std::string system_identifier = "handscan handheld scanner";
    std::string generating_software = "handscan";
    double scale = 1e-4;  // 0.1 mm
    int creation_day_of_year = 1;
    int creation_year = 2026;
};

struct E57Options {
    std::string scan_name = "scan";
    std::string description =
        "handheld spinning-laser scan; timeStamp in seconds of the scan clock";
    std::string sensor_vendor = "handscan";
    std::string sensor_model = "handscan handheld spinning-laser scanner";
    std::string sensor_serial = "unknown";
    std::string software_version;
    std::vector<journal::TrajectoryPose> trajectory;  // written as handscan:trajectory
    // > 0: cartesianX/Y/Z as ScaledInteger of this many metres per step (32-bit raw values,
    // half the bytes of doubles; e.g. 1e-4: 0.1 mm steps, ±214 km); 0: Float double.
    double coordinate_scale = 0.0;
};

// The one PLY point-cloud writer of the tree (exports, replay's map.ply and --dump-sweeps, the
// demo's live-map export). `comment`: the header's comment lines (frame, units, time origin),
// one per element, without "comment ".
inline const std::vector<std::string> kPlyWorldComment = {
    "handscan colourised point cloud, metres, world frame"};
// `with_session`: one more property, `ushort session` (MapPoint::session: a merged
// multi-session map).
std::unique_ptr<PointFileWriter> makePlyWriter(SafeFileWriter& file,
                                               std::vector<std::string> comment = kPlyWorldComment,
                                               bool with_session = false);
std::unique_ptr<PointFileWriter> makeLasWriter(SafeFileWriter& file, LasOptions options = {});
// Installs its per-page CRC-32C check on `file`'s read-back.
std::unique_ptr<PointFileWriter> makeE57Writer(SafeFileWriter& file, E57Options options);

// Sizes, for the free-space check before writing.
std::uint64_t plyBytes(std::uint64_t points);
std::uint64_t lasBytes(std::uint64_t points);
std::uint64_t e57Bytes(std::uint64_t points, std::uint64_t trajectory_poses, bool scaled = false);
constexpr std::size_t kPlyPointRecordBytes = 3 * 4 + 3 + 2 + 8;  // x y z, rgb, intensity, time
constexpr std::size_t kLasHeaderBytes = 375;
constexpr std::size_t kLasPointRecordBytes = 36;

}  // namespace handscan::exporter
