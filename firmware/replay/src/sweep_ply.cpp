#include "handscan/replay/sweep_ply.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "handscan/export/point_formats.hpp"

namespace handscan::replay {

Status writeSweepPly(const std::string& path, const scan::Sweep& sweep) {
    std::vector<journal::MapPoint> points;
    points.reserve(sweep.points.size());
    for (const scan::SweepPoint& p : sweep.points) {
        journal::MapPoint m;
        m.t_s = toSeconds(p.t);
        m.x = static_cast<float>(p.p_start.x());
        m.y = static_cast<float>(p.p_start.y());
        m.z = static_cast<float>(p.p_start.z());
        // The Hokuyo's intensity is an integer count (0 .. 65535 in the ME/MD reply).
        m.intensity =
            static_cast<std::uint16_t>(std::clamp(std::round(p.intensity), 0.0f, 65535.0f));
        points.push_back(m);
    }
    exporter::SafeFileWriter file(path);
    if (Status s = file.open(); !s.isOk()) return s;
    auto writer = exporter::makePlyWriter(
        file, {"handscan sweep " + std::to_string(sweep.index),
               "frame: rig (tracking camera) frame at the sweep's first point, metres",
               "time: seconds of the scan clock (host CLOCK_MONOTONIC); first point at " +
                   std::to_string(toSeconds(sweep.t_start))});
    if (Status s = writer->begin(points.size()); !s.isOk()) return s;
    if (Status s = writer->write(points); !s.isOk()) return s;
    return writer->end();
}

}  // namespace handscan::replay
