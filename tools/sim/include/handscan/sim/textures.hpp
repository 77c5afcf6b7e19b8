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
    static Eigen::Vector2f planarUv(const Eigen::Vector3f& p, const Eigen::Vector3f& n,
                                    float scale_m);
    // Which world axes give (u, v) on a surface with normal n (v is negated when it is z, so
    // textures stand upright on walls).
    static void planarAxes(const Eigen::Vector3f& n, int& axis_u, int& axis_v, float& sign_v);

    // Fast path for many pixels on one surface: pick the mip level once, then sample it.
    struct Level {
        int size = 0;
        std::vector<std::array<std::uint8_t, 4>> texels;  // r, g, b, grey (compact: cache-friendly)
        std::vector<std::uint8_t> grey;  // grey alone: 4x less cache for mono cameras
    };
    const Level& level(TextureId id, float footprint) const;
    // Bilinear sample of `channels` (1: grey, 3: rgb) into out. Inline: the renderer's inner loop.
    static void sampleLevel(const Level& l, float u, float v, int channels, float* out) {
        const float x = u * static_cast<float>(l.size) - 0.5f,
                    y = v * static_cast<float>(l.size) - 0.5f;
        int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
        x0 -= x < static_cast<float>(x0);  // floor for negative coordinates too
        y0 -= y < static_cast<float>(y0);
        const float fx = x - static_cast<float>(x0), fy = y - static_cast<float>(y0);
        const float wa = (1 - fx) * (1 - fy) * (1.0f / 255.0f),
                    wb = fx * (1 - fy) * (1.0f / 255.0f);
        const float wc = (1 - fx) * fy * (1.0f / 255.0f), wd = fx * fy * (1.0f / 255.0f);
        const int m = l.size - 1;  // sizes are powers of two: wrap = tile
        const std::size_t r0 = static_cast<std::size_t>(y0 & m) * static_cast<std::size_t>(l.size);
        const std::size_t r1 =
            static_cast<std::size_t>((y0 + 1) & m) * static_cast<std::size_t>(l.size);
        const std::size_t c0 = static_cast<std::size_t>(x0 & m),
                          c1 = static_cast<std::size_t>((x0 + 1) & m);
        if (channels == 1) {
            const std::uint8_t* g = l.grey.data();
            out[0] = wa * g[r0 + c0] + wb * g[r0 + c1] + wc * g[r1 + c0] + wd * g[r1 + c1];
            return;
        }
        const auto& a = l.texels[r0 + c0];
        const auto& b = l.texels[r0 + c1];
        const auto& c = l.texels[r1 + c0];
        const auto& d = l.texels[r1 + c1];
        for (std::size_t k = 0; k < 3; ++k) out[k] = wa * a[k] + wb * b[k] + wc * c[k] + wd * d[k];
    }

private:
    std::array<float, 4> sample(TextureId id, float u, float v, float footprint) const;
    std::array<std::vector<Level>, static_cast<std::size_t>(TextureId::kCount)> mips_;
};

}  // namespace handscan::sim
