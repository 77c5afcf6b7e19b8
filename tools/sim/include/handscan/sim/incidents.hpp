// Incidents: one failure in the middle of a walk, each an option of `handscan sim` (issue 13:
// "the laser blinded for 5 s while walking, a 2 s IMU gap, a sudden drop of the scanner"), so the
// pipeline's own failure handling can be measured against ground truth:
//   blind laser  something over the laser's window (a hand, a jacket): every beam comes back as
//                the sensor's too-near error code; the scanner keeps moving;
//   IMU gap      the MTi's serial link silent (a loose connector): no Xbus frames, while the
//                device's own packet counter and clock run on;
//   drop         the scanner slips out of the hand: it falls to the floor turning onto its side,
//                lies there, is picked up and carried on from where it fell (the walk resumes,
//                delayed by the incident).
#pragma once

#include "handscan/sim/trajectory.hpp"

namespace handscan::sim {

struct IncidentOptions {
    double blind_laser_at_s = -1.0;  // < 0: none
    double blind_laser_for_s = 5.0;
    double imu_gap_at_s = -1.0;
    double imu_gap_for_s = 2.0;
    double drop_at_s = -1.0;
    double drop_lie_s = 1.5;     // on the floor before the operator reaches it
    double drop_pickup_s = 1.5;  // from the floor back into the hand

    bool laserBlind(double t) const {
        return blind_laser_at_s >= 0.0 && t >= blind_laser_at_s &&
               t < blind_laser_at_s + blind_laser_for_s;
    }
    bool imuSilent(double t) const {
        return imu_gap_at_s >= 0.0 && t >= imu_gap_at_s && t < imu_gap_at_s + imu_gap_for_s;
    }
    bool any() const { return blind_laser_at_s >= 0.0 || imu_gap_at_s >= 0.0 || drop_at_s >= 0.0; }
};

// `walk` with a drop spliced in at `t_drop`: free fall from the hand to `floor_z` + 0.1 m
// (the device's half height) while rolling 90 degrees onto its side (its forward speed carries
// on), `lie_s` still on the floor, then `pickup_s` back up to the pose it fell from, after which
// the walk carries on, late by the incident's length. The recording keeps `walk`'s duration.
// The spline smooths the impact over a few knots (a few g, as on a carpeted floor), so the IMU
// and the ground truth still agree exactly.
Trajectory withDrop(const Trajectory& walk, double t_drop, double floor_z, double lie_s,
                    double pickup_s);

}  // namespace handscan::sim
