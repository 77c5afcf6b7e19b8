#include "handscan/replay/tiled_voxel_map.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <queue>
#include <type_traits>

#include "handscan/export/voxel_filter.hpp"
#include "spill_file.hpp"

namespace handscan::replay {
namespace {

using exporter::VoxelFilter;
using journal::MapPoint;

static_assert(std::is_trivially_copyable_v<VoxelFilter::Cell> &&
                  std::is_trivially_copyable_v<MapPoint>,
              "spilled as raw bytes");

constexpr std::size_t kChunkCells = std::size_t{1} << 16;   // flush / read-back granularity
constexpr std::size_t kOutputBatch = std::size_t{1} << 16;  // points per sink() call
// A tile's table starts at 256 voxels (22 KiB): the far tiles a sweep touches get a few points
// each.
constexpr unsigned kTileInitialBits = 8;
// A tile flushed with this many fragments on disk is merged with them into one.
constexpr std::size_t kMaxFragments = 4;

std::int64_t floorDiv(std::int64_t a, std::int64_t b) {
    return a / b - ((a % b != 0) && ((a < 0) != (b < 0)));
}

template <class T>
std::span<const std::uint8_t> bytesOf(std::span<const T> v) {
    return {reinterpret_cast<const std::uint8_t*>(v.data()), v.size_bytes()};
}
template <class T>
std::span<std::uint8_t> bytesOf(std::span<T> v) {
    return {reinterpret_cast<std::uint8_t*>(v.data()), v.size_bytes()};
}

// One sorted run of the final merge, read back in blocks.
struct RunCursor {
    std::uint64_t offset = 0;     // next unread point in the runs file
    std::uint64_t remaining = 0;  // unread points
    std::vector<MapPoint> block;
    std::size_t pos = 0;
    const MapPoint& head() const { return block[pos]; }
};

}  // namespace

TiledVoxelMap::TiledVoxelMap(TiledMapConfig config)
    : config_(std::move(config)),
      voxels_per_tile_(std::max<std::int64_t>(1, std::llround(config_.tile_m / config_.voxel_m))),
      probe_(std::make_unique<VoxelFilter>(config_.voxel_m, kTileInitialBits)) {}

TiledVoxelMap::~TiledVoxelMap() = default;

TiledVoxelMap::Tile& TiledVoxelMap::tileOf(const MapPoint& p) {
    // A tile is a whole number of voxels, so no voxel straddles two tiles.
    const std::int64_t t[3] = {floorDiv(probe_->voxelIndex(p.x), voxels_per_tile_),
                               floorDiv(probe_->voxelIndex(p.y), voxels_per_tile_),
                               floorDiv(probe_->voxelIndex(p.z), voxels_per_tile_)};
    auto field = [](std::int64_t v) {
        return static_cast<std::uint64_t>(v + (1 << 20)) & 0x1FFFFF;
    };
    const std::uint64_t key = field(t[0]) | (field(t[1]) << 21) | (field(t[2]) << 42);
    if (key == last_key_) return *last_tile_;
    auto [it, inserted] = tiles_.try_emplace(key);
    Tile& tile = it->second;
    if (inserted) {
        const double edge = static_cast<double>(voxels_per_tile_) * config_.voxel_m;
        tile.centre = (Eigen::Vector3d(static_cast<double>(t[0]), static_cast<double>(t[1]),
                                       static_cast<double>(t[2])) +
                       Eigen::Vector3d::Constant(0.5)) *
                      edge;
        ++stats_.tiles;
    }
    if (!tile.voxels)
        tile.voxels =
            std::make_unique<VoxelFilter>(config_.voxel_m, kTileInitialBits);  // a new fragment
    last_key_ = key;
    last_tile_ = &tile;
    return tile;
}

Status TiledVoxelMap::add(std::span<const MapPoint> points, const Eigen::Vector3d& sensor_world) {
    // Consecutive points of a scan line mostly share a tile: add them as one span.
    std::size_t i = 0;
    while (i < points.size()) {
        Tile& tile = tileOf(points[i]);
        std::size_t j = i + 1;
        while (j < points.size() && &tileOf(points[j]) == &tile) ++j;
        tile.voxels->add(points.subspan(i, j - i));
        i = j;
    }
    std::uint64_t resident = 0;
    for (const auto& [key, tile] : tiles_) resident += tile.voxels ? tile.voxels->memoryBytes() : 0;
    stats_.resident_bytes = resident;
    stats_.peak_resident_bytes = std::max(stats_.peak_resident_bytes, resident);
    if (resident <= config_.memory_budget_bytes) return Status::ok();
    return flushFarthest(sensor_world);
}

Status TiledVoxelMap::flushFarthest(const Eigen::Vector3d& sensor_world) {
    struct Candidate {
        double distance_m;
        std::uint64_t key;
        Tile* tile;
    };
    std::vector<Candidate> held;
    for (auto& [key, tile] : tiles_) {
        if (tile.voxels) held.push_back({(tile.centre - sensor_world).norm(), key, &tile});
    }
    std::sort(held.begin(), held.end(), [](const Candidate& a, const Candidate& b) {
        return a.distance_m != b.distance_m ? a.distance_m > b.distance_m : a.key < b.key;
    });
    // Down to 3/4 of the budget, so that the next sweeps do not flush again at once.
    const std::uint64_t target = config_.memory_budget_bytes / 4 * 3;
    for (const Candidate& c : held) {
        if (stats_.resident_bytes <= target) break;
        stats_.resident_bytes -= c.tile->voxels->memoryBytes();
        if (Status s = flush(*c.tile); !s.isOk()) return s;
    }
    return Status::ok();
}

Status TiledVoxelMap::spillOpen(std::unique_ptr<SpillFile>& file, const char* name,
                                const char* what) {
    if (file) return Status::ok();
    auto f = SpillFile::create((std::filesystem::path(config_.spill_dir) / name).string(), what);
    if (!f.isOk()) return f.status();
    file = std::move(*f);
    return Status::ok();
}

Status TiledVoxelMap::appendSpill(SpillFile& file, std::span<const std::uint8_t> bytes,
                                  std::uint64_t* offset) {
    auto r = file.append(bytes);
    if (!r.isOk()) return r.status();
    if (offset != nullptr) *offset = *r;
    stats_.spill_written_bytes += bytes.size();
    stats_.spill_bytes = (fragments_ ? fragments_->size() : 0) + (runs_ ? runs_->size() : 0);
    stats_.peak_spill_bytes = std::max(stats_.peak_spill_bytes, stats_.spill_bytes);
    return Status::ok();
}

Status TiledVoxelMap::flush(Tile& tile) {
    if (Status s = spillOpen(fragments_, ".map-fragments.spill", "map spill file"); !s.isOk())
        return s;
    if (tile.fragments.size() + 1 >= kMaxFragments) {
        // A tile flushed again and again (the sensor keeps seeing it): fold its fragments into
        // the table (one tile's worth of memory, briefly) so it goes back as one.
        for (const Fragment& f : tile.fragments) dead_bytes_ += f.cells * sizeof(VoxelFilter::Cell);
        if (Status s = mergeFragments(tile, *tile.voxels); !s.isOk()) return s;
        ++stats_.consolidations;
    }
    Fragment fragment{fragments_->size(), 0};
    std::vector<VoxelFilter::Cell> chunk;
    chunk.reserve(std::min(kChunkCells, tile.voxels->size()));
    Status status = Status::ok();
    auto put = [&] {
        status =
            appendSpill(*fragments_, bytesOf(std::span<const VoxelFilter::Cell>(chunk)), nullptr);
        fragment.cells += chunk.size();
        chunk.clear();
    };
    tile.voxels->forEachCellSpread([&](const VoxelFilter::Cell& c) {
        if (!status.isOk()) return;
        chunk.push_back(c);
        if (chunk.size() == kChunkCells) put();
    });
    if (status.isOk() && !chunk.empty()) put();
    if (!status.isOk()) return status;
    tile.fragments.push_back(fragment);
    tile.voxels.reset();
    if (last_tile_ == &tile) last_key_ = ~0ull;  // the cache must not hand out the flushed table
    ++stats_.fragments_flushed;
    stats_.cells_flushed += fragment.cells;
    const std::uint64_t live = fragments_->size() - dead_bytes_;
    if (dead_bytes_ > std::max(live, config_.spill_slack_bytes)) return compactFragments();
    return Status::ok();
}

Status TiledVoxelMap::compactFragments() {
    // Copy the live fragments into a fresh scratch file (the old one's name is free: it was
    // unlinked at creation), then drop the old one, which returns its space.
    std::unique_ptr<SpillFile> old = std::move(fragments_);
    if (Status s = spillOpen(fragments_, ".map-fragments.spill", "map spill file"); !s.isOk())
        return s;
    std::vector<std::uint8_t> buffer;
    for (auto& [key, tile] : tiles_) {
        for (Fragment& f : tile.fragments) {
            const std::uint64_t bytes = f.cells * sizeof(VoxelFilter::Cell);
            std::uint64_t offset = 0;
            for (std::uint64_t done = 0; done < bytes;) {
                buffer.resize(static_cast<std::size_t>(std::min<std::uint64_t>(
                    kChunkCells * sizeof(VoxelFilter::Cell), bytes - done)));
                if (Status s = old->read(f.offset + done, buffer); !s.isOk()) return s;
                std::uint64_t at = 0;
                if (Status s = appendSpill(*fragments_, buffer, &at); !s.isOk()) return s;
                if (done == 0) offset = at;
                done += buffer.size();
            }
            f.offset = offset;
        }
    }
    old.reset();
    dead_bytes_ = 0;
    ++stats_.compactions;
    stats_.spill_bytes = fragments_->size() + (runs_ ? runs_->size() : 0);
    return Status::ok();
}

Status TiledVoxelMap::mergeFragments(Tile& tile, VoxelFilter& voxels) {
    // At least as many voxels as the largest part holds: no rehashing for most of the merge.
    std::uint64_t largest = voxels.size();
    for (const Fragment& f : tile.fragments) largest = std::max(largest, f.cells);
    voxels.reserve(static_cast<std::size_t>(largest));
    std::vector<VoxelFilter::Cell> chunk;
    for (const Fragment& f : tile.fragments) {
        for (std::uint64_t done = 0; done < f.cells;) {
            chunk.resize(
                static_cast<std::size_t>(std::min<std::uint64_t>(kChunkCells, f.cells - done)));
            const std::uint64_t offset = f.offset + done * sizeof(VoxelFilter::Cell);
            if (Status s = fragments_->read(offset, bytesOf(std::span<VoxelFilter::Cell>(chunk)));
                !s.isOk())
                return s;
            for (const VoxelFilter::Cell& c : chunk) voxels.merge(c);
            done += chunk.size();
        }
    }
    tile.fragments.clear();
    return Status::ok();
}

Result<std::unique_ptr<VoxelFilter>> TiledVoxelMap::mergedTile(Tile& tile) {
    std::unique_ptr<VoxelFilter> voxels =
        tile.voxels ? std::move(tile.voxels)
                    : std::make_unique<VoxelFilter>(config_.voxel_m, kTileInitialBits);
    if (Status s = mergeFragments(tile, *voxels); !s.isOk()) return s;
    return voxels;
}

Result<std::uint64_t> TiledVoxelMap::drain(const BeginFn& begin, const SinkFn& sink) {
    last_key_ = ~0ull;
    // 1. Tile by tile: merge the fragments, sort, store as a run.
    std::vector<RunCursor> runs;
    std::uint64_t total = 0;
    for (auto& [key, tile] : tiles_) {
        auto voxels = mergedTile(tile);
        if (!voxels.isOk()) return voxels.status();
        const std::vector<MapPoint> pts = (*voxels)->take();
        voxels->reset();
        if (pts.empty()) continue;
        if (Status s = spillOpen(runs_, ".map-runs.spill", "map merge file"); !s.isOk()) return s;
        std::uint64_t offset = 0;
        if (Status s = appendSpill(*runs_, bytesOf(std::span<const MapPoint>(pts)), &offset);
            !s.isOk())
            return s;
        runs.push_back({offset, pts.size(), {}, 0});
        total += pts.size();
    }
    tiles_.clear();
    fragments_.reset();  // no longer needed: give the disk space back before the output is written
    stats_.resident_bytes = 0;

    // 2. k-way merge of the runs in take()'s order; read blocks share about the memory budget.
    if (Status s = begin(total); !s.isOk()) return s;
    const std::size_t block = static_cast<std::size_t>(std::clamp<std::uint64_t>(
        config_.memory_budget_bytes / 2 / std::max<std::size_t>(1, runs.size()) / sizeof(MapPoint),
        256, 1 << 15));
    auto refill = [&](RunCursor& r) -> Status {
        r.block.resize(static_cast<std::size_t>(std::min<std::uint64_t>(block, r.remaining)));
        r.pos = 0;
        if (Status s = runs_->read(r.offset, bytesOf(std::span<MapPoint>(r.block))); !s.isOk())
            return s;
        r.offset += r.block.size() * sizeof(MapPoint);
        r.remaining -= r.block.size();
        return Status::ok();
    };
    auto later = [&](std::size_t a, std::size_t b) {  // priority_queue: the top is the earliest
        const MapPoint &pa = runs[a].head(), &pb = runs[b].head();
        return VoxelFilter::before(pb, pa) || (!VoxelFilter::before(pa, pb) && a > b);
    };
    std::priority_queue<std::size_t, std::vector<std::size_t>, decltype(later)> heads(later);
    for (std::size_t i = 0; i < runs.size(); ++i) {
        if (Status s = refill(runs[i]); !s.isOk()) return s;
        heads.push(i);
    }
    std::vector<MapPoint> out;
    out.reserve(std::min<std::uint64_t>(kOutputBatch, total));
    while (!heads.empty()) {
        const std::size_t i = heads.top();
        heads.pop();
        RunCursor& r = runs[i];
        out.push_back(r.head());
        if (++r.pos == r.block.size() && r.remaining > 0) {
            if (Status s = refill(r); !s.isOk()) return s;
        }
        if (r.pos < r.block.size()) heads.push(i);
        if (out.size() == kOutputBatch) {
            if (Status s = sink(out); !s.isOk()) return s;
            out.clear();
        }
    }
    if (!out.empty()) {
        if (Status s = sink(out); !s.isOk()) return s;
    }
    runs_.reset();
    return total;
}

}  // namespace handscan::replay
