// The Hokuyo UTM-30LX-EW as a measuring instrument: 1081 steps over 270 deg (0.25 deg/step,
// front = step 540), one scan per 25 ms mirror revolution, each step at its own time; range
// 0.023-60 m; range noise growing with distance; intensity from the surface's reflectivity, the
// incidence angle and the distance; dropouts (error codes below DMIN) on black or glancing
// surfaces and beyond the range. The byte encoding is the driver codec's (hokuyo_stream.hpp).
#pragma once

#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "handscan/sim/laser_hazards.hpp"
#include "handscan/sim/random.hpp"
#include "handscan/sim/raycaster.hpp"

namespace handscan::sim {

struct LaserConfig {
    int steps = 1081;              // AMIN 0 .. AMAX 1080
    int front_step = 540;          // AFRT
    int steps_per_rev = 1440;      // ARES
    double scan_period_s = 0.025;  // SCAN 2400 rpm
    std::uint32_t dmin_mm = 23;
    std::uint32_t dmax_mm = 60000;
    // Range noise sigma = base + per_m * range (datasheet: +-30 mm to 10 m, +-50 mm to 30 m).
    double noise_base_m = 0.008;
    double noise_per_m = 0.0012;
    // Received power ~ reflectivity * cos(incidence) / max(range, 1 m)^2; below this: no echo.
    // 10 % reflectivity is detected to 10 m, white to ~30 m, black plastic to ~5 m.
    double min_return = 8e-4;
    double glancing_cos = 0.06;  // incidence beyond ~86.5 deg: no usable echo
    // Error codes (values below DMIN) the simulator reports.
    std::uint32_t code_no_echo = 1;
    std::uint32_t code_weak = 2;
    std::uint32_t code_too_near = 22;
};

struct LaserScanTruth {
    double t_first_step = 0.0;             // simulation time of step 0
    std::vector<std::uint32_t> ranges_mm;  // what the sensor sends (error codes < dmin_mm)
    std::vector<std::uint32_t> intensities;
    std::vector<float> true_range_m;  // noise-free, NaN without a hit
};

class LaserModel {
public:
    // `hazards` (may be null): people, glass, dark surfaces and mixed pixels (laser_hazards.hpp).
    LaserModel(const LaserConfig& config, const Raycaster& raycaster, Rng rng,
               LaserHazards* hazards = nullptr);

    double stepPeriod() const { return cfg_.scan_period_s / cfg_.steps_per_rev; }
    // Beam direction of a step in the laser frame {L}: x at the front step, rotating about +z.
    Eigen::Vector3f beam(double step) const;
    // One scan whose step 0 is measured at simulation time t0. `pose(t)` gives T_world_laser.
    LaserScanTruth scan(double t0, const std::function<Eigen::Isometry3d(double)>& pose);

private:
    // A mixed pixel: the half-step sub-beams' echoes this far apart merge into one pulse.
    static constexpr double kMixedMinSpread_m = 0.05;
    static constexpr double kMixedMaxSpread_m = 1.0;
    bool mixedPixels() const { return hazards_ != nullptr && hazards_->options().mixed_pixels; }
    std::optional<LaserEcho> sceneEcho(const RayHit& hit, const Eigen::Vector3f& dir) const;
    // The centre beam's echo merged with its footprint halves' (step k) at a depth edge.
    LaserEcho mixedEcho(const LaserEcho& centre, std::size_t k) const;

    LaserConfig cfg_;
    const Raycaster& rc_;
    Rng rng_;
    LaserHazards* hazards_;
    std::vector<Eigen::Vector3f> beams_;
    std::vector<Ray> rays_;
    std::vector<RayHit> hits_;
    std::array<std::vector<Eigen::Vector3f>, 2> half_beams_;
    std::array<std::vector<Ray>, 2> half_rays_;
    std::array<std::vector<RayHit>, 2> half_hits_;
    std::vector<Eigen::Matrix3f> step_rotations_;  // the laser's orientation at each step
};

}  // namespace handscan::sim
