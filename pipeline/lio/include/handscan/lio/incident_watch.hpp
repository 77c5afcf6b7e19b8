// IncidentWatch: failures the pipeline can see in its input streams before any scan match says
// something is wrong (issue 13: "the laser blinded for 5 s while walking, a 2 s IMU gap, a sudden
// drop of the scanner ... flagged within 1 s"). A match only judges a whole sweep, half a second
// after it started, and a blinded laser or a silent IMU gives no sweep to judge at all; these
// checks look at every scan and IMU sample instead:
//   laser blind  the laser's scans have (almost) no valid returns for `blind_after_s`: something
//                covers the window. A real scene always returns something within 30 m (floor,
//                walls; the open field's ground), so a scan with under 2 % valid steps is blind;
//   IMU silent   laser scans keep coming while no IMU sample has for `imu_silent_after_s`: the
//                prediction has nothing to carry it, and the sweeps cannot be placed;
//   free fall    the accelerometer's specific force under `free_fall_mps2` for
//                `free_fall_after_s`: in the hand it stays near g (walking moves it by a few
//                m/s^2, the aggressive motion of the paper's Figure 30 by less than g); falling,
//                it drops to zero. A 0.5 m fall lasts 0.32 s.
// Each incident is reported once, at the time it is seen; it is reported again only after the
// stream has been normal in between. Pure computation, in sample-time order.
#pragma once

#include <optional>
#include <string>

#include "handscan/core/samples.hpp"
#include "handscan/fusion/tracking_monitor.hpp"

namespace handscan::lio {

struct IncidentWatchConfig {
    bool enabled = true;
    double blind_valid_fraction = 0.02;
    double blind_after_s = 0.25;
    double imu_silent_after_s = 0.15;  // the MTi sends every 2.5-10 ms
    double free_fall_mps2 = 2.5;
    double free_fall_after_s = 0.12;
};

struct Incident {
    TimeNs t = 0;  // when it began (the first blind scan, the last IMU sample, the fall's start)
    TimeNs t_seen = 0;  // the sample time it was recognised at
    fusion::LostReason reason = fusion::LostReason::kNone;
    std::string detail;
};

class IncidentWatch {
public:
    explicit IncidentWatch(const IncidentWatchConfig& config = {}) : config_(config) {}

    std::optional<Incident> addImu(const ImuSample& s);
    std::optional<Incident> addScan(const LaserScan& scan);

private:
    IncidentWatchConfig config_;
    TimeNs last_imu_t_ = 0;
    bool imu_reported_ = false;
    TimeNs blind_since_ = -1;
    bool blind_reported_ = false;
    TimeNs falling_since_ = -1;
    bool fall_reported_ = false;
};

}  // namespace handscan::lio
