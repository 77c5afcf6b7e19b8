// A registered, colourised map point at full resolution, as journaled and exported.
#pragma once

#include <cstdint>

namespace handscan::journal {

struct MapPoint {
    double t_s = 0.0;           // capture time, seconds of the scan clock (host monotonic / 1e9)
    float x = 0, y = 0, z = 0;  // metres, world frame of the scan (gravity aligned)
    std::uint8_t r = 0, g = 0, b = 0;
    std::uint16_t intensity = 0;
};

// Whether the colour camera saw the point: an uncoloured point keeps RGB 0,0,0.
inline bool hasColour(const MapPoint& p) { return (p.r | p.g | p.b) != 0; }

// A trajectory sample of the rig's body frame in the scan's world frame.
struct TrajectoryPose {
    double t_s = 0.0;
    double x = 0, y = 0, z = 0;
    double qx = 0, qy = 0, qz = 0, qw = 1;
};

}  // namespace handscan::journal
