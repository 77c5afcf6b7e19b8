#include "handscan/sim/laser_model.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace handscan::sim {

LaserModel::LaserModel(const LaserConfig& config, const Raycaster& raycaster, Rng rng)
    : cfg_(config), rc_(raycaster), rng_(rng) {
    for (int k = 0; k < cfg_.steps; ++k) beams_.push_back(beam(k));
    rays_.resize(static_cast<std::size_t>(cfg_.steps));
    hits_.resize(static_cast<std::size_t>(cfg_.steps));
}

Eigen::Vector3f LaserModel::beam(int step) const {
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
        rays_[k].origin = T.translation().cast<float>();
        rays_[k].dir = (T.linear().cast<float>() * beams_[k]).normalized();
        rays_[k].tmax = static_cast<float>(max_m * 1.05);
    }
    rc_.castBatch(rays_, hits_, false);
    out.ranges_mm.resize(n);
    out.intensities.resize(n);
    out.true_range_m.resize(n);
    const World& w = rc_.world();
    for (std::size_t k = 0; k < n; ++k) {
        const RayHit& h = hits_[k];
        if (!h.hit()) {
            out.true_range_m[k] = std::numeric_limits<float>::quiet_NaN();
            out.ranges_mm[k] = cfg_.code_no_echo;
            out.intensities[k] = static_cast<std::uint32_t>(rng_.below(40));
            continue;
        }
        const double r = h.t;
        out.true_range_m[k] = h.t;
        const Material& m = w.materials[w.triangle_material[h.triangle]];
        const double cos_inc =
            std::abs(static_cast<double>(w.triangleNormal(h.triangle).dot(rays_[k].dir)));
        const double power = m.reflectivity * cos_inc / std::max(r * r, 1.0);
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
            200.0 + 9000.0 * m.reflectivity * cos_inc * std::min(1.0, 3.0 / std::max(r, 1e-3));
        out.intensities[k] = static_cast<std::uint32_t>(std::clamp(
            intensity * (1.0 + rng_.gauss(0.03)), 0.0, 16000.0));  // 3-char field max 262143
    }
    return out;
}

}  // namespace handscan::sim
