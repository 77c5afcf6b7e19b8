// The simulator's incidents (tools/sim incidents.hpp) against the pipeline's detectors
// (lio::IncidentWatch): a dropped scanner falls onto its side, lies on the floor and resumes the
// walk where it fell; its IMU reads free fall at once, while no walk, however aggressive, ever
// does (the detector's threshold checked against the simulator's exact specific force).
#include "handscan/sim/incidents.hpp"

#include <gtest/gtest.h>

#include <numbers>

#include "handscan/lio/incident_watch.hpp"
#include "handscan/sim/scenes.hpp"

namespace handscan::sim {
namespace {

const Eigen::Vector3d kGravity(0.0, 0.0, -9.81);

// What the MTi reads at t (noise-free): the specific force and the rate in the body frame.
ImuSample reading(const Trajectory& tr, double t) {
    const BodyState s = tr.at(t);
    ImuSample m;
    m.t_host = fromSeconds(10.0 + t);
    m.accel_mps2_imu = s.T_world_body.linear().transpose() * (s.a_world - kGravity);
    m.gyro_radps_imu = s.omega_body;
    return m;
}

// The first free-fall incident IncidentWatch reports on `tr` sampled at 400 Hz (seconds, <0: none).
double firstFreeFall(const Trajectory& tr, double t0, double t1) {
    lio::IncidentWatch watch;
    for (double t = t0; t < t1; t += 0.0025) {
        if (auto i = watch.addImu(reading(tr, t)); i && i->reason == fusion::LostReason::kDropped)
            return toSeconds(i->t_seen) - 10.0;
    }
    return -1.0;
}

WalkPlan walk(MotionStyle style, std::uint64_t seed, double duration = 40.0) {
    WalkOptions o;
    o.duration_s = duration;
    o.style = style;
    o.seed = seed;
    return makeWalk(buildScene("house").walk_loop, o);
}

TEST(Incidents, DropFallsOntoItsSideLiesStillAndResumesTheWalk) {
    const Trajectory w = walk(MotionStyle::kWalk, 3).trajectory;
    const double t_drop = 12.0, floor_z = 0.0;
    const Trajectory d = withDrop(w, t_drop, floor_z, 1.5, 1.5);
    EXPECT_DOUBLE_EQ(d.duration(), w.duration());
    // Before the drop: the same walk.
    for (double t = 0.5; t < t_drop - 0.1; t += 0.7)
        EXPECT_LT((d.at(t).T_world_body.translation() - w.at(t).T_world_body.translation()).norm(),
                  1e-9);
    // On the floor: 0.1 m up, turned about 90 degrees, still.
    const double h = w.at(t_drop).T_world_body.translation().z() - 0.1;
    const double t_fall = std::sqrt(2.0 * h / 9.81);
    const BodyState lying = d.at(t_drop + t_fall + 0.8);
    EXPECT_NEAR(lying.T_world_body.translation().z(), floor_z + 0.1, 0.02);
    EXPECT_LT(lying.v_world.norm(), 1e-6);
    const double turned = Eigen::AngleAxisd(w.at(t_drop).T_world_body.linear().transpose() *
                                            lying.T_world_body.linear())
                              .angle();
    EXPECT_NEAR(turned * 180.0 / std::numbers::pi, 90.0, 5.0);
    // Falling: the specific force near zero; the impact a few g, within the MTi's 200 m/s^2.
    const ImuSample mid_fall = reading(d, t_drop + 0.5 * t_fall);
    EXPECT_LT(mid_fall.accel_mps2_imu.norm(), 1.0);
    double impact = 0.0;
    for (double t = t_drop; t < t_drop + t_fall + 0.3; t += 0.001)
        impact = std::max(impact, reading(d, t).accel_mps2_imu.norm());
    EXPECT_GT(impact, 30.0);
    EXPECT_LT(impact, 200.0);
    // Back in the hand: the walk carries on from where it fell, late by the incident.
    const double late =
        static_cast<double>(d.controlPoints().size() - w.controlPoints().size()) * w.knotSpacing();
    EXPECT_NEAR(late, t_fall + 3.0, 3 * w.knotSpacing());  // whole knots
    for (double t = t_drop + late + 0.2; t < w.duration() - 1.0; t += 1.3)
        EXPECT_LT(
            (d.at(t).T_world_body.translation() - w.at(t - late).T_world_body.translation()).norm(),
            1e-9)
            << t;
}

TEST(Incidents, FreeFallIsSeenWithinAFifthOfASecondAndNeverWhileWalking) {
    for (std::uint64_t seed : {4, 5}) {
        const Trajectory w = walk(MotionStyle::kWalk, seed).trajectory;
        EXPECT_LT(firstFreeFall(w, 0.0, w.duration()), 0.0) << "walk seed " << seed;
        const Trajectory d = withDrop(w, 20.0, 0.0, 1.5, 1.5);
        const double seen = firstFreeFall(d, 0.0, d.duration());
        EXPECT_GT(seen, 20.0) << seed;
        EXPECT_LT(seen, 20.2) << seed;
    }
    // The paper's aggressive motion (370 deg/s) swings the device hard but never lets it fall.
    for (std::uint64_t seed : {4, 5}) {
        const Trajectory a = walk(MotionStyle::kAggressive, seed, 60.0).trajectory;
        EXPECT_LT(firstFreeFall(a, 0.0, a.duration()), 0.0) << "aggressive seed " << seed;
    }
}

}  // namespace
}  // namespace handscan::sim
