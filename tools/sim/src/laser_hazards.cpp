#include "handscan/sim/laser_hazards.hpp"

#include <algorithm>
#include <cmath>

namespace handscan::sim {

namespace {
constexpr double kPersonRadius = 0.22;
constexpr double kPersonHeight = 1.75;
constexpr double kPersonReflectivity = 0.35;  // clothes at 905 nm
constexpr double kPersonAside = 0.6;          // a person coming towards passes this far aside
constexpr double kPersonHidden = 0.5;         // nearer than this to the laser: stepped aside
constexpr double kPaneHalfWidth = 0.75, kPaneHalfHeight = 1.0, kPaneAside = 1.0;
constexpr double kPaneSpecularCos = 0.990;  // within ~8 deg of the normal: the pane answers
constexpr double kPaneMirrorShare = 0.25;   // of the other beams, mirrored
constexpr double kPaneTransmission = 0.85;  // power through two glass surfaces
constexpr double kDarkReflectivity = 0.03;

// The path's horizontal left-hand side at time t (x when standing still).
Eigen::Vector3d sideAt(const Trajectory& trajectory, double t) {
    const Eigen::Vector3d v = trajectory.at(t).v_world;
    const Eigen::Vector2d h(v.x(), v.y());
    if (h.norm() < 0.1) return Eigen::Vector3d::UnitX();
    return Eigen::Vector3d(-h.y(), h.x(), 0.0) / h.norm();
}
}  // namespace

LaserHazards::LaserHazards(const HazardOptions& options, const Trajectory& trajectory,
                           const World& world, Rng rng, double hand_height_m)
    : opt_(options), trajectory_(trajectory), rng_(rng), hand_height_m_(hand_height_m) {
    dark_.resize(world.materials.size(), false);
    for (std::size_t m = 0; m < dark_.size(); ++m) dark_[m] = rng_.uniform() < opt_.dark_surfaces;
    const double T = trajectory_.duration();
    for (int i = 0; i < opt_.glass_panes; ++i) {
        const double t = T * (i + 1) / (opt_.glass_panes + 1);
        const Eigen::Vector3d side = sideAt(trajectory_, t) * ((i % 2) == 0 ? 1.0 : -1.0);
        Pane p;
        p.centre = trajectory_.at(t).T_world_body.translation() + kPaneAside * side;
        p.centre.z() += -hand_height_m_ + 0.1 + kPaneHalfHeight;
        p.normal = side;
        p.along = Eigen::Vector3d(-side.y(), side.x(), 0.0);
        panes_.push_back(p);
    }
}

double LaserHazards::reflectivity(const World& world, std::uint32_t triangle) const {
    const std::uint16_t m = world.triangle_material[triangle];
    return dark_[m] ? kDarkReflectivity : world.materials[m].reflectivity;
}

Eigen::Vector3d LaserHazards::personAt(int i, double t) const {
    const double T = trajectory_.duration();
    double tau = 0.0;
    if (i % 2 == 0) {
        tau = t + 3.0 + 1.5 * (i / 2);  // ahead of the operator, on the same path
    } else {
        const int towards = opt_.people / 2;  // the odd ones cross the operator once each
        const double t_cross = T * (i / 2 + 1) / (towards + 1);
        tau = 2.0 * t_cross - t;
    }
    tau = std::clamp(tau, 0.0, T);
    Eigen::Vector3d p = trajectory_.at(tau).T_world_body.translation();
    if (i % 2 == 1) p += kPersonAside * sideAt(trajectory_, tau);
    p.z() -= hand_height_m_;
    return p;
}

std::optional<LaserEcho> LaserHazards::sceneEcho(const Eigen::Vector3f& origin,
                                                 const Eigen::Vector3f& dir, float max_range_m,
                                                 const Raycaster& raycaster) const {
    const RayHit h = raycaster.cast(Ray{origin, dir, max_range_m});
    if (!h.hit()) return std::nullopt;
    const World& w = raycaster.world();
    return LaserEcho{h.t, reflectivity(w, h.triangle),
                     std::abs(static_cast<double>(w.triangleNormal(h.triangle).dot(dir)))};
}

std::optional<LaserEcho> LaserHazards::echo(const Eigen::Vector3f& origin_f,
                                            const Eigen::Vector3f& dir_f, double t,
                                            std::optional<LaserEcho> scene, float max_range_m,
                                            const Raycaster& raycaster) {
    const Eigen::Vector3d o = origin_f.cast<double>(), d = dir_f.cast<double>();
    // The nearest person in front of the beam.
    std::optional<LaserEcho> person;
    for (int i = 0; i < opt_.people; ++i) {
        const Eigen::Vector3d c = personAt(i, t);
        const Eigen::Vector2d rel(o.x() - c.x(), o.y() - c.y());
        if (rel.norm() < kPersonHidden) continue;
        const double a = d.x() * d.x() + d.y() * d.y();
        if (a < 1e-9) continue;
        const double b = 2.0 * (rel.x() * d.x() + rel.y() * d.y());
        const double disc = b * b - 4.0 * a * (rel.squaredNorm() - kPersonRadius * kPersonRadius);
        if (disc < 0.0) continue;
        const double r = (-b - std::sqrt(disc)) / (2.0 * a);
        const double z = o.z() + r * d.z();
        if (r <= 0.0 || z < c.z() || z > c.z() + kPersonHeight) continue;
        if (person && person->range_m <= r) continue;
        const Eigen::Vector2d n = (rel + r * Eigen::Vector2d(d.x(), d.y())).normalized();
        person = LaserEcho{r, kPersonReflectivity, std::abs(n.x() * d.x() + n.y() * d.y())};
    }
    // What the beam meets without glass.
    std::optional<LaserEcho> solid = scene;
    if (person && (!solid || person->range_m < solid->range_m)) solid = person;
    // The nearest pane in front of that.
    const Pane* pane = nullptr;
    double r_pane = solid ? solid->range_m : static_cast<double>(max_range_m);
    for (const Pane& p : panes_) {
        const double den = p.normal.dot(d);
        if (std::abs(den) < 1e-6) continue;
        const double r = p.normal.dot(p.centre - o) / den;
        if (r <= 0.0 || r >= r_pane) continue;
        const Eigen::Vector3d q = o + r * d - p.centre;
        if (std::abs(q.dot(p.along)) > kPaneHalfWidth || std::abs(q.z()) > kPaneHalfHeight)
            continue;
        pane = &p;
        r_pane = r;
    }
    if (pane == nullptr) return solid;
    const double cos_inc = std::abs(pane->normal.dot(d));
    if (cos_inc > kPaneSpecularCos) return LaserEcho{r_pane, 0.6, 1.0};
    if (rng_.uniform() < kPaneMirrorShare) {
        // Mirrored: the point appears behind the pane at the reflected path's length.
        const Eigen::Vector3d m = d - 2.0 * d.dot(pane->normal) * pane->normal;
        const Eigen::Vector3f from = (o + r_pane * d + 1e-3 * m).cast<float>();
        std::optional<LaserEcho> e =
            sceneEcho(from, m.cast<float>(), max_range_m - static_cast<float>(r_pane), raycaster);
        if (!e) return std::nullopt;
        e->range_m += r_pane;
        e->reflectivity *= kPaneTransmission * 0.1;  // a few % of the power is reflected
        return e;
    }
    if (solid) solid->reflectivity *= kPaneTransmission;
    return solid;
}

}  // namespace handscan::sim
