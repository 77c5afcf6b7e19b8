// The replay's output map (map.ply) built within a memory budget: the voxel filter of the export
// (one point per voxel at the centroid, exact integer sums) split into cubic tiles. Tiles near the
// sensor stay in memory; when the tiles held exceed the budget, the ones farthest from the sensor
// are flushed (their voxel sums, already deduplicated) to an unlinked scratch file as a fragment.
// A flushed tile that receives points again starts a new fragment; a tile flushed with several
// fragments on disk already is merged with them into one (so the scratch file holds about one copy
// of the map, rewritten without the superseded fragments when they dominate). At the end every
// tile's fragments are merged one tile at a time into a time-sorted run, and the runs are merged
// into the output. Because the voxel sums are exact, the result equals, byte for byte, what one
// in-memory VoxelFilter fed the same points gives, whatever was flushed when.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "handscan/core/status.hpp"
#include "handscan/journal/map_point.hpp"

namespace handscan::exporter {
class VoxelFilter;
}

namespace handscan::replay {

class SpillFile;

struct TiledMapConfig {
    double voxel_m = 0.02;
    double tile_m =
        4.0;  // edge of a tile (rounded to whole voxels); small, so a flush is selective
    std::uint64_t memory_budget_bytes = 256ull << 20;  // voxel tables held in memory
    std::string spill_dir = ".";                       // where the scratch files go
    // Superseded fragments tolerated in the scratch file (beyond as many bytes as the live ones)
    // before it is rewritten without them.
    std::uint64_t spill_slack_bytes = 64ull << 20;
};

struct TiledMapStats {
    std::uint64_t tiles = 0;
    std::uint64_t resident_bytes = 0;       // now
    std::uint64_t peak_resident_bytes = 0;  // after any add(), before flushing
    std::uint64_t fragments_flushed = 0;
    std::uint64_t cells_flushed = 0;
    std::uint64_t consolidations = 0;  // flushes that merged the tile's fragments into one
    std::uint64_t compactions = 0;     // rewrites of the scratch file without dead fragments
    std::uint64_t spill_bytes = 0;     // scratch file(s) now
    std::uint64_t peak_spill_bytes = 0;
    std::uint64_t spill_written_bytes = 0;  // all writes to the scratch files
};

class TiledVoxelMap {
public:
    explicit TiledVoxelMap(TiledMapConfig config);
    ~TiledVoxelMap();
    TiledVoxelMap(const TiledVoxelMap&) = delete;
    TiledVoxelMap& operator=(const TiledVoxelMap&) = delete;

    // Adds registered points; `sensor_world` (where the sensor is now) decides which tiles stay.
    [[nodiscard]] Status add(std::span<const journal::MapPoint> points,
                             const Eigen::Vector3d& sensor_world);

    using BeginFn = std::function<Status(std::uint64_t total_points)>;
    using SinkFn = std::function<Status(std::span<const journal::MapPoint> points)>;
    // Streams the map in VoxelFilter::take()'s order: `begin` once with the count, then batches.
    // Holds one tile (plus read buffers) at a time. The map is consumed.
    [[nodiscard]] Result<std::uint64_t> drain(const BeginFn& begin, const SinkFn& sink);

    const TiledMapStats& stats() const { return stats_; }
    const TiledMapConfig& config() const { return config_; }

private:
    struct Fragment {
        std::uint64_t offset = 0;
        std::uint64_t cells = 0;
    };
    struct Tile {
        std::unique_ptr<exporter::VoxelFilter> voxels;  // null: not in memory
        std::vector<Fragment> fragments;                // flushed, oldest first
        Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    };

    Tile& tileOf(const journal::MapPoint& p);
    Status flushFarthest(const Eigen::Vector3d& sensor_world);
    Status flush(Tile& tile);
    Status mergeFragments(Tile& tile, exporter::VoxelFilter& into);
    Status compactFragments();
    Status appendSpill(SpillFile& file, std::span<const std::uint8_t> bytes, std::uint64_t* offset);
    Status spillOpen(std::unique_ptr<SpillFile>& file, const char* name, const char* what);
    Result<std::unique_ptr<exporter::VoxelFilter>> mergedTile(Tile& tile);

    TiledMapConfig config_;
    std::int64_t voxels_per_tile_;
    std::map<std::uint64_t, Tile> tiles_;  // ordered: the merge and the flushing are deterministic
    std::uint64_t last_key_ = ~0ull;
    Tile* last_tile_ = nullptr;
    std::unique_ptr<exporter::VoxelFilter> probe_;  // voxel indices, same arithmetic as the tiles'
    std::unique_ptr<SpillFile> fragments_;
    std::unique_ptr<SpillFile> runs_;
    std::uint64_t dead_bytes_ = 0;  // superseded fragments still in fragments_
    TiledMapStats stats_;
};

}  // namespace handscan::replay
