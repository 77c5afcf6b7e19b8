#include "handscan/live_output/sweep_points.hpp"

#include <algorithm>

namespace handscan::live_output {

std::vector<journal::MapPoint> sweepMapPoints(const lio::RegisteredSweep& s,
                                              const colour::ColourResult* colours) {
    std::vector<journal::MapPoint> pts;
    pts.reserve(s.points_world.size());
    for (std::size_t i = 0; i < s.points_world.size(); ++i) {
        const auto& p = s.points_world[i];
        const auto intensity =
            static_cast<std::uint16_t>(std::clamp(s.intensities[i], 0.0f, 65535.0f));
        const std::uint8_t grey = journal::laserGrey(intensity);
        journal::MapPoint m{
            toSeconds(s.times[i]), p.x(), p.y(), p.z(), grey, grey, grey, intensity};
        if (colours && colours->valid(i)) {
            m.r = colours->rgb[i][0];
            m.g = colours->rgb[i][1];
            m.b = colours->rgb[i][2];
        }
        pts.push_back(m);
    }
    return pts;
}

journal::TrajectoryPose trajectoryPose(const PoseEstimate& p) {
    const Eigen::Vector3d t = p.T_world_body.translation();
    const Eigen::Quaterniond q(p.T_world_body.linear());
    return {toSeconds(p.t_host), t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()};
}

}  // namespace handscan::live_output
