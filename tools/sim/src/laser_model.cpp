#include "handscan/sim/laser_model.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace handscan::sim {

LaserModel::LaserModel(const LaserConfig& config, const Raycaster& raycaster, Rng rng,
                       LaserHazards* hazards)
    : cfg_(config), rc_(raycaster), rng_(rng), hazards_(hazards) {
    for (int k = 0; k < cfg_.steps; ++k) beams_.push_back(beam(k));
    rays_.resize(static_cast<std::size_t>(cfg_.steps));
    hits_.resize(static_cast<std::size_t>(cfg_.steps));
    if (mixedPixels()) {
        // The footprint's two halves: half a step either side of the beam's centre.
        for (int k = 0; k < cfg_.steps; ++k) {
            half_beams_[0].push_back(beam(k - 0.5));
            half_beams_[1].push_back(beam(k + 0.5));
        }
        step_rotations_.resize(rays_.size());
        for (int side = 0; side < 2; ++side) {
            half_rays_[side].resize(rays_.size());
            half_hits_[side].resize(rays_.size());
        }
    }
}

Eigen::Vector3f LaserModel::beam(double step) const {
    const double a = (step - cfg_.front_step) * 2.0 * std::numbers::pi / cfg_.steps_per_rev;
    return Eigen::Vector3f(static_cast<float>(std::cos(a)), static_cast<float>(std::sin(a)), 0.0f);
}

LaserScanTruth LaserModel::scan(double t0, const std::function<Eigen::Isometry3d(double)>& pose) {
    LaserScanTruth out;
    out.t_first_step = t0;
    const auto n = static_cast<std::size_t>(cfg_.steps);
    const double max_m = cfg_.dmax_mm * 1e-3;
    // Each step's ray leaves from the laser's pose at that step's time (the rig moves and the
    // shaft turns during the 18.75 ms the beam needs for 270 deg).
    for (std::size_t k = 0; k < n; ++k) {
        const Eigen::Isometry3d T = pose(t0 + static_cast<double>(k) * stepPeriod());
        if (mixedPixels()) step_rotations_[k] = T.linear().cast<float>();
        rays_[k].origin = T.translation().cast<float>();
        rays_[k].dir = (T.linear().cast<float>() * beams_[k]).normalized();
        rays_[k].tmax = static_cast<float>(max_m * 1.05);
    }
    rc_.castBatch(rays_, hits_, false);
    if (mixedPixels()) {
        for (int side = 0; side < 2; ++side) {
            for (std::size_t k = 0; k < n; ++k) {
                half_rays_[side][k] = rays_[k];
                half_rays_[side][k].dir = (step_rotations_[k] * half_beams_[side][k]).normalized();
            }
            rc_.castBatch(half_rays_[side], half_hits_[side], false);
        }
    }
    out.ranges_mm.resize(n);
    out.intensities.resize(n);
    out.true_range_m.resize(n);
    for (std::size_t k = 0; k < n; ++k) {
        std::optional<LaserEcho> e = sceneEcho(hits_[k], rays_[k].dir);
        if (mixedPixels() && e) e = mixedEcho(*e, k);
        if (hazards_ != nullptr) {
            e = hazards_->echo(rays_[k].origin, rays_[k].dir,
                               t0 + static_cast<double>(k) * stepPeriod(), e,
                               static_cast<float>(max_m * 1.05), rc_);
        }
        if (!e) {
            out.true_range_m[k] = std::numeric_limits<float>::quiet_NaN();
            out.ranges_mm[k] = cfg_.code_no_echo;
            out.intensities[k] = static_cast<std::uint32_t>(rng_.below(40));
            continue;
        }
        const double r = e->range_m;
        out.true_range_m[k] = static_cast<float>(r);
        const double cos_inc = e->cos_incidence;
        const double reflectivity = e->reflectivity;
        const double power = reflectivity * cos_inc / std::max(r * r, 1.0);
        // Soft detection threshold: near the limit echoes come and go.
        const double margin = std::log(power / cfg_.min_return);
        const bool detected =
            cos_inc > cfg_.glancing_cos && rng_.uniform() < 1.0 / (1.0 + std::exp(-margin / 0.15));
        if (!detected) {
            out.ranges_mm[k] = cfg_.code_weak;
            out.intensities[k] = static_cast<std::uint32_t>(rng_.below(80));
            continue;
        }
        const double measured = r + rng_.gauss(cfg_.noise_base_m + cfg_.noise_per_m * r);
        const double mm = std::round(measured * 1000.0);
        if (mm < cfg_.dmin_mm) {
            out.ranges_mm[k] = cfg_.code_too_near;
        } else if (mm > cfg_.dmax_mm) {
            out.ranges_mm[k] = cfg_.code_no_echo;
        } else {
            out.ranges_mm[k] = static_cast<std::uint32_t>(mm);
        }
        // Intensity (arbitrary units as the UTM reports them, saturating at close range).
        const double intensity =
            200.0 + 9000.0 * reflectivity * cos_inc * std::min(1.0, 3.0 / std::max(r, 1e-3));
        out.intensities[k] = static_cast<std::uint32_t>(std::clamp(
            intensity * (1.0 + rng_.gauss(0.03)), 0.0, 16000.0));  // 3-char field max 262143
    }
    return out;
}

std::optional<LaserEcho> LaserModel::sceneEcho(const RayHit& h, const Eigen::Vector3f& dir) const {
    if (!h.hit()) return std::nullopt;
    const World& w = rc_.world();
    const double reflectivity = hazards_ != nullptr
                                    ? hazards_->reflectivity(w, h.triangle)
                                    : w.materials[w.triangle_material[h.triangle]].reflectivity;
    return LaserEcho{h.t, reflectivity,
                     std::abs(static_cast<double>(w.triangleNormal(h.triangle).dot(dir)))};
}

LaserEcho LaserModel::mixedEcho(const LaserEcho& centre, std::size_t k) const {
    const std::optional<LaserEcho> a = sceneEcho(half_hits_[0][k], half_rays_[0][k].dir);
    const std::optional<LaserEcho> b = sceneEcho(half_hits_[1][k], half_rays_[1][k].dir);
    if (!a || !b) return centre;  // an edge against nothing: one echo or none
    const double lo = std::min({a->range_m, b->range_m, centre.range_m});
    const double hi = std::max({a->range_m, b->range_m, centre.range_m});
    // Farther apart than the pulse (~1 m), the echoes separate and the first one is reported.
    if (hi - lo < kMixedMinSpread_m || hi - lo > kMixedMaxSpread_m) return centre;
    double sum_w = 0.0, sum_r = 0.0;
    LaserEcho mixed = centre;
    for (const auto& [e, share] :
         {std::pair{*a, 1.0}, std::pair{centre, 2.0}, std::pair{*b, 1.0}}) {
        const double w =
            share * e.reflectivity * e.cos_incidence / std::max(e.range_m * e.range_m, 1.0);
        sum_w += w;
        sum_r += w * e.range_m;
    }
    if (sum_w > 0.0) mixed.range_m = sum_r / sum_w;
    return mixed;
}

}  // namespace handscan::sim
