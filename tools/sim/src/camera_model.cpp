#include "handscan/sim/camera_model.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <stdexcept>
#include <tuple>

#include "handscan/sim/textures.hpp"

namespace handscan::sim {
namespace {

// x with Phi(x) = p, by Newton's method from the median: Phi is convex below it and concave
// above, so the iterates approach the root from one side without overshooting.
double normalQuantile(double p) {
    const double target = std::clamp(p, 1e-12, 1.0 - 1e-12);
    double x = 0.0;
    for (int it = 0; it < 100; ++it) {
        const double cdf = 0.5 * std::erfc(-x / std::numbers::sqrt2);
        const double pdf = std::exp(-0.5 * x * x) / std::sqrt(2.0 * std::numbers::pi);
        const double step = (cdf - target) / pdf;
        x -= step;
        if (std::abs(step) < 1e-12) break;
    }
    return x;
}

}  // namespace

std::vector<Eigen::Vector3f> cameraRays(const CameraIntrinsics& cam) {
    const int w = cam.resolution[0], h = cam.resolution[1];
    const double fu = cam.intrinsics[0], fv = cam.intrinsics[1], cu = cam.intrinsics[2],
                 cv = cam.intrinsics[3];
    const auto& k = cam.distortion_coeffs;
    auto coeff = [&](std::size_t i) { return i < k.size() ? k[i] : 0.0; };
    std::vector<Eigen::Vector3f> rays(static_cast<std::size_t>(w) * h);
    for (int v = 0; v < h; ++v) {
        for (int u = 0; u < w; ++u) {
            const double mx = (u - cu) / fu, my = (v - cv) / fv;
            Eigen::Vector3d d;
            if (cam.distortion_model == "equidistant") {
                // Kalibr pinhole-equi: theta_d = theta (1 + k1 theta^2 + k2 theta^4 + k3 theta^6 +
                // k4 theta^8).
                const double theta_d = std::hypot(mx, my);
                double th = theta_d;
                for (int it = 0; it < 8; ++it) {
                    const double t2 = th * th;
                    const double f =
                        th * (1 +
                              t2 * (coeff(0) + t2 * (coeff(1) + t2 * (coeff(2) + t2 * coeff(3))))) -
                        theta_d;
                    const double df =
                        1 + t2 * (3 * coeff(0) +
                                  t2 * (5 * coeff(1) + t2 * (7 * coeff(2) + t2 * 9 * coeff(3))));
                    th -= f / df;
                }
                const double s = theta_d > 1e-12 ? std::sin(th) / theta_d : 1.0;
                d = Eigen::Vector3d(mx * s, my * s, std::cos(th));
            } else if (cam.distortion_model == "radtan") {
                // Invert k1 k2 p1 p2 by fixed-point iteration.
                double x = mx, y = my;
                for (int it = 0; it < 20; ++it) {
                    const double r2 = x * x + y * y,
                                 radial = 1 + coeff(0) * r2 + coeff(1) * r2 * r2;
                    const double dx = 2 * coeff(2) * x * y + coeff(3) * (r2 + 2 * x * x);
                    const double dy = coeff(2) * (r2 + 2 * y * y) + 2 * coeff(3) * x * y;
                    x = (mx - dx) / radial;
                    y = (my - dy) / radial;
                }
                d = Eigen::Vector3d(x, y, 1.0).normalized();
            } else {
                d = Eigen::Vector3d(mx, my, 1.0).normalized();
            }
            rays[static_cast<std::size_t>(v) * w + u] = d.cast<float>();
        }
    }
    return rays;
}

CameraRenderer::CameraRenderer(const CameraIntrinsics& intrinsics, const CameraRenderConfig& config,
                               const Raycaster& raycaster, Rng rng)
    : intr_(intrinsics),
      cfg_(config),
      rc_(raycaster),
      rng_(rng),
      w_(intrinsics.resolution[0]),
      h_(intrinsics.resolution[1]),
      channels_(config.colour ? 3 : 1) {
    if (w_ <= 1 || h_ <= 1) throw std::invalid_argument("camera resolution must be at least 2x2");
    const double sc = std::clamp(cfg_.render_scale, 0.1, 1.0);
    rw_ = std::max(2, static_cast<int>(std::lround(w_ * sc)));
    rh_ = std::max(2, static_cast<int>(std::lround(h_ * sc)));
    CameraIntrinsics shading = intr_;
    if (rw_ != w_ || rh_ != h_) {
        // Same lens, fewer pixels: scale focal lengths and principal point (pixel-centre
        // convention).
        const double sx = static_cast<double>(rw_) / w_, sy = static_cast<double>(rh_) / h_;
        shading.intrinsics = {intr_.intrinsics[0] * sx, intr_.intrinsics[1] * sy,
                              (intr_.intrinsics[2] + 0.5) * sx - 0.5,
                              (intr_.intrinsics[3] + 0.5) * sy - 0.5};
        shading.resolution = {rw_, rh_};
    }
    dirs_ = cameraRays(shading);
    vignette_.resize(dirs_.size());
    for (std::size_t i = 0; i < dirs_.size(); ++i)
        vignette_[i] = std::pow(std::max(dirs_[i].z(), 0.05f), 1.5f);
    pixel_angle_ = static_cast<float>(1.0 / shading.intrinsics[0]);
    // Group triangles by (plane, material): a grid cell whose corners share a group is planar.
    const World& w = rc_.world();
    plane_id_.resize(w.triangles.size());
    planes_.resize(w.triangles.size());
    std::map<std::tuple<long, long, long, long, int>, std::uint32_t> ids;
    for (std::size_t i = 0; i < w.triangles.size(); ++i) {
        const Eigen::Vector3f n = w.triangleNormal(i);
        const float d = n.dot(w.vertices[w.triangles[i][0]]);
        planes_[i] = Eigen::Vector4f(n.x(), n.y(), n.z(), d);
        const auto key = std::make_tuple(std::lround(n.x() * 2000), std::lround(n.y() * 2000),
                                         std::lround(n.z() * 2000), std::lround(d * 1000),
                                         static_cast<int>(w.triangle_material[i]));
        plane_id_[i] = ids.emplace(key, static_cast<std::uint32_t>(ids.size())).first->second;
    }
    // Standard normal quantiles at (k + 0.5) / 4096: a table small enough for L1, of exactly
    // Gaussian shape (to +-3.5 sigma); the noise draws pick entries uniformly.
    gauss_table_.resize(4096);
    for (std::size_t k = 0; k < gauss_table_.size(); ++k) {
        gauss_table_[k] =
            static_cast<float>(normalQuantile((static_cast<double>(k) + 0.5) / 4096.0));
    }
    // Column taps of the bilinear upsampling (render_scale < 1).
    up_x0_.resize(static_cast<std::size_t>(w_));
    up_tx_.resize(static_cast<std::size_t>(w_));
    const float sx = static_cast<float>(rw_) / static_cast<float>(w_);
    for (int x = 0; x < w_; ++x) {
        const float fx = std::clamp((static_cast<float>(x) + 0.5f) * sx - 0.5f, 0.0f,
                                    static_cast<float>(rw_ - 1));
        const int x0 = std::min(static_cast<int>(fx), rw_ - 2);
        up_x0_[static_cast<std::size_t>(x)] = static_cast<std::size_t>(x0);
        up_tx_[static_cast<std::size_t>(x)] = fx - static_cast<float>(x0);
    }
}

void CameraRenderer::shade(std::size_t pixel, const Eigen::Vector3f& origin,
                           const Eigen::Vector3f& dir, float t, std::uint32_t triangle,
                           float* out) const {
    const World& w = rc_.world();
    const Material& m = w.materials[w.triangle_material[triangle]];
    Eigen::Vector3f n = planes_[triangle].head<3>();
    float cos_inc = n.dot(dir);
    if (cos_inc > 0) {
        n = -n;
    } else {
        cos_inc = -cos_inc;
    }
    const Eigen::Vector3f p = origin + t * dir;
    const Eigen::Vector2f uv = TextureAtlas::planarUv(p, n, m.texture_scale_m);
    const float footprint = t * pixel_angle_ / (m.texture_scale_m * std::max(cos_inc, 0.25f));
    static const Eigen::Vector3f kLight = Eigen::Vector3f(0.3f, 0.2f, 0.93f).normalized();
    const float light = (0.55f + 0.45f * std::max(0.0f, n.dot(kLight))) * vignette_[pixel] *
                        static_cast<float>(cfg_.illumination);
    const TextureAtlas& atlas = TextureAtlas::instance();
    if (channels_ == 1) {
        const float albedo = 0.299f * m.colour[0] + 0.587f * m.colour[1] + 0.114f * m.colour[2];
        out[0] = atlas.grey(m.texture, uv.x(), uv.y(), footprint) * albedo * light;
    } else {
        const Eigen::Vector3f c = atlas.rgb(m.texture, uv.x(), uv.y(), footprint);
        out[0] = c.x() * m.colour[0] * light;
        out[1] = c.y() * m.colour[1] * light;
        out[2] = c.z() * m.colour[2] * light;
    }
}

void CameraRenderer::radiance(const Eigen::Isometry3d& T, std::vector<float>& rad) {
    const Eigen::Matrix3f R = T.linear().cast<float>();
    const Eigen::Vector3f o = T.translation().cast<float>();
    const int G = std::max(1, cfg_.coarse);
    const World& world = rc_.world();
    const TextureAtlas& atlas = TextureAtlas::instance();
    const Eigen::Vector3f light_dir = Eigen::Vector3f(0.3f, 0.2f, 0.93f).normalized();
    const float illum = static_cast<float>(cfg_.illumination);
    rad.assign(static_cast<std::size_t>(rw_) * rh_ * channels_, 0.0f);
    const float sky[3] = {0.75f * static_cast<float>(cfg_.illumination),
                          0.8f * static_cast<float>(cfg_.illumination),
                          0.9f * static_cast<float>(cfg_.illumination)};
    auto setSky = [&](std::size_t p) {
        for (int c = 0; c < channels_; ++c)
            rad[p * channels_ + c] = channels_ == 1 ? 0.8f * sky[0] / 0.75f : sky[c];
    };
    // 1. Coarse grid of rays.
    std::vector<int> gx, gy;
    for (int x = 0; x < rw_ - 1; x += G) gx.push_back(x);
    gx.push_back(rw_ - 1);
    for (int y = 0; y < rh_ - 1; y += G) gy.push_back(y);
    gy.push_back(rh_ - 1);
    const std::size_t nx = gx.size(), ny = gy.size();
    rays_.resize(nx * ny);
    for (std::size_t j = 0; j < ny; ++j)
        for (std::size_t i = 0; i < nx; ++i) {
            const std::size_t p = static_cast<std::size_t>(gy[j]) * rw_ + gx[i];
            rays_[j * nx + i] = Ray{o, R * dirs_[p], 1e4f};
        }
    std::vector<RayHit> grid(rays_.size());
    rc_.castBatch(rays_, grid, true);
    rays_cast_ += rays_.size();
    // 2. Cells: planar -> analytic; empty -> sky; otherwise trace every pixel.
    std::vector<std::size_t> traced;
    std::vector<Ray> pixel_rays;
    for (std::size_t j = 0; j + 1 < ny; ++j) {
        for (std::size_t i = 0; i + 1 < nx; ++i) {
            const RayHit& a = grid[j * nx + i];
            const RayHit& b = grid[j * nx + i + 1];
            const RayHit& c = grid[(j + 1) * nx + i];
            const RayHit& d = grid[(j + 1) * nx + i + 1];
            const int y0 = gy[j], y1 = (j + 2 == ny) ? gy[j + 1] + 1 : gy[j + 1];
            const int x0 = gx[i], x1 = (i + 2 == nx) ? gx[i + 1] + 1 : gx[i + 1];
            const bool all_hit = a.hit() && b.hit() && c.hit() && d.hit();
            const bool none_hit = !a.hit() && !b.hit() && !c.hit() && !d.hit();
            if (all_hit && plane_id_[a.triangle] == plane_id_[b.triangle] &&
                plane_id_[a.triangle] == plane_id_[c.triangle] &&
                plane_id_[a.triangle] == plane_id_[d.triangle]) {
                // One surface: material, light, texture axes and mip level are the cell's.
                const Eigen::Vector4f& pl = planes_[a.triangle];
                const Eigen::Vector3f n = pl.head<3>();
                const Material& m = world.materials[world.triangle_material[a.triangle]];
                const Eigen::Vector3f dir_a = rays_[j * nx + i].dir;
                const float cos_inc = std::abs(n.dot(dir_a));
                const Eigen::Vector3f nf = n.dot(dir_a) > 0 ? Eigen::Vector3f(-n) : n;
                const float light = (0.55f + 0.45f * std::max(0.0f, nf.dot(light_dir))) * illum;
                float k[3];
                if (channels_ == 1) {
                    k[0] = light *
                           (0.299f * m.colour[0] + 0.587f * m.colour[1] + 0.114f * m.colour[2]);
                } else {
                    for (int ch = 0; ch < 3; ++ch)
                        k[ch] = light * m.colour[static_cast<std::size_t>(ch)];
                }
                int au, av;
                float sv;
                TextureAtlas::planarAxes(n, au, av, sv);
                const float inv_scale = 1.0f / m.texture_scale_m;
                const float t_mid = 0.25f * (a.t + b.t + c.t + d.t);
                const TextureAtlas::Level& level = atlas.level(
                    m.texture, t_mid * pixel_angle_ * inv_scale / std::max(cos_inc, 0.25f));
                // Texture coordinates at the four corner hits, interpolated across the cell: over a
                // few pixels of one plane the lens mapping is smooth enough that this matches the
                // exact per-pixel intersection (camera_test checks against full ray tracing).
                auto uvAt = [&](const RayHit& h, const Ray& r) {
                    const Eigen::Vector3f q = o + h.t * r.dir;
                    return Eigen::Vector2f(q[au] * inv_scale, sv * q[av] * inv_scale);
                };
                const Eigen::Vector2f uva = uvAt(a, rays_[j * nx + i]),
                                      uvb = uvAt(b, rays_[j * nx + i + 1]);
                const Eigen::Vector2f uvc = uvAt(c, rays_[(j + 1) * nx + i]),
                                      uvd = uvAt(d, rays_[(j + 1) * nx + i + 1]);
                const float sx = 1.0f / static_cast<float>(gx[i + 1] - gx[i]);
                const float sy = 1.0f / static_cast<float>(gy[j + 1] - gy[j]);
                for (int y = y0; y < y1; ++y) {
                    const float fy = static_cast<float>(y - y0) * sy;
                    const Eigen::Vector2f left = uva + (uvc - uva) * fy,
                                          right = uvb + (uvd - uvb) * fy;
                    const Eigen::Vector2f step = (right - left) * sx;
                    Eigen::Vector2f uv = left;
                    for (int x = x0; x < x1; ++x, uv += step) {
                        const std::size_t p = static_cast<std::size_t>(y) * rw_ + x;
                        float tex[3];
                        TextureAtlas::sampleLevel(level, uv.x(), uv.y(), channels_, tex);
                        float* out = &rad[p * channels_];
                        const float vig = vignette_[p];
                        for (int ch = 0; ch < channels_; ++ch) out[ch] = tex[ch] * k[ch] * vig;
                    }
                }
            } else if (none_hit) {
                for (int y = y0; y < y1; ++y)
                    for (int x = x0; x < x1; ++x) setSky(static_cast<std::size_t>(y) * rw_ + x);
            } else {
                for (int y = y0; y < y1; ++y)
                    for (int x = x0; x < x1; ++x) {
                        const std::size_t p = static_cast<std::size_t>(y) * rw_ + x;
                        traced.push_back(p);
                        pixel_rays.push_back(Ray{o, R * dirs_[p], 1e4f});
                    }
            }
        }
    }
    hits_.resize(pixel_rays.size());
    rc_.castBatch(pixel_rays, hits_, true);
    rays_cast_ += pixel_rays.size();
    for (std::size_t k = 0; k < traced.size(); ++k) {
        const std::size_t p = traced[k];
        if (hits_[k].hit()) {
            shade(p, o, pixel_rays[k].dir, hits_[k].t, hits_[k].triangle, &rad[p * channels_]);
        } else {
            setSky(p);
        }
    }
}

void CameraRenderer::render(double t_start, const std::function<Eigen::Isometry3d(double)>& pose,
                            std::vector<std::uint8_t>& out) {
    const int samples = cfg_.motion_blur ? std::max(2, cfg_.blur_samples) : 1;
    if (samples == 1) {
        radiance(pose(t_start + 0.5 * cfg_.exposure_s), rad_);
    } else {
        acc_.assign(static_cast<std::size_t>(rw_) * rh_ * channels_, 0.0f);
        for (int s = 0; s < samples; ++s) {
            radiance(pose(t_start + cfg_.exposure_s * (s + 0.5) / samples), rad_);
            for (std::size_t i = 0; i < acc_.size(); ++i)
                acc_[i] += rad_[i] / static_cast<float>(samples);
        }
        rad_.swap(acc_);
    }
    if (rw_ != w_ || rh_ != h_) {
        // Bilinear upsampling of the shaded image to the sensor's resolution (column taps and
        // weights precomputed: this runs over every output value of the colour camera).
        full_.resize(static_cast<std::size_t>(w_) * h_ * channels_);
        const float sy = static_cast<float>(rh_) / static_cast<float>(h_);
        const std::size_t C = static_cast<std::size_t>(channels_);
        for (int y = 0; y < h_; ++y) {
            const float fy = std::clamp((static_cast<float>(y) + 0.5f) * sy - 0.5f, 0.0f,
                                        static_cast<float>(rh_ - 1));
            const int y0 = std::min(static_cast<int>(fy), rh_ - 2);
            const float ty = fy - static_cast<float>(y0);
            const float* r0 = &rad_[static_cast<std::size_t>(y0) * rw_ * C];
            const float* r1 = r0 + static_cast<std::size_t>(rw_) * C;
            float* o = &full_[static_cast<std::size_t>(y) * w_ * C];
            for (int x = 0; x < w_; ++x, o += C) {
                const std::size_t i = up_x0_[static_cast<std::size_t>(x)] * C;
                const float tx = up_tx_[static_cast<std::size_t>(x)];
                for (std::size_t c = 0; c < C; ++c) {
                    const float top = r0[i + c] + (r0[i + C + c] - r0[i + c]) * tx;
                    const float bottom = r1[i + c] + (r1[i + C + c] - r1[i + c]) * tx;
                    o[c] = top + (bottom - top) * ty;
                }
            }
        }
        rad_.swap(full_);
    }
    // Exposure, shot + read noise, 8 bits.
    const float scale =
        static_cast<float>(255.0 * cfg_.gain * cfg_.exposure_s / cfg_.reference_exposure_s);
    // Noise sigma per signal level (read noise + shot noise), tabulated.
    float sigma[257];
    for (int d = 0; d <= 256; ++d)
        sigma[d] = static_cast<float>(
            std::sqrt(cfg_.read_noise_dn * cfg_.read_noise_dn + cfg_.shot_noise_gain * d));
    out.resize(rad_.size());
    // One 64-bit draw gives four 12-bit indices into the Gaussian quantile table.
    auto noisy = [&](float radiance, unsigned index) {
        const float dn = std::min(radiance * scale, 300.0f);
        const int level = std::clamp(static_cast<int>(dn), 0, 256);
        // Clamped to 0..255 first, so truncation is the floor.
        const float v = std::clamp(dn + gauss_table_[index] * sigma[level] + 0.5f, 0.0f, 255.0f);
        return static_cast<std::uint8_t>(v);
    };
    const std::size_t n = rad_.size();
    std::size_t i = 0;
    for (; i + 4 <= n; i += 4) {
        const std::uint64_t bits = rng_.next();
        for (unsigned k = 0; k < 4; ++k)
            out[i + k] = noisy(rad_[i + k], static_cast<unsigned>(bits >> (16 * k)) & 0xFFFu);
    }
    for (const std::uint64_t bits = rng_.next(); i < n; ++i)
        out[i] = noisy(rad_[i], static_cast<unsigned>(bits >> (16 * (i & 3))) & 0xFFFu);
    pixels_ += static_cast<std::uint64_t>(w_) * h_;
}

}  // namespace handscan::sim
