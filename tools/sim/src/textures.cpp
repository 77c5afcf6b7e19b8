#include "handscan/sim/textures.hpp"

#include <algorithm>
#include <cmath>

#include "handscan/sim/random.hpp"

namespace handscan::sim {
namespace {

constexpr int N = TextureAtlas::kSize;

// Periodic value noise on an integer lattice of `period` cells across the tile.
struct ValueNoise {
    std::vector<float> lattice;
    int period;
    ValueNoise(int p, Rng& rng) : lattice(static_cast<std::size_t>(p) * p), period(p) {
        for (auto& v : lattice) v = static_cast<float>(rng.uniform());
    }
    float at(int x, int y) const {
        x %= period;
        y %= period;
        if (x < 0) x += period;
        if (y < 0) y += period;
        return lattice[static_cast<std::size_t>(y) * period + x];
    }
    // (u, v) in [0, 1): smooth interpolation.
    float operator()(float u, float v) const {
        const float x = u * period, y = v * period;
        const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
        float fx = x - x0, fy = y - y0;
        fx = fx * fx * (3 - 2 * fx);
        fy = fy * fy * (3 - 2 * fy);
        const float a = at(x0, y0), b = at(x0 + 1, y0), c = at(x0, y0 + 1), d = at(x0 + 1, y0 + 1);
        return (a * (1 - fx) + b * fx) * (1 - fy) + (c * (1 - fx) + d * fx) * fy;
    }
};

struct Fbm {
    std::vector<ValueNoise> octaves;
    Fbm(int base_period, int count, Rng& rng) {
        for (int i = 0; i < count; ++i) octaves.emplace_back(base_period << i, rng);
    }
    float operator()(float u, float v) const {
        float sum = 0, amp = 0.5f, norm = 0;
        for (const auto& o : octaves) {
            sum += amp * o(u, v);
            norm += amp;
            amp *= 0.5f;
        }
        return sum / norm;
    }
};

using Image = std::vector<std::array<float, 4>>;

void set(Image& img, int x, int y, float r, float g, float b) {
    img[static_cast<std::size_t>(y) * N + x] = {r, g, b, 0.0f};
}

Image generate(TextureId id) {
    Rng rng(0x7E47u + static_cast<std::uint64_t>(id), "texture");
    Image img(static_cast<std::size_t>(N) * N);
    auto each = [&](auto f) {
        for (int y = 0; y < N; ++y)
            for (int x = 0; x < N; ++x) {
                const auto c = f((x + 0.5f) / N, (y + 0.5f) / N);
                set(img, x, y, c[0], c[1], c[2]);
            }
    };
    using C = std::array<float, 3>;
    switch (id) {
        case TextureId::kPlain: {
            Fbm f(2, 3, rng);
            each([&](float u, float v) { const float g = 0.9f + 0.06f * f(u, v); return C{g, g, g}; });
            break;
        }
        case TextureId::kPlaster: {
            Fbm f(4, 6, rng);
            each([&](float u, float v) { const float g = 0.65f + 0.35f * f(u, v); return C{g, g, g}; });
            break;
        }
        case TextureId::kConcrete: {
            Fbm f(4, 7, rng);
            ValueNoise speck(128, rng);
            each([&](float u, float v) {
                float g = 0.35f + 0.55f * f(u, v);
                if (speck(u, v) > 0.82f) g *= 0.45f;
                return C{g, g, g};
            });
            break;
        }
        case TextureId::kChecker: {
            Fbm f(8, 3, rng);
            each([&](float u, float v) {
                const bool on = (static_cast<int>(u * 8) + static_cast<int>(v * 8)) % 2 == 0;
                const float g = (on ? 0.92f : 0.12f) + 0.04f * f(u, v);
                return C{g, g, g};
            });
            break;
        }
        case TextureId::kPosters: {
            Fbm f(8, 4, rng);
            each([&](float u, float v) { const float g = 0.85f + 0.1f * f(u, v); return C{g, g, g}; });
            for (int k = 0; k < 60; ++k) {  // rectangles, text-like bars and discs in random colours
                const int x0 = static_cast<int>(rng.below(N)), y0 = static_cast<int>(rng.below(N));
                const int w = 8 + static_cast<int>(rng.below(120)), h = 4 + static_cast<int>(rng.below(90));
                const C col{static_cast<float>(rng.uniform(0.05, 1)), static_cast<float>(rng.uniform(0.05, 1)),
                            static_cast<float>(rng.uniform(0.05, 1))};
                const bool disc = rng.chance(0.3);
                for (int y = y0; y < y0 + h; ++y)
                    for (int x = x0; x < x0 + w; ++x) {
                        if (disc) {
                            const float dx = (x - x0 - w / 2.0f) / (w / 2.0f), dy = (y - y0 - h / 2.0f) / (h / 2.0f);
                            if (dx * dx + dy * dy > 1) continue;
                        }
                        set(img, x & (N - 1), y & (N - 1), col[0], col[1], col[2]);
                    }
            }
            break;
        }
        case TextureId::kWood: {
            Fbm f(4, 5, rng);
            each([&](float u, float v) {
                const float ring = 0.5f + 0.5f * std::sin(40.0f * (v + 0.15f * f(u, v)));
                const float g = 0.45f + 0.35f * ring + 0.1f * f(u * 4, v);
                return C{g * 1.0f, g * 0.8f, g * 0.6f};
            });
            break;
        }
        case TextureId::kBrick: {
            Fbm f(16, 4, rng);
            ValueNoise tone(64, rng);
            each([&](float u, float v) {
                const int row = static_cast<int>(v * 16);
                const float bu = u * 8 + (row % 2 ? 0.5f : 0.0f);
                const float fu = bu - std::floor(bu), fv = v * 16 - row;
                if (fu < 0.06f || fv < 0.12f) return C{0.8f, 0.8f, 0.78f};  // mortar
                const float t = tone(std::floor(bu) / 64.0f, row / 64.0f);
                const float g = 0.5f + 0.3f * t + 0.15f * f(u, v);
                return C{g, g * 0.7f, g * 0.6f};
            });
            break;
        }
        case TextureId::kCarpet: {
            Fbm f(32, 4, rng);
            ValueNoise fine(256, rng);
            each([&](float u, float v) { const float g = 0.4f + 0.3f * f(u, v) + 0.3f * fine(u, v); return C{g, g, g}; });
            break;
        }
        case TextureId::kFoliage: {
            Fbm f(16, 5, rng);
            each([&](float u, float v) {
                const float n = f(u, v);
                const float g = n > 0.55f ? 0.9f : (n < 0.42f ? 0.15f : 0.5f);
                return C{g * 0.7f, g, g * 0.6f};
            });
            break;
        }
        case TextureId::kGrass: {
            Fbm f(16, 6, rng);
            ValueNoise blades(256, rng);
            each([&](float u, float v) {
                const float g = 0.3f + 0.4f * f(u, v) + 0.3f * blades(u * 0.25f, v);
                return C{g * 0.8f, g, g * 0.6f};
            });
            break;
        }
        case TextureId::kBark: {
            Fbm f(8, 5, rng);
            each([&](float u, float v) {
                const float g = 0.3f + 0.5f * f(u * 8.0f - std::floor(u * 8.0f), v * 0.5f);
                return C{g, g * 0.85f, g * 0.7f};
            });
            break;
        }
        case TextureId::kCount:
            break;
    }
    for (auto& t : img) t[3] = 0.299f * t[0] + 0.587f * t[1] + 0.114f * t[2];
    return img;
}

}  // namespace

TextureAtlas::TextureAtlas() {
    for (std::size_t i = 0; i < mips_.size(); ++i) {
        auto& chain = mips_[i];
        chain.push_back({N, generate(static_cast<TextureId>(i))});
        while (chain.back().size > 1) {  // box-filtered mip chain
            const Level& prev = chain.back();
            Level next{prev.size / 2, {}};
            next.texels.resize(static_cast<std::size_t>(next.size) * next.size);
            for (int y = 0; y < next.size; ++y)
                for (int x = 0; x < next.size; ++x) {
                    std::array<float, 4> s{};
                    for (int dy = 0; dy < 2; ++dy)
                        for (int dx = 0; dx < 2; ++dx) {
                            const auto& t = prev.texels[static_cast<std::size_t>(2 * y + dy) * prev.size + 2 * x + dx];
                            for (int c = 0; c < 4; ++c) s[c] += 0.25f * t[c];
                        }
                    next.texels[static_cast<std::size_t>(y) * next.size + x] = s;
                }
            chain.push_back(std::move(next));
        }
    }
}

const TextureAtlas& TextureAtlas::instance() {
    static const TextureAtlas atlas;
    return atlas;
}

std::array<float, 4> TextureAtlas::sample(TextureId id, float u, float v, float footprint) const {
    const auto& chain = mips_[static_cast<std::size_t>(id)];
    const float texels = std::max(footprint * N, 1.0f);
    const int level = std::min(static_cast<int>(std::log2(texels)), static_cast<int>(chain.size()) - 1);
    const Level& l = chain[static_cast<std::size_t>(level)];
    const float x = (u - std::floor(u)) * l.size - 0.5f, y = (v - std::floor(v)) * l.size - 0.5f;
    const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
    const float fx = x - x0, fy = y - y0;
    const auto& a = texel(l, x0, y0);
    const auto& b = texel(l, x0 + 1, y0);
    const auto& c = texel(l, x0, y0 + 1);
    const auto& d = texel(l, x0 + 1, y0 + 1);
    std::array<float, 4> out;
    for (int k = 0; k < 4; ++k) out[k] = (a[k] * (1 - fx) + b[k] * fx) * (1 - fy) + (c[k] * (1 - fx) + d[k] * fx) * fy;
    return out;
}

Eigen::Vector3f TextureAtlas::rgb(TextureId id, float u, float v, float footprint) const {
    const auto s = sample(id, u, v, footprint);
    return {s[0], s[1], s[2]};
}

float TextureAtlas::grey(TextureId id, float u, float v, float footprint) const { return sample(id, u, v, footprint)[3]; }

Eigen::Vector2f TextureAtlas::planarUv(const Eigen::Vector3f& p, const Eigen::Vector3f& n, float scale_m) {
    const Eigen::Vector3f a = n.cwiseAbs();
    const float inv = 1.0f / scale_m;
    if (a.z() >= a.x() && a.z() >= a.y()) return {p.x() * inv, p.y() * inv};
    if (a.x() >= a.y()) return {p.y() * inv, -p.z() * inv};
    return {p.x() * inv, -p.z() * inv};
}

}  // namespace handscan::sim
