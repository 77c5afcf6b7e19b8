// Voxel downsampling for export: one point per occupied voxel at the centroid of its points,
// with their mean colour, intensity and time.
#pragma once

#include <cmath>
#include <cstdint>
#include <span>
#include <unordered_map>
#include <vector>

#include "handscan/journal/map_point.hpp"

namespace handscan::exporter {

class VoxelFilter {
public:
    explicit VoxelFilter(double voxel_m) : inv_(1.0 / voxel_m) {}

    void add(std::span<const journal::MapPoint> points) {
        for (const journal::MapPoint& p : points) {
            Accum& a = cells_[key(p)];
            a.x += p.x;
            a.y += p.y;
            a.z += p.z;
            a.t += p.t_s;
            a.r += p.r;
            a.g += p.g;
            a.b += p.b;
            a.i += p.intensity;
            ++a.n;
        }
    }

    std::vector<journal::MapPoint> take() const {
        std::vector<journal::MapPoint> out;
        out.reserve(cells_.size());
        for (const auto& [k, a] : cells_) {
            const double n = static_cast<double>(a.n);
            out.push_back({a.t / n, static_cast<float>(a.x / n), static_cast<float>(a.y / n), static_cast<float>(a.z / n),
                           static_cast<std::uint8_t>(std::lround(a.r / n)), static_cast<std::uint8_t>(std::lround(a.g / n)),
                           static_cast<std::uint8_t>(std::lround(a.b / n)), static_cast<std::uint16_t>(std::lround(a.i / n))});
        }
        // Time order, so the output does not depend on the hash map's iteration order.
        std::sort(out.begin(), out.end(), [](const auto& l, const auto& r) {
            return l.t_s != r.t_s ? l.t_s < r.t_s : (l.x != r.x ? l.x < r.x : (l.y != r.y ? l.y < r.y : l.z < r.z));
        });
        return out;
    }

private:
    struct Accum {
        double x = 0, y = 0, z = 0, t = 0, r = 0, g = 0, b = 0, i = 0;
        std::uint64_t n = 0;
    };
    std::uint64_t key(const journal::MapPoint& p) const {
        // 21 bits per axis around the origin: +-10 km at 1 cm voxels.
        auto cell = [&](float v) { return static_cast<std::uint64_t>(std::floor(v * inv_) + (1 << 20)) & 0x1FFFFF; };
        return cell(p.x) | (cell(p.y) << 21) | (cell(p.z) << 42);
    }
    double inv_;
    std::unordered_map<std::uint64_t, Accum> cells_;
};

}  // namespace handscan::exporter
