// SeenSpace: where a session's laser looked through empty space, and in which directions, as a
// dense grid over a fixed box. A return at `end` seen from `origin` says the segment between them
// was empty when it was measured; every cell the segment crosses up to `short_m` before the
// return (its range noise, and the surface a ray entering at an angle meets just past the cell)
// records the ray's direction, one of 26 (the grid's neighbour directions). This is what tells a
// change from new ground (section 9's change report): a surface where the other session's rays
// went straight through, into its face, is a change; a surface the other session never looked
// at, or only skimmed at a grazing angle, or saw from its back, is not. Dense so that a query is
// one index; the cell grows until the box fits in max_cells.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

namespace handscan::localize {

struct SeenSpaceConfig {
    double cell_m = 0.1;                           // finest cell; coarser when the box is large
    std::size_t max_cells = std::size_t{1} << 22;  // 16 MiB of direction masks at most
    // Space this close before a return is not claimed empty: LocalizerConfig::change_m, the
    // distance within which a point is the same surface (at least three cells).
    double short_m = 0.3;
    // A ray counts as going into a surface when its direction bin lies within this angle of the
    // surface's inward normal (a bin is up to ~27 deg off the ray, so the ray is within ~52 deg:
    // one passing a cell above a standing surface at that angle meets it within short_m).
    double into_deg = 50.0;
};

class SeenSpace {
public:
    SeenSpace() = default;
    // An empty grid over `box` (nothing seen yet).
    SeenSpace(const Eigen::AlignedBox3d& box, const SeenSpaceConfig& config = {});

    // The cells the segment origin -> end crosses up to short_m before `end`, each once, with
    // the segment's direction, appended to `cells` (parts outside the box are skipped).
    struct Crossing {
        std::uint32_t cell;
        std::uint8_t direction;
    };
    void cellsAlong(const Eigen::Vector3d& origin, const Eigen::Vector3d& end,
                    std::vector<Crossing>& cells) const;
    void add(const std::vector<Crossing>& cells);
    // No rays seen anywhere (the same box and cells).
    void clear();
    // Whether a ray went through the cell holding the surface point `p` into the surface (within
    // into_deg of -n, `n` its unit normal facing the laser that found it) and on past it.
    bool seenThrough(const Eigen::Vector3d& p, const Eigen::Vector3d& n) const;
    // Whether any ray crossed the cell holding `p`.
    bool crossed(const Eigen::Vector3d& p) const;

    double cellSize() const { return cell_; }
    bool empty() const { return masks_.empty(); }
    std::size_t cellsCrossed() const;

private:
    bool indexOf(const Eigen::Vector3d& p, std::uint32_t& index) const;

    Eigen::AlignedBox3d box_;
    double cell_ = 0.1;
    double short_m_ = 0.3;
    double into_cos_ = 0.8;
    Eigen::Vector3i dims_ = Eigen::Vector3i::Zero();
    std::vector<std::uint32_t> masks_;  // per cell: a bit per direction that crossed it
};

}  // namespace handscan::localize
