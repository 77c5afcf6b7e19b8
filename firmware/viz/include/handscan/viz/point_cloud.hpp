// The point records of the /map and /sweep channels (foxglove.PointCloud's packed `data`), and
// the display map /map shows: one point per voxel, the first one seen, as the touch screen keeps
// it (shm::DisplayVoxelFilter, 5 cm).
//
// Record (20 bytes, little-endian): x, y, z float32 (m, world frame), intensity float32 (the
// laser's return intensity), rgb uint32 packed as PCL and ROS do (0x00RRGGBB: bytes b, g, r, 0).
// A point the colour camera did not see gets the grey of its intensity, as on the touch screen.
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "handscan/journal/map_point.hpp"
#include "handscan/shm/display_voxel_filter.hpp"

namespace handscan::viz {

inline constexpr std::uint32_t kPointStride = 20;

// foxglove.PackedElementField.NumericType values used by the record.
enum class NumericType : std::uint8_t { kUint32 = 5, kFloat32 = 7 };

struct PointField {
    const char* name;
    std::uint32_t offset;
    NumericType type;
};
inline constexpr PointField kPointFields[] = {{"x", 0, NumericType::kFloat32},
                                              {"y", 4, NumericType::kFloat32},
                                              {"z", 8, NumericType::kFloat32},
                                              {"intensity", 12, NumericType::kFloat32},
                                              {"rgb", 16, NumericType::kUint32}};

// Appends the point's record to `out`.
void appendPointRecord(const journal::MapPoint& p, std::string& out);

class DisplayMap {
public:
    // `max_points`: a larger map's snapshot is thinned to this many points (see snapshot).
    DisplayMap(float voxel_m, std::size_t max_points);

    // A registered sweep's points: those in voxels not shown yet join the map.
    void add(std::span<const journal::MapPoint> points);
    // The whole map's records into `out` (replacing it). Beyond max_points, max_points of them
    // evenly spaced in the order the scan met the voxels, so the thinned map covers everything
    // evenly, and the file grows by at most max_points per sweep.
    void snapshot(std::string& out) const;
    std::size_t size() const { return records_.size() / kPointStride; }
    // Points a snapshot holds now.
    std::size_t snapshotSize() const;

private:
    shm::DisplayVoxelFilter voxels_;
    std::size_t max_points_;
    std::string records_;
};

}  // namespace handscan::viz
