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
            each([&](float u, float v) {
                const float g = 0.9f + 0.06f * f(u, v);
                return C{g, g, g};
            });
            break;
        }
        case TextureId::kPlaster: {
            Fbm f(4, 6, rng);
            each([&](float u, float v) {
                const float g = 0.65f + 0.35f * f(u, v);
                return C{g, g, g};
            });
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
            each([&](float u, float v) {
                const float g = 0.85f + 0.1f * f(u, v);
                return C{g, g, g};
            });
            for (int k = 0; k < 60;
                 ++k) {  // rectangles, text-like bars and discs in random colours
                const int x0 = static_cast<int>(rng.below(N)), y0 = static_cast<int>(rng.below(N));
                const int w = 8 + static_cast<int>(rng.below(120)),
                          h = 4 + static_cast<int>(rng.below(90));
                const C col{static_cast<float>(rng.uniform(0.05, 1)),
                            static_cast<float>(rng.uniform(0.05, 1)),
                            static_cast<float>(rng.uniform(0.05, 1))};
                const bool disc = rng.chance(0.3);
                for (int y = y0; y < y0 + h; ++y)
                    for (int x = x0; x < x0 + w; ++x) {
                        if (disc) {
                            const float dx = (x - x0 - w / 2.0f) / (w / 2.0f),
                                        dy = (y - y0 - h / 2.0f) / (h / 2.0f);
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
            each([&](float u, float v) {
                const float g = 0.4f + 0.3f * f(u, v) + 0.3f * fine(u, v);
                return C{g, g, g};
            });
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
    auto toByte = [](float v) {
        return static_cast<std::uint8_t>(std::clamp(v, 0.0f, 1.0f) * 255.0f + 0.5f);
    };
    for (std::size_t i = 0; i < mips_.size(); ++i) {
        auto& chain = mips_[i];
        // Box-filtered mip chain, filtered in float and stored as bytes.
        Image level = generate(static_cast<TextureId>(i));
        int size = N;
        for (;;) {
            Level l{size, {}, {}};
            l.texels.resize(level.size());
            l.grey.resize(level.size());
            for (std::size_t k = 0; k < level.size(); ++k) {
                for (int c = 0; c < 4; ++c)
                    l.texels[k][static_cast<std::size_t>(c)] =
                        toByte(level[k][static_cast<std::size_t>(c)]);
                l.grey[k] = l.texels[k][3];
            }
            chain.push_back(std::move(l));
            if (size == 1) break;
            const int half = size / 2;
            Image next(static_cast<std::size_t>(half) * half);
            for (int y = 0; y < half; ++y)
                for (int x = 0; x < half; ++x) {
                    std::array<float, 4> sum{};
                    for (int dy = 0; dy < 2; ++dy)
                        for (int dx = 0; dx < 2; ++dx) {
                            const auto& t =
                                level[static_cast<std::size_t>(2 * y + dy) * size + 2 * x + dx];
                            for (int c = 0; c < 4; ++c) sum[c] += 0.25f * t[c];
                        }
                    next[static_cast<std::size_t>(y) * half + x] = sum;
                }
            level = std::move(next);
            size = half;
        }
    }
}

const TextureAtlas& TextureAtlas::instance() {
    static const TextureAtlas atlas;
    return atlas;
}

const TextureAtlas::Level& TextureAtlas::level(TextureId id, float footprint) const {
    const auto& chain = mips_[static_cast<std::size_t>(id)];
    const float texels = footprint * N;
    // Mip level = floor(log2(texels per pixel)), from the float's exponent.
    const int lv =
        texels < 2.0f ? 0 : std::min(std::ilogb(texels), static_cast<int>(chain.size()) - 1);
    return chain[static_cast<std::size_t>(lv)];
}

std::array<float, 4> TextureAtlas::sample(TextureId id, float u, float v, float footprint) const {
    std::array<float, 4> out{};
    const Level& l = level(id, footprint);
    sampleLevel(l, u, v, 3, out.data());
    sampleLevel(l, u, v, 1, out.data() + 3);
    return out;
}

Eigen::Vector3f TextureAtlas::rgb(TextureId id, float u, float v, float footprint) const {
    const auto s = sample(id, u, v, footprint);
    return {s[0], s[1], s[2]};
}

float TextureAtlas::grey(TextureId id, float u, float v, float footprint) const {
    return sample(id, u, v, footprint)[3];
}

void TextureAtlas::planarAxes(const Eigen::Vector3f& n, int& axis_u, int& axis_v, float& sign_v) {
    const Eigen::Vector3f a = n.cwiseAbs();
    if (a.z() >= a.x() && a.z() >= a.y()) {
        axis_u = 0, axis_v = 1, sign_v = 1.0f;
    } else if (a.x() >= a.y()) {
        axis_u = 1, axis_v = 2, sign_v = -1.0f;
    } else {
        axis_u = 0, axis_v = 2, sign_v = -1.0f;
    }
}

Eigen::Vector2f TextureAtlas::planarUv(const Eigen::Vector3f& p, const Eigen::Vector3f& n,
                                       float scale_m) {
    int au, av;
    float sv;
    planarAxes(n, au, av, sv);
    const float inv = 1.0f / scale_m;
    return {p[au] * inv, sv * p[av] * inv};
}

}  // namespace handscan::sim
