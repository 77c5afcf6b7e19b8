// Procedural textures for the cameras: one tiling 512x512 RGB image per TextureId, generated
// once (deterministically) with a mip chain, sampled bilinearly at the level that matches a
// pixel's footprint (so distant surfaces do not alias into fake corners). Surfaces are mapped
// by triplanar projection: the two world axes most parallel to the triangle, divided by the
// material's tile size.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "handscan/sim/world.hpp"

namespace handscan::sim {

class TextureAtlas {
public:
    static constexpr int kSize = 512;
    TextureAtlas();
    // Shared, built on first use.
    static const TextureAtlas& instance();

    // RGB in [0, 1] at texture coordinates (u, v) in tiles; `footprint` is the pixel's size in
    // tiles (chooses the mip level).
    Eigen::Vector3f rgb(TextureId id, float u, float v, float footprint) const;
    float grey(TextureId id, float u, float v, float footprint) const;

    // Texture coordinates (in tiles) of world point p on a surface with normal n.
    static Eigen::Vector2f planarUv(const Eigen::Vector3f& p, const Eigen::Vector3f& n, float scale_m);

private:
    struct Level {
        int size = 0;
        std::vector<std::array<float, 4>> texels;  // r, g, b, grey
    };
    const std::array<float, 4>& texel(const Level& l, int x, int y) const {
        return l.texels[static_cast<std::size_t>(y & (l.size - 1)) * l.size + (x & (l.size - 1))];
    }
    std::array<float, 4> sample(TextureId id, float u, float v, float footprint) const;
    std::array<std::vector<Level>, static_cast<std::size_t>(TextureId::kCount)> mips_;
};

}  // namespace handscan::sim
