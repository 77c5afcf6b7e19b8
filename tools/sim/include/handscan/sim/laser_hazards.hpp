// LaserHazards: what makes the world harder for a real laser than the scene's static surfaces,
// each an option of `handscan sim` (issue 13), so the pipeline's figures can be measured under it:
//   people       pedestrians (vertical cylinders, 0.22 m radius, 1.75 m tall) walking the
//                operator's own path - half of them ahead of the operator, half coming towards
//                and passing 0.6 m to the side - so they are in view, move, and occlude;
//   glass        vertical panes (1.5 x 2 m) beside the path: near normal incidence (< 8 deg) a
//                specular return from the pane; otherwise a quarter of the beams are mirrored
//                (a phantom point behind the pane at the reflected path's length), the rest pass
//                through, weakened;
//   mixed pixels the beam's footprint (one step wide) straddling a depth edge: when the two
//                half-step sub-beams' ranges differ by 5 cm to 1 m (one merged echo pulse), the
//                range is their power-weighted mean - the points floating between the surfaces;
//   dark         a share of the scene's materials black at 905 nm (3 % reflectivity): dropouts
//                from a few metres (the detection model of LaserModel);
//   range noise  the datasheet's range noise scaled (an older or dirtier sensor).
// Laser only: the cameras render the static scene. Deterministic per seed (own random stream).
#pragma once

#include <Eigen/Geometry>
#include <optional>
#include <vector>

#include "handscan/sim/random.hpp"
#include "handscan/sim/raycaster.hpp"
#include "handscan/sim/trajectory.hpp"

namespace handscan::sim {

struct HazardOptions {
    int people = 0;
    int glass_panes = 0;
    bool mixed_pixels = false;
    double dark_surfaces = 0.0;      // share of the scene's materials made black, [0, 1]
    double range_noise_scale = 1.0;  // times the datasheet's range noise
    bool any() const {
        return people > 0 || glass_panes > 0 || mixed_pixels || dark_surfaces > 0.0 ||
               range_noise_scale != 1.0;
    }
};

// One beam's echo: range along the beam, the surface's reflectivity and the incidence cosine.
struct LaserEcho {
    double range_m = 0.0;
    double reflectivity = 0.0;
    double cos_incidence = 1.0;
};

class LaserHazards {
public:
    // `trajectory`: the operator's path (people walk it, panes stand beside it); `hand_height_m`:
    // the device's height above the floor while walking.
    LaserHazards(const HazardOptions& options, const Trajectory& trajectory, const World& world,
                 Rng rng, double hand_height_m = 1.3);

    const HazardOptions& options() const { return opt_; }
    // The reflectivity the laser sees for a material (dark surfaces).
    double reflectivity(const World& world, std::uint32_t triangle) const;
    // The echo of a beam from `origin` along unit `dir` at simulation time t, given what the
    // static scene returned (nullopt: nothing within range): people and glass in front of it
    // replace it. `raycaster` casts the glass's transmitted and mirrored beams.
    std::optional<LaserEcho> echo(const Eigen::Vector3f& origin, const Eigen::Vector3f& dir,
                                  double t, std::optional<LaserEcho> scene, float max_range_m,
                                  const Raycaster& raycaster);
    // A person's feet position at time t (tests, the figures).
    Eigen::Vector3d personAt(int i, double t) const;

private:
    struct Pane {
        Eigen::Vector3d centre, normal, along;  // along: horizontal unit in the pane
    };
    std::optional<LaserEcho> sceneEcho(const Eigen::Vector3f& origin, const Eigen::Vector3f& dir,
                                       float max_range_m, const Raycaster& raycaster) const;

    HazardOptions opt_;
    const Trajectory& trajectory_;
    Rng rng_;
    double hand_height_m_;
    std::vector<bool> dark_;  // per material
    std::vector<Pane> panes_;
};

}  // namespace handscan::sim
