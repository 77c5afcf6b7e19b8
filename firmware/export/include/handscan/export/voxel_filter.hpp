// Voxel downsampling for export: one point per occupied voxel at the centroid of its points,
// with their mean colour, intensity and time. The voxels live in one open-addressing hash table
// keyed by the packed voxel index (linear probing, no allocation per point or per voxel), so
// thinning a 10 M point scan costs a hash and a few adds per point.
//
// The sums are integers (position as a fixed-point offset inside the voxel, time in nanoseconds),
// so they are exact: the result does not depend on the order of the points, and the sums of one
// voxel kept by several partial filters merge (merge()) into exactly the bits one filter fed all
// the points would hold. That is what lets a map that does not fit in memory be built in pieces
// (replay's TiledVoxelMap) and still equal the in-memory result byte for byte.
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
    // The exact sums of one voxel (88 bytes, no padding: it is spilled to disk as is).
    struct Cell {
        std::uint64_t key = 0;
        std::uint64_t n = 0;             // 0: empty slot
        std::int64_t t_s = 0, t_ns = 0;  // time: sums of the whole seconds and of the nanoseconds
        std::uint64_t x = 0, y = 0, z = 0;  // sums of the offsets inside the voxel, in voxel / 2^32
        std::uint64_t r = 0, g = 0, b = 0, i = 0;
    };

    // `initial_bits`: the table starts with 2^initial_bits slots (it doubles as voxels come).
    explicit VoxelFilter(double voxel_m, unsigned initial_bits = 12)
        : voxel_(voxel_m), inv_(1.0 / voxel_m), bits_(initial_bits) {
        cells_.resize(std::size_t{1} << bits_);
    }

    void add(std::span<const journal::MapPoint> points) {
        for (const journal::MapPoint& p : points) {
            if ((occupied_ + 1) * 10 > cells_.size() * 7) grow();  // load factor <= 0.7
            const double sx = p.x * inv_, sy = p.y * inv_, sz = p.z * inv_;
            const double fx = std::floor(sx), fy = std::floor(sy), fz = std::floor(sz);
            Cell& c = find(key(fx, fy, fz));
            c.x += fixedOffset(sx - fx);
            c.y += fixedOffset(sy - fy);
            c.z += fixedOffset(sz - fz);
            const std::int64_t t = std::llround(p.t_s * 1e9);
            c.t_s += t / 1'000'000'000;
            c.t_ns += t % 1'000'000'000;
            c.r += p.r;
            c.g += p.g;
            c.b += p.b;
            c.i += p.intensity;
            ++c.n;
        }
    }

    // Adds the sums of one voxel from another filter of the same voxel size (exact).
    void merge(const Cell& other) {
        if ((occupied_ + 1) * 10 > cells_.size() * 7) grow();
        Cell& c = find(other.key);
        c.n += other.n;
        c.t_s += other.t_s;
        c.t_ns += other.t_ns;
        c.x += other.x;
        c.y += other.y;
        c.z += other.z;
        c.r += other.r;
        c.g += other.g;
        c.b += other.b;
        c.i += other.i;
    }

    template <class Fn>
    void forEachCell(Fn&& fn) const {
        for (const Cell& c : cells_) {
            if (c.n != 0) fn(c);
        }
    }
    // The same, in an order spread over the whole hash space: for cells that will be merged into
    // another table. In slot order they would arrive sorted by hash, and linear probing fed keys
    // sorted by hash into a smaller table piles them into one ever longer run (quadratic time).
    template <class Fn>
    void forEachCellSpread(Fn&& fn) const {
        const std::size_t mask = cells_.size() - 1;
        const std::size_t stride =
            (static_cast<std::size_t>(static_cast<double>(cells_.size()) * 0.6180339887) | 1) &
            mask;
        for (std::size_t i = 0, s = 0; i < cells_.size(); ++i, s = (s + stride) & mask) {
            if (cells_[s].n != 0) fn(cells_[s]);
        }
    }
    // Sizes the table for `voxels` occupied voxels at once (no rehashing on the way there).
    void reserve(std::size_t voxels) {
        while (voxels * 10 > cells_.size() * 7) grow();
    }

    // Occupied voxels so far.
    std::size_t size() const { return occupied_; }
    // Heap bytes the table holds (what a memory budget counts).
    std::size_t memoryBytes() const { return cells_.capacity() * sizeof(Cell); }
    // The voxel index along one axis of a coordinate (the key's per-axis part, before packing).
    std::int64_t voxelIndex(float v) const {
        return static_cast<std::int64_t>(std::floor(v * inv_));
    }

    // The voxel's point: centroid, mean time, colour and intensity.
    journal::MapPoint point(const Cell& c) const {
        const double n = static_cast<double>(c.n);
        auto mean8 = [n](std::uint64_t sum) {
            return static_cast<std::uint8_t>(std::lround(static_cast<double>(sum) / n));
        };
        auto axis = [&](std::uint64_t k, std::uint64_t sum) {
            const double index =
                static_cast<double>(static_cast<std::int64_t>(k & 0x1FFFFF) - (1 << 20));
            return static_cast<float>((index + static_cast<double>(sum) / n * 0x1p-32) * voxel_);
        };
        const double t = static_cast<double>(c.t_s) / n + static_cast<double>(c.t_ns) / n * 1e-9;
        return {t,
                axis(c.key, c.x),
                axis(c.key >> 21, c.y),
                axis(c.key >> 42, c.z),
                mean8(c.r),
                mean8(c.g),
                mean8(c.b),
                static_cast<std::uint16_t>(std::lround(static_cast<double>(c.i) / n))};
    }

    // The order of the output: by time, so that it does not depend on the hash table's layout.
    static bool before(const journal::MapPoint& l, const journal::MapPoint& r) {
        return l.t_s != r.t_s ? l.t_s < r.t_s
                              : (l.x != r.x ? l.x < r.x : (l.y != r.y ? l.y < r.y : l.z < r.z));
    }

    std::vector<journal::MapPoint> take() const {
        std::vector<journal::MapPoint> out;
        out.reserve(occupied_);
        forEachCell([&](const Cell& c) { out.push_back(point(c)); });
        std::sort(out.begin(), out.end(), before);
        return out;
    }

private:
    // 21 bits per axis around the origin: +-10 km at 1 cm voxels.
    static std::uint64_t key(double fx, double fy, double fz) {
        auto cell = [](double f) {
            return static_cast<std::uint64_t>(static_cast<std::int64_t>(f) + (1 << 20)) & 0x1FFFFF;
        };
        return cell(fx) | (cell(fy) << 21) | (cell(fz) << 42);
    }
    // An offset in [0, 1) voxel as 32-bit fixed point: rounded per point, so sums are exact.
    static std::uint64_t fixedOffset(double f) {
        return static_cast<std::uint64_t>(std::llround(f * 0x1p32));
    }
    // Fibonacci hashing: the multiply spreads neighbouring voxel keys over the whole table.
    std::size_t slot(std::uint64_t k) const {
        return static_cast<std::size_t>((k * 0x9E3779B97F4A7C15ull) >> (64 - bits_));
    }

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

    double voxel_;
    double inv_;
    unsigned bits_;
    std::size_t occupied_ = 0;
    std::vector<Cell> cells_;
};

static_assert(sizeof(VoxelFilter::Cell) == 88, "spilled to disk as raw bytes: no padding");

}  // namespace handscan::exporter
