#include "handscan/fusion/tracking_monitor.hpp"

#include <gtest/gtest.h>

namespace handscan::fusion {
namespace {

constexpr TimeNs kSweep = 500 * kNsPerMs;  // half-revolution sweeps at 1 rev/s

// A walker at 1 m/s along x; the match lands `jump_m` from the prediction along y.
SweepEvidence walking(int k, double jump_m = 0.002, std::size_t matches = 800,
                      double rms_m = 0.01) {
    SweepEvidence e;
    e.t = 1000 * kNsPerMs + k * kSweep;
    e.T_world_prior.translation() = Eigen::Vector3d(0.5 * k, 0.0, 1.2);
    e.T_world_match = e.T_world_prior;
    e.T_world_match.translation().y() += jump_m;
    // The corrected prediction's 5 mm / 0.3 deg (LioConfig::imu_prior_sigma_*).
    e.prior_information.diagonal() << Eigen::Vector3d::Constant(4e4),
        Eigen::Vector3d::Constant(4e4);
    e.founds_map = k == 0;
    e.enough_matches = matches >= 20;
    e.features = 1000;
    e.matches = matches;
    e.rms_m = rms_m;
    return e;
}

TEST(TrackingMonitor, ConsistentWalkNeverLost) {
    TrackingMonitor m;
    for (int k = 0; k < 200; ++k) {
        const TrackingVerdict v = m.assess(walking(k, k % 2 ? 0.01 : -0.01));
        EXPECT_TRUE(v.consistent) << k << ": " << v.detail;
        EXPECT_TRUE(v.enters_map);
        EXPECT_FALSE(v.lost);
    }
    EXPECT_TRUE(m.intervals().empty());
    EXPECT_EQ(m.rejectedSweeps(), 0u);
}

TEST(TrackingMonitor, OneOutlierStaysOutOfTheMapWithoutLosingTracking) {
    TrackingMonitor m;
    for (int k = 0; k < 5; ++k) m.assess(walking(k));
    const TrackingVerdict v = m.assess(walking(5, 0.3));
    EXPECT_FALSE(v.consistent);
    EXPECT_FALSE(v.enters_map);
    EXPECT_TRUE(v.fits_map);  // the map is the reference: the prediction gets corrected
    EXPECT_FALSE(v.lost);
    EXPECT_EQ(v.reason, LostReason::kPredictionDisagrees);
    EXPECT_TRUE(m.assess(walking(6)).enters_map);
    EXPECT_TRUE(m.intervals().empty());
}

TEST(TrackingMonitor, FailingEveryOtherSweepIsLost) {
    // Never two in a row, but three of the last eight: the map has stopped agreeing.
    TrackingMonitor m;
    for (int k = 0; k < 4; ++k) m.assess(walking(k));
    EXPECT_FALSE(m.assess(walking(4, 0.3)).lost);
    EXPECT_FALSE(m.assess(walking(5)).lost);
    EXPECT_FALSE(m.assess(walking(6, 0.3)).lost);
    EXPECT_FALSE(m.assess(walking(7)).lost);
    const TrackingVerdict v = m.assess(walking(8, 0.3));
    EXPECT_TRUE(v.lost);
    ASSERT_EQ(m.intervals().size(), 1u);
    EXPECT_EQ(m.intervals()[0].t_begin, walking(8).t);
}

TEST(TrackingMonitor, OccasionalOutliersFartherApartAreNot) {
    TrackingMonitor m;
    for (int k = 0; k < 60; ++k) EXPECT_FALSE(m.assess(walking(k, k % 4 == 3 ? 0.3 : 0.002)).lost);
    EXPECT_TRUE(m.intervals().empty());
    EXPECT_EQ(m.rejectedSweeps(), 15u);
}

TEST(TrackingMonitor, BlindedLaserIsLostWithinOneSecondAndRecoversOnTheOldMap) {
    TrackingMonitor m;
    for (int k = 0; k < 10; ++k) m.assess(walking(k));
    // 5 s without correspondences (the laser blinded): lost at the second sweep (1 s).
    for (int k = 10; k < 20; ++k) {
        const TrackingVerdict v = m.assess(walking(k, 0.0, 5));
        EXPECT_FALSE(v.enters_map);
        EXPECT_FALSE(v.fits_map);
        EXPECT_EQ(v.lost, k >= 11) << k;
        EXPECT_EQ(v.reason, LostReason::kNoMatch);
    }
    // Back on the map: recover_after consistent sweeps, the last of which enters the map again.
    // The prediction ran 5 s unfed: a larger jump back to the map is allowed.
    EXPECT_FALSE(m.assess(walking(20, 0.25)).enters_map);
    EXPECT_FALSE(m.assess(walking(21)).enters_map);
    const TrackingVerdict back = m.assess(walking(22));
    EXPECT_FALSE(back.lost);
    EXPECT_TRUE(back.enters_map);
    ASSERT_EQ(m.intervals().size(), 1u);
    const LostInterval& i = m.intervals()[0];
    EXPECT_EQ(i.t_begin, walking(11).t);
    EXPECT_EQ(i.t_end, walking(22).t);
    EXPECT_EQ(i.reason, LostReason::kNoMatch);
    EXPECT_EQ(i.sweeps, 11u);  // sweeps 11..21 held out while lost
}

TEST(TrackingMonitor, EachCheckNamesItsReason) {
    struct Case {
        SweepEvidence e;
        LostReason reason;
    };
    const Case cases[] = {
        {walking(5, 0.0, 10), LostReason::kNoMatch},
        {walking(5, 0.0, 200), LostReason::kMapDisagrees},
        {walking(5, 0.0, 800, 0.08), LostReason::kPoorFit},
        {walking(5, 0.5), LostReason::kPredictionDisagrees},
    };
    for (const Case& c : cases) {
        TrackingMonitor m;
        for (int k = 0; k < 5; ++k) m.assess(walking(k));
        const TrackingVerdict v = m.assess(c.e);
        EXPECT_EQ(v.reason, c.reason) << lostReasonName(c.reason) << ": " << v.detail;
        EXPECT_FALSE(v.detail.empty());
        EXPECT_FALSE(v.lost);  // one inconsistent sweep is not yet a loss
    }
}

TEST(TrackingMonitor, PredictionJumpsAlongUnsolvedDirectionsAreAllowed) {
    TrackingMonitor m;
    for (int k = 0; k < 5; ++k) m.assess(walking(k));
    // A corridor's axis (y here) left unsolved: the prediction there is the walker's 20 cm guess.
    SweepEvidence e = walking(5, 0.3);
    e.prior_information(4, 4) = 1.0 / (0.2 * 0.2);
    EXPECT_TRUE(m.assess(e).consistent);
    SweepEvidence solved = walking(6, 0.3);
    EXPECT_EQ(m.assess(solved).reason, LostReason::kPredictionDisagrees);
}

TEST(TrackingMonitor, ImpossibleMotionIsLostAtOnce) {
    TrackingMonitor m;
    for (int k = 0; k < 5; ++k) m.assess(walking(k));
    // Prior and match agree, but the pair jumped 5 m in half a second (10 m/s).
    SweepEvidence e = walking(5);
    e.T_world_prior.translation().x() += 5.0;
    e.T_world_match = e.T_world_prior;
    const TrackingVerdict v = m.assess(e);
    EXPECT_TRUE(v.lost);
    EXPECT_FALSE(v.fits_map);
    EXPECT_EQ(v.reason, LostReason::kImplausibleMotion);
    EXPECT_NE(v.detail.find("speed"), std::string::npos) << v.detail;
}

TEST(TrackingMonitor, TurnRateBeyondAHandHeldDevice) {
    TrackingMonitor m;
    for (int k = 0; k < 5; ++k) m.assess(walking(k));
    SweepEvidence e = walking(5);
    e.T_world_prior.linear() = Eigen::AngleAxisd(M_PI * 0.9, Eigen::Vector3d::UnitZ()).matrix();
    e.T_world_match = e.T_world_prior;  // 162 deg in 0.5 s: 324 deg/s is fine ...
    EXPECT_TRUE(m.assess(e).consistent);
    TrackingMonitor fast(TrackingMonitorConfig{.max_rate_radps = 3.0});
    for (int k = 0; k < 5; ++k) fast.assess(walking(k));
    EXPECT_EQ(fast.assess(e).reason, LostReason::kImplausibleMotion);  // ... above 172 deg/s not
}

TEST(TrackingMonitor, AnImuGapIsLostAtOnceAndRecoversOnlyAfterARelocalisation) {
    TrackingMonitor m;
    for (int k = 0; k < 5; ++k) m.assess(walking(k));
    const TimeNs t_fall = walking(5).t - 100 * kNsPerMs;
    const TrackingVerdict v =
        m.fail(t_fall, t_fall + 150 * kNsPerMs, LostReason::kImuSilent, "no IMU", true);
    EXPECT_TRUE(v.lost);
    EXPECT_FALSE(v.enters_map);
    EXPECT_TRUE(m.lost());
    ASSERT_EQ(m.intervals().size(), 1u);
    EXPECT_EQ(m.intervals()[0].t_begin, t_fall);
    EXPECT_EQ(m.intervals()[0].reason, LostReason::kImuSilent);
    EXPECT_EQ(m.intervals()[0].t_flagged, t_fall + 150 * kNsPerMs);
    // A second report while lost opens no second interval.
    EXPECT_TRUE(
        m.fail(t_fall + kSweep, t_fall + kSweep, LostReason::kLaserBlind, "blind", false).lost);
    EXPECT_EQ(m.intervals().size(), 1u);
    // Consistent matches from an unknown pose prove nothing: no recovery until the relocaliser
    // has found the old map.
    EXPECT_TRUE(m.awaitingRelocalisation());
    // The lost sweeps' own map (the odometry tracking them meanwhile) is founded: still lost,
    // nothing of it enters the scan's map.
    SweepEvidence founding = walking(5);
    founding.founds_map = true;
    const TrackingVerdict f = m.assess(founding);
    EXPECT_TRUE(f.lost);
    EXPECT_FALSE(f.enters_map);
    EXPECT_FALSE(f.consistent);
    EXPECT_EQ(f.reason, LostReason::kImuSilent);
    for (int k = 5; k < 9; ++k) {
        const TrackingVerdict r = m.assess(walking(k));
        EXPECT_TRUE(r.consistent) << k << ": " << r.detail;
        EXPECT_FALSE(r.enters_map);
        EXPECT_TRUE(r.lost);
    }
    m.relocalised(walking(9).t - kSweep / 2, "relocalised 3.00 m away");
    EXPECT_FALSE(m.awaitingRelocalisation());
    // The scanner was found 3 m away: no implausible motion across the jump, and three
    // consistent sweeps against the old map recover.
    for (int k = 9; k < 12; ++k) {
        SweepEvidence e = walking(k);
        e.T_world_prior.translation().y() += 3.0;
        e.T_world_match.translation().y() += 3.0;
        const TrackingVerdict r = m.assess(e);
        EXPECT_TRUE(r.consistent) << k << ": " << r.detail;
        EXPECT_TRUE(r.fits_map);
        EXPECT_EQ(r.enters_map, k == 11) << k;
    }
    EXPECT_FALSE(m.lost());
    EXPECT_EQ(m.intervals()[0].t_end, walking(11).t);
    EXPECT_NE(m.intervals()[0].detail.find("relocalised 3.00 m"), std::string::npos);
    EXPECT_STREQ(lostReasonName(LostReason::kDropped), "dropped");
    EXPECT_STREQ(lostReasonName(LostReason::kLaserBlind), "laser_blind");
    EXPECT_STREQ(lostReasonName(LostReason::kImuSilent), "imu_silent");
}

TEST(TrackingMonitor, ALossTheMatchesDoNotRecoverWaitsForARelocalisation) {
    TrackingMonitor m;
    for (int k = 0; k < 5; ++k) m.assess(walking(k));
    // The prediction 0.6 m off the map's answer, sweep after sweep (drifted beyond the
    // matcher's reach): lost after trip_after, and after relocalise_after sweeps with
    // correspondences the pose is taken as unknown.
    const int give_up = m.config().relocalise_after;
    for (int k = 5; k < 5 + m.config().trip_after + give_up; ++k) {
        const TrackingVerdict v = m.assess(walking(k, 0.6));
        EXPECT_FALSE(v.consistent);
        EXPECT_FALSE(v.enters_map);
    }
    EXPECT_TRUE(m.lost());
    EXPECT_TRUE(m.awaitingRelocalisation());
    EXPECT_NE(m.intervals()[0].detail.find("relocalising"), std::string::npos)
        << m.intervals()[0].detail;
    // Consistent sweeps now prove nothing until the relocaliser found the map.
    int k = 5 + m.config().trip_after + give_up;
    for (int i = 0; i < 4; ++i, ++k) EXPECT_FALSE(m.assess(walking(k)).enters_map);
    EXPECT_TRUE(m.lost());
    m.relocalised(walking(k).t - kSweep / 2, "relocalised 0.60 m away");
    for (int i = 0; i < m.config().recover_after; ++i, ++k) m.assess(walking(k));
    EXPECT_FALSE(m.lost());
    EXPECT_FALSE(m.awaitingRelocalisation());
}

TEST(TrackingMonitor, ARecoveryUnderWayIsNotCutShortByTheGivingUp) {
    TrackingMonitor m;
    for (int k = 0; k < 5; ++k) m.assess(walking(k));
    // Failed sweeps one short of giving up, then the matches come back: they recover.
    const int failed = m.config().trip_after - 1 + m.config().relocalise_after - 1;
    int k = 5;
    for (int i = 0; i < failed; ++i, ++k) EXPECT_FALSE(m.assess(walking(k, 0.6)).consistent);
    ASSERT_TRUE(m.lost());
    for (int i = 0; i < m.config().recover_after; ++i, ++k) m.assess(walking(k));
    EXPECT_FALSE(m.awaitingRelocalisation());
    EXPECT_FALSE(m.lost());
}

TEST(TrackingMonitor, SweepsWithoutCorrespondencesDoNotGiveUpTheMatches) {
    TrackingMonitorConfig c;
    c.relocalise_after = 2;
    TrackingMonitor m(c);
    for (int k = 0; k < 5; ++k) m.assess(walking(k));
    for (int k = 5; k < 15; ++k) m.assess(walking(k, 0.0, 5));  // nothing seen: nothing tried
    EXPECT_TRUE(m.lost());
    EXPECT_FALSE(m.awaitingRelocalisation());
}

TEST(TrackingMonitor, AFallIsLostAtOnceAndRecoversAsAnyLoss) {
    TrackingMonitor m;
    for (int k = 0; k < 5; ++k) m.assess(walking(k));
    EXPECT_TRUE(
        m.fail(walking(5).t - kSweep / 4, walking(5).t, LostReason::kDropped, "free fall", false)
            .lost);
    EXPECT_FALSE(m.awaitingRelocalisation());
    // Lying 1.2 m lower on the floor a sweep later: no implausible motion across the fall.
    for (int k = 5; k < 8; ++k) {
        SweepEvidence e = walking(k);
        e.T_world_prior.translation().z() -= 1.2;
        e.T_world_match.translation().z() -= 1.2;
        const TrackingVerdict r = m.assess(e);
        EXPECT_TRUE(r.consistent) << k << ": " << r.detail;
        EXPECT_EQ(r.enters_map, k == 7) << k;
    }
    EXPECT_FALSE(m.lost());
    EXPECT_EQ(m.intervals().at(0).reason, LostReason::kDropped);
}

TEST(TrackingMonitor, DisabledAcceptsEverything) {
    TrackingMonitor m(TrackingMonitorConfig{.enabled = false});
    for (int k = 0; k < 10; ++k) {
        const TrackingVerdict v = m.assess(walking(k, 1.0, 0));
        EXPECT_TRUE(v.enters_map);
        EXPECT_FALSE(v.lost);
    }
}

}  // namespace
}  // namespace handscan::fusion
