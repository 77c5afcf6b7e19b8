// A registered, colourised map point at full resolution, as journaled and exported.
#pragma once

#include <cstdint>

namespace handscan::journal {

struct MapPoint {
    double t_s = 0.0;           // capture time, seconds of the scan clock (host monotonic / 1e9)
    float x = 0, y = 0, z = 0;  // metres, world frame of the scan (gravity aligned)
    std::uint8_t r = 0, g = 0, b = 0;
    std::uint16_t intensity = 0;
    // Which scan session the point comes from (handscan merge; 0 in a single scan). Not
    // journaled: a journal is one session.
    std::uint16_t session = 0;
};

// The grey a point the colour camera did not see is journaled, shown and exported in: its laser
// return's intensity (live_output::sweepMapPoints), so an uncoloured cloud still shows surfaces.
inline std::uint8_t laserGrey(std::uint16_t intensity) {
    return static_cast<std::uint8_t>(intensity / 16 < 255 ? intensity / 16 : 255);
}

// Whether the colour camera saw the point: the others carry exactly their laser grey. A camera
// colour that happens to equal that grey in all three channels counts as unseen (on a grey
// surface about one point in 256; nowhere else).
inline bool hasColour(const MapPoint& p) {
    return !(p.r == p.g && p.g == p.b && p.r == laserGrey(p.intensity));
}

// A trajectory sample of the rig's body frame in the scan's world frame.
struct TrajectoryPose {
    double t_s = 0.0;
    double x = 0, y = 0, z = 0;
    double qx = 0, qy = 0, qz = 0, qw = 1;
};

}  // namespace handscan::journal
