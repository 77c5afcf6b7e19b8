#include "handscan/scan/voxel_map.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_set>

namespace handscan::scan {
namespace {

int positiveMod(int a, int n) { return ((a % n) + n) % n; }

}  // namespace

VoxelMap::VoxelMap(const VoxelMapConfig& config)
    : config_(config), fine_size_m_(config.coarse_size_m / config.fine_per_coarse) {
    leaves_per_axis_[0] =
        std::max(1, static_cast<int>(std::ceil(fine_size_m_ / config.edge_leaf_m)));
    leaves_per_axis_[1] =
        std::max(1, static_cast<int>(std::ceil(fine_size_m_ / config.planar_leaf_m)));
    slots_.resize(static_cast<std::size_t>(config.window_voxels.prod()));
}

bool VoxelMap::inside(const VoxelKey& coarse) const {
    const VoxelKey d = coarse - origin_;
    return has_origin_ && (d.array() >= 0).all() &&
           (d.array() < config_.window_voxels.array()).all();
}

std::size_t VoxelMap::slotOf(const VoxelKey& c) const {
    const Eigen::Vector3i& n = config_.window_voxels;
    // Every term is non-negative and below the window's voxel count, which fits an int.
    const int slot = positiveMod(c.x(), n.x()) +
                     n.x() * (positiveMod(c.y(), n.y()) + n.y() * positiveMod(c.z(), n.z()));
    return static_cast<std::size_t>(slot);
}

std::size_t VoxelMap::clearSlot(CoarseVoxel& v) {
    std::size_t cleared = 0;
    for (auto& [idx, cell] : v.cells) {
        for (int k = 0; k < 2; ++k) {
            cleared += cell.pts[k].size();
            stats_points_[k] -= cell.pts[k].size();
        }
    }
    v.cells.clear();
    v.used = false;
    return cleared;
}

std::size_t VoxelMap::recenter(const Eigen::Vector3d& sensor_world) {
    const VoxelKey s = voxelOf(sensor_world, config_.coarse_size_m);
    const Eigen::Vector3i& n = config_.window_voxels;
    if (!has_origin_) {
        origin_ = s - n / 2;
        has_origin_ = true;
        return 0;
    }
    const int margin = std::min(config_.roll_margin_voxels, (n.minCoeff() - 1) / 2);
    bool moved = false;
    for (int a = 0; a < 3; ++a) {
        if (s[a] - origin_[a] < margin) {
            origin_[a] = s[a] - margin;
            moved = true;
        } else if (origin_[a] + n[a] - 1 - s[a] < margin) {
            origin_[a] = s[a] + margin - n[a] + 1;
            moved = true;
        }
    }
    std::size_t cleared = 0;
    if (moved) {
        for (CoarseVoxel& v : slots_) {
            if (v.used && !inside(v.key)) {
                cleared += clearSlot(v);  // Figure 10a: moved voxels are cleared, the map truncated
            }
        }
    }
    truncated_ += cleared;
    return cleared;
}

std::size_t VoxelMap::insert(FeatureKind kind, const std::vector<Eigen::Vector3d>& points_world,
                             const std::vector<Eigen::Vector3d>& origins_world) {
    const bool with_origins = origins_world.size() == points_world.size();
    const int k = static_cast<int>(kind);
    const int F = config_.fine_per_coarse;
    const int L = leaves_per_axis_[k];
    const double leaf = fine_size_m_ / L;
    std::size_t kept = 0;
    for (std::size_t i = 0; i < points_world.size(); ++i) {
        const Eigen::Vector3d& p = points_world[i];
        const VoxelKey fine = voxelOf(p, fine_size_m_);
        const VoxelKey coarse = floorDiv(fine, F);
        if (!inside(coarse)) {
            ++rejected_outside_;
            continue;
        }
        CoarseVoxel& v = slots_[slotOf(coarse)];
        if (v.used && v.key != coarse) {
            truncated_ += clearSlot(v);
        }
        v.used = true;
        v.key = coarse;
        const VoxelKey local = fine - coarse * F;
        const auto cell_idx =
            static_cast<std::uint32_t>(local.x() + F * (local.y() + F * local.z()));
        FineCell& cell = v.cells[cell_idx];
        if (cell.leaves[k].empty()) {
            cell.leaves[k].assign((static_cast<std::size_t>(L) * L * L + 63) / 64, 0);
        }
        const Eigen::Vector3d rel = p - fine.cast<double>() * fine_size_m_;
        const auto q = [&](double x) { return std::clamp(static_cast<int>(x / leaf), 0, L - 1); };
        const int leaf_index = q(rel.x()) + L * (q(rel.y()) + L * q(rel.z()));  // < L^3
        const auto bit = static_cast<std::size_t>(leaf_index);
        std::uint64_t& word = cell.leaves[k][bit / 64];
        const std::uint64_t mask = 1ULL << (bit % 64);
        if (word & mask) {
            ++rejected_density_;
            continue;
        }
        word |= mask;
        cell.pts[k].push_back(p.cast<float>());
        cell.origins[k].push_back(
            with_origins ? Eigen::Vector3f(origins_world[i].cast<float>())
                         : Eigen::Vector3f::Constant(std::numeric_limits<float>::quiet_NaN()));
        ++stats_points_[k];
        ++kept;
    }
    return kept;
}

const VoxelMap::FineCell* VoxelMap::findCell(const VoxelKey& fine) const {
    const int F = config_.fine_per_coarse;
    const VoxelKey coarse = floorDiv(fine, F);
    if (!inside(coarse)) {
        return nullptr;
    }
    const CoarseVoxel& v = slots_[slotOf(coarse)];
    if (!v.used || v.key != coarse) {
        return nullptr;
    }
    const VoxelKey local = fine - coarse * F;
    const auto it =
        v.cells.find(static_cast<std::uint32_t>(local.x() + F * (local.y() + F * local.z())));
    return it == v.cells.end() ? nullptr : &it->second;
}

LocalMap VoxelMap::extract(const std::vector<Eigen::Vector3d>& edges_world,
                           const std::vector<Eigen::Vector3d>& planars_world) const {
    const int F = config_.fine_per_coarse;
    const int D = config_.green_dilation;
    // Green fine voxels: those the new features fall into (Figure 10b).
    std::unordered_set<VoxelKey, VoxelKeyHash> green;
    for (const auto* set : {&edges_world, &planars_world}) {
        for (const Eigen::Vector3d& p : *set) {
            green.insert(voxelOf(p, fine_size_m_));
        }
    }
    // Each coarse voxel's trees hold its green voxels and their neighbours, even across the
    // coarse boundary, so a query never misses a neighbour just over the edge.
    std::unordered_map<VoxelKey, std::unordered_set<VoxelKey, VoxelKeyHash>, VoxelKeyHash>
        per_coarse;
    for (const VoxelKey& g : green) {
        auto& cells = per_coarse[floorDiv(g, F)];
        for (int dz = -D; dz <= D; ++dz) {
            for (int dy = -D; dy <= D; ++dy) {
                for (int dx = -D; dx <= D; ++dx) {
                    cells.insert(g + VoxelKey(dx, dy, dz));
                }
            }
        }
    }
    LocalMap local(fine_size_m_, F);
    for (const auto& [coarse, cells] : per_coarse) {
        std::vector<Eigen::Vector3d> pts[2];
        std::vector<Eigen::Vector3f> origins[2];
        for (const VoxelKey& f : cells) {
            const FineCell* cell = findCell(f);
            if (cell == nullptr) {
                continue;
            }
            for (int k = 0; k < 2; ++k) {
                for (const Eigen::Vector3f& p : cell->pts[k]) {
                    pts[k].push_back(p.cast<double>());
                }
                origins[k].insert(origins[k].end(), cell->origins[k].begin(),
                                  cell->origins[k].end());
            }
        }
        if (!pts[0].empty() || !pts[1].empty()) {
            local.addVoxel(coarse, std::move(pts[0]), std::move(pts[1]), std::move(origins[1]));
        }
    }
    return local;
}

std::vector<Eigen::Vector3f> VoxelMap::points(FeatureKind kind) const {
    const int k = static_cast<int>(kind);
    std::vector<Eigen::Vector3f> out;
    out.reserve(stats_points_[k]);
    // Slot order, then cell index order: deterministic for byte-exact replays.
    for (const CoarseVoxel& v : slots_) {
        if (!v.used) {
            continue;
        }
        std::vector<std::uint32_t> keys;
        keys.reserve(v.cells.size());
        for (const auto& [idx, cell] : v.cells) {
            keys.push_back(idx);
        }
        std::sort(keys.begin(), keys.end());
        for (std::uint32_t idx : keys) {
            const auto& pts = v.cells.at(idx).pts[k];
            out.insert(out.end(), pts.begin(), pts.end());
        }
    }
    return out;
}

FeatureMapPoints VoxelMap::featurePoints() const {
    FeatureMapPoints out;
    out.edges = points(FeatureKind::kEdge);
    out.planars = points(FeatureKind::kPlanar);
    out.planar_origins.reserve(out.planars.size());
    for (const CoarseVoxel& v : slots_) {
        if (!v.used) continue;
        std::vector<std::uint32_t> keys;
        keys.reserve(v.cells.size());
        for (const auto& [idx, cell] : v.cells) keys.push_back(idx);
        std::sort(keys.begin(), keys.end());
        for (std::uint32_t idx : keys) {
            const FineCell& cell = v.cells.at(idx);
            const auto k = static_cast<int>(FeatureKind::kPlanar);
            for (std::size_t i = 0; i < cell.pts[k].size(); ++i) {
                out.planar_origins.push_back(
                    i < cell.origins[k].size()
                        ? cell.origins[k][i]
                        : Eigen::Vector3f::Constant(std::numeric_limits<float>::quiet_NaN()));
            }
        }
    }
    return out;
}

VoxelMapStats VoxelMap::stats() const {
    VoxelMapStats s;
    s.points[0] = stats_points_[0];
    s.points[1] = stats_points_[1];
    s.truncated_points = truncated_;
    s.rejected_outside = rejected_outside_;
    s.rejected_density = rejected_density_;
    s.memory_bytes = slots_.capacity() * sizeof(CoarseVoxel);
    for (const CoarseVoxel& v : slots_) {
        if (!v.used) {
            continue;
        }
        ++s.coarse_voxels_used;
        s.fine_cells += v.cells.size();
        for (const auto& [idx, cell] : v.cells) {
            s.memory_bytes += sizeof(FineCell) + 2 * sizeof(void*);
            for (int k = 0; k < 2; ++k) {
                s.memory_bytes += (cell.pts[k].capacity() + cell.origins[k].capacity()) *
                                      sizeof(Eigen::Vector3f) +
                                  cell.leaves[k].capacity() * sizeof(std::uint64_t);
            }
        }
    }
    return s;
}

std::size_t VoxelMap::capacityBound() const {
    const std::size_t cells =
        slots_.size() * static_cast<std::size_t>(std::pow(config_.fine_per_coarse, 3));
    std::size_t per_cell = 0;
    for (int k = 0; k < 2; ++k) {
        per_cell += static_cast<std::size_t>(leaves_per_axis_[k]) * leaves_per_axis_[k] *
                    leaves_per_axis_[k];
    }
    return cells * per_cell;
}

}  // namespace handscan::scan
