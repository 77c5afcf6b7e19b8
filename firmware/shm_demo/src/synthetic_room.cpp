#include "handscan/shm_demo/synthetic_room.hpp"

#include <algorithm>
#include <cmath>

namespace handscan::shm_demo {
namespace {

constexpr double kPi = 3.14159265358979323846;

}  // namespace

SyntheticRoom::SyntheticRoom(RoomOptions options)
    : o_(options), rng_(options.seed), voxels_(static_cast<float>(options.voxel_m)) {}

PoseEstimate SyntheticRoom::poseAt(double t_s) const {
    // An ellipse 1 m inside the walls, walked at walk_speed_mps (approximately), facing forward.
    const double a = o_.width_m / 2 - 1.0, b = o_.depth_m / 2 - 1.0;
    const double circumference = kPi * (3 * (a + b) - std::sqrt((3 * a + b) * (a + 3 * b)));
    const double phi = 2 * kPi * t_s * o_.walk_speed_mps / circumference;
    PoseEstimate p;
    p.t_host = static_cast<TimeNs>(t_s * 1e9);
    p.T_world_body.translation() =
        Eigen::Vector3d(a * std::cos(phi), b * std::sin(phi), 1.4 + 0.03 * std::sin(5 * phi));
    const double heading = std::atan2(b * std::cos(phi), -a * std::sin(phi));
    p.T_world_body.linear() =
        Eigen::AngleAxisd(heading, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    p.source = PoseSource::kIntegrated;
    p.solved_dof_mask = 0x3F;
    return p;
}

std::vector<shm::DisplayPoint> SyntheticRoom::observe(const PoseEstimate& pose, int samples) {
    std::vector<shm::DisplayPoint> out;
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const Eigen::Vector3d c = pose.T_world_body.translation();
    const double w = o_.width_m / 2, d = o_.depth_m / 2, h = o_.height_m;
    for (int i = 0; i < samples; ++i) {
        // Pick a surface by area, then a point on it.
        const int s = static_cast<int>(u(rng_) * 6);
        double x = 0, y = 0, z = 0;
        std::uint8_t r = 0, g = 0, b = 0;
        switch (s) {
            case 0:
                x = -w;
                y = (u(rng_) * 2 - 1) * d;
                z = u(rng_) * h;
                r = 200;
                g = 90;
                b = 70;
                break;  // west wall: brick red
            case 1:
                x = w;
                y = (u(rng_) * 2 - 1) * d;
                z = u(rng_) * h;
                r = 80;
                g = 140;
                b = 200;
                break;  // east wall: blue
            case 2:
                y = -d;
                x = (u(rng_) * 2 - 1) * w;
                z = u(rng_) * h;
                r = 220;
                g = 210;
                b = 120;
                break;  // south: yellow
            case 3:
                y = d;
                x = (u(rng_) * 2 - 1) * w;
                z = u(rng_) * h;
                r = 110;
                g = 190;
                b = 110;
                break;  // north: green
            case 4:
                z = 0;
                x = (u(rng_) * 2 - 1) * w;
                y = (u(rng_) * 2 - 1) * d;
                {  // floor: tiles
                    const bool dark =
                        (static_cast<int>(std::floor(x)) + static_cast<int>(std::floor(y))) & 1;
                    r = g = b = dark ? 90 : 170;
                }
                break;
            default:
                z = h;
                x = (u(rng_) * 2 - 1) * w;
                y = (u(rng_) * 2 - 1) * d;
                r = g = b = 235;
                break;  // ceiling
        }
        const Eigen::Vector3d pt(x, y, z);
        if ((pt - c).norm() > o_.range_m) continue;
        shm::DisplayPoint p;
        p.x_m = static_cast<float>(x);
        p.y_m = static_cast<float>(y);
        p.z_m = static_cast<float>(z);
        if (!voxels_.insert(p)) continue;
        p.r = r;
        p.g = g;
        p.b = b;
        // Intensity falls with range and incidence, as a real return does.
        p.intensity =
            static_cast<std::uint8_t>(std::clamp(255.0 - 30.0 * (pt - c).norm(), 20.0, 255.0));
        out.push_back(p);
    }
    return out;
}

}  // namespace handscan::shm_demo
