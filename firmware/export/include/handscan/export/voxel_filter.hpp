// Voxel downsampling for export: one point per occupied voxel at the centroid of its points,
// with their mean colour, intensity and time. The voxels live in one open-addressing hash table
// keyed by the packed voxel index (linear probing, no allocation per point or per voxel), so
// thinning a 10 M point scan costs a hash and a few adds per point.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "handscan/journal/map_point.hpp"

namespace handscan::exporter {

class VoxelFilter {
public:
    explicit VoxelFilter(double voxel_m) : inv_(1.0 / voxel_m) { cells_.resize(std::size_t{1} << bits_); }

    void add(std::span<const journal::MapPoint> points) {
        for (const journal::MapPoint& p : points) {
            if ((occupied_ + 1) * 10 > cells_.size() * 7) grow();  // load factor <= 0.7
            Cell& c = find(key(p));
            c.x += p.x;
            c.y += p.y;
            c.z += p.z;
            c.t += p.t_s;
            c.r += p.r;
            c.g += p.g;
            c.b += p.b;
            c.i += p.intensity;
            ++c.n;
        }
    }

    // Occupied voxels so far.
    std::size_t size() const { return occupied_; }

    std::vector<journal::MapPoint> take() const {
        std::vector<journal::MapPoint> out;
        out.reserve(occupied_);
        for (const Cell& c : cells_) {
            if (c.n == 0) continue;
            const double n = static_cast<double>(c.n);
            auto mean8 = [n](std::uint64_t sum) { return static_cast<std::uint8_t>(std::lround(static_cast<double>(sum) / n)); };
            out.push_back({c.t / n, static_cast<float>(c.x / n), static_cast<float>(c.y / n), static_cast<float>(c.z / n),
                           mean8(c.r), mean8(c.g), mean8(c.b),
                           static_cast<std::uint16_t>(std::lround(static_cast<double>(c.i) / n))});
        }
        // Time order, so the output does not depend on the hash table's layout.
        std::sort(out.begin(), out.end(), [](const auto& l, const auto& r) {
            return l.t_s != r.t_s ? l.t_s < r.t_s : (l.x != r.x ? l.x < r.x : (l.y != r.y ? l.y < r.y : l.z < r.z));
        });
        return out;
    }

private:
    struct Cell {
        std::uint64_t key = 0;
        std::uint64_t n = 0;  // 0: empty slot
        double x = 0, y = 0, z = 0, t = 0;
        std::uint64_t r = 0, g = 0, b = 0, i = 0;
    };

    std::uint64_t key(const journal::MapPoint& p) const {
        // 21 bits per axis around the origin: +-10 km at 1 cm voxels.
        auto cell = [&](float v) { return static_cast<std::uint64_t>(std::floor(v * inv_) + (1 << 20)) & 0x1FFFFF; };
        return cell(p.x) | (cell(p.y) << 21) | (cell(p.z) << 42);
    }
    // Fibonacci hashing: the multiply spreads neighbouring voxel keys over the whole table.
    std::size_t slot(std::uint64_t k) const { return static_cast<std::size_t>((k * 0x9E3779B97F4A7C15ull) >> (64 - bits_)); }

    Cell& find(std::uint64_t k) {
        const std::size_t mask = cells_.size() - 1;
        for (std::size_t s = slot(k);; s = (s + 1) & mask) {
            Cell& c = cells_[s];
            if (c.n == 0) {
                c.key = k;
                ++occupied_;
                return c;
            }
            if (c.key == k) return c;
        }
    }

    void grow() {
        std::vector<Cell> old(std::size_t{1} << (bits_ + 1));
        old.swap(cells_);
        ++bits_;
        const std::size_t mask = cells_.size() - 1;
        for (const Cell& c : old) {
            if (c.n == 0) continue;
            std::size_t s = slot(c.key);
            while (cells_[s].n != 0) s = (s + 1) & mask;
            cells_[s] = c;
        }
    }

    double inv_;
    unsigned bits_ = 12;
    std::size_t occupied_ = 0;
    std::vector<Cell> cells_;
};

}  // namespace handscan::exporter
