// The localizer of section 9 on a synthetic room: the lock from a hint 1 m and 15 deg off, no
// lock where the prior map has nothing to match, a lock confirmed by two searches, headings
// searched about the hint's place, new ground left out of the score, a moved object that neither
// breaks the lock nor goes unreported, odometry drift corrected at each match; the sweep stack and
// the prior map's voxels.
#include "handscan/localize/localizer.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <memory>
#include <thread>

#include "handscan/core/se3.hpp"
#include "synthetic_room.hpp"

namespace handscan::localize {
namespace {

using test::pose;

constexpr TimeNs kHalfSecond = kNsPerSec / 2;

// The matches run on the localizer's thread; the tests apply each at the next sweep (or settle()).
LocalizerConfig atNextSweep() {
    LocalizerConfig c;
    c.apply = MatchApply::kAtNextSweep;
    return c;
}

// The earlier session: the room as seen from three places (its laser centres kept).
const std::vector<Eigen::Vector3d> kPriorViewpoints = {
    {2.5, 2.0, 1.3}, {7.5, 2.0, 1.3}, {3.5, 5.5, 1.3}};

std::shared_ptr<const PriorMap> roomPrior(
    const std::vector<Eigen::Vector3d>& viewpoints = kPriorViewpoints) {
    return std::make_shared<PriorMap>(
        test::roomWorld(0.2, 0.0, Eigen::Vector3d::Zero(), viewpoints), pose(5, 3.5, 1.3, 0));
}

double angleDeg(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
    return rotationAngle(a.linear(), b.linear()) * 180.0 / M_PI;
}

// Feeds `n` sweeps half a second apart seen at T_true, the odometry saying T_odom; returns
// whether the estimate changed at any of them.
bool feed(Localizer& l, int n, TimeNs& t, const Eigen::Isometry3d& T_true,
          const Eigen::Isometry3d& T_odom, const Eigen::Vector3d& moved = Eigen::Vector3d::Zero()) {
    const auto f = std::make_shared<const scan::FeatureCloud>(test::sweepAt(T_true, moved));
    bool changed = false;
    for (int i = 0; i < n; ++i, t += kHalfSecond) changed = l.addSweep(t, T_odom, f) || changed;
    return changed;
}

TEST(LocalizerTest, LocksFromAHintOneMetreAndFifteenDegreesOff) {
    const Eigen::Isometry3d truth = pose(3.2, 2.4, 1.3, 40);
    const Eigen::Isometry3d hint = pose(3.2 + 0.8, 2.4 + 0.6, 1.3, 55);
    Localizer l(atNextSweep(), roomPrior(), hint);
    TimeNs t = 1000 * kNsPerSec;
    // The odometry's own world: the session started at its origin.
    const Eigen::Isometry3d odom = Eigen::Isometry3d::Identity();
    EXPECT_FALSE(feed(l, 4, t, truth, odom));  // no match before a full stack (2 s)
    EXPECT_FALSE(l.locked());
    EXPECT_FALSE(feed(l, 1, t, truth, odom));  // the search starts on its thread
    EXPECT_TRUE(l.matchRunning());
    EXPECT_EQ(l.lockState(), LockState::kSearching);
    EXPECT_FALSE(l.locked());
    EXPECT_TRUE(feed(l, 1, t, truth, odom));  // and takes effect at the next sweep
    ASSERT_TRUE(l.locked());
    EXPECT_EQ(l.lockState(), LockState::kLocked);
    const Eigen::Isometry3d est = l.priorFromOdom() * odom;
    EXPECT_LT((est.translation() - truth.translation()).norm(), 0.01);
    EXPECT_LT(angleDeg(est, truth), 0.2);
    EXPECT_GT(l.stats().lock_on_map, 0.9);
    EXPECT_EQ(l.stats().lock_attempts, 1u);
    EXPECT_TRUE(l.changes().empty());
}

TEST(LocalizerTest, NoLockWhereThePriorMapHasNothingNearTheHint) {
    // The hint 12 m outside the room: nothing within the search radius matches.
    Localizer l(atNextSweep(), roomPrior(), pose(-12, 3.5, 1.3, 0));
    TimeNs t = 1000 * kNsPerSec;
    feed(l, 9, t, pose(3.2, 2.4, 1.3, 40), Eigen::Isometry3d::Identity());
    EXPECT_FALSE(l.settle());
    EXPECT_EQ(l.stats().lock_attempts, 2u);
    EXPECT_FALSE(l.locked());
    EXPECT_EQ(l.lockState(), LockState::kNotLocked);
    EXPECT_LT(l.stats().lock_on_map, 0.6);
}

TEST(LocalizerTest, PlacedAgainWhereTheOperatorStandsNowItLocks) {
    // The first hint 12 m outside the room: no lock. Then the operator, having walked 1 m on
    // (the odometry says so), taps roughly where they stand now.
    const Eigen::Isometry3d truth = pose(3.2, 2.4, 1.3, 40);
    Localizer l(atNextSweep(), roomPrior(), pose(-12, 3.5, 1.3, 0));
    TimeNs t = 1000 * kNsPerSec;
    feed(l, 9, t, truth, Eigen::Isometry3d::Identity());
    EXPECT_FALSE(l.settle());
    ASSERT_EQ(l.lockState(), LockState::kNotLocked);
    const Eigen::Isometry3d walked = pose(1.0, 0.0, 0.0, 0.0);
    const Eigen::Isometry3d now = truth * walked;
    EXPECT_TRUE(l.placeAt(pose(now.translation().x() + 0.8, now.translation().y() - 0.6, 1.3, 50)));
    feed(l, 5, t, now, walked);
    EXPECT_TRUE(l.settle());
    ASSERT_TRUE(l.locked());
    const Eigen::Isometry3d est = l.priorFromOdom() * walked;
    EXPECT_LT((est.translation() - now.translation()).norm(), 0.01);
    EXPECT_LT(angleDeg(est, now), 0.2);
    EXPECT_FALSE(l.placeAt(pose(0, 0, 1.3, 0)));  // locked: a tap changes nothing
}

// Whether `c` lies within a cell of the box (its centre at most half a cell outside it).
bool nearBox(const ChangeCell& c, const test::Box& b, double cell = 0.5) {
    return (c.centre.array() >= b.lo.array() - cell).all() &&
           (c.centre.array() <= b.hi.array() + cell).all();
}

TEST(LocalizerTest, AMovedObjectKeepsTheLockAndIsReportedWhereItNowStandsAndWhereItStood) {
    const Eigen::Vector3d moved(-0.6, -0.5, 0.0);  // the cabinet, 0.78 m
    const test::Box before = test::furniture()[2], after = test::furnitureMoved(moved)[2];
    const Eigen::Isometry3d truth = pose(6.5, 3.0, 1.3, -20);
    Localizer l(atNextSweep(), roomPrior(), pose(7.3, 3.6, 1.3, -5));
    TimeNs t = 1000 * kNsPerSec;
    feed(l, 5, t, truth, Eigen::Isometry3d::Identity(), moved);
    EXPECT_TRUE(l.settle());
    ASSERT_TRUE(l.locked());
    for (const ChangeCell& c : l.changes())  // one view of an appearance is not yet a change
        EXPECT_NE(c.kind, ChangeKind::kAppeared) << c.centre.transpose();
    // Walked on to the east, where the cabinet's old place shows past its new one: a tracking
    // match sees both.
    const Eigen::Isometry3d east = pose(9.4, 3.5, 1.3, 60);
    feed(l, 4, t, east, truth.inverse() * east, moved);
    EXPECT_TRUE(l.settle());
    const Eigen::Isometry3d est = l.priorFromOdom();
    EXPECT_LT((est.translation() - truth.translation()).norm(), 0.01);
    EXPECT_LT(angleDeg(est, truth), 0.2);
    int appeared = 0, vanished = 0;
    for (const ChangeCell& c : l.changes()) {
        // The cabinet's new place (appeared) and its old one (vanished), nothing elsewhere.
        if (c.kind == ChangeKind::kAppeared) {
            ++appeared;
            EXPECT_TRUE(nearBox(c, after)) << "appeared at " << c.centre.transpose();
        } else {
            ++vanished;
            EXPECT_TRUE(nearBox(c, before)) << "vanished at " << c.centre.transpose();
        }
    }
    EXPECT_GT(appeared, 0);
    EXPECT_GT(vanished, 0);
}

TEST(LocalizerTest, SurfacesTheEarlierSessionNeverLookedAtAreNoChange) {
    // The earlier session stood only at the room's west end: the far sides of the crate and the
    // cabinet, and whatever they hid, it never saw. This session, in the unchanged room, sees
    // them from the east: new ground, close to the prior's points, but no change.
    const std::vector<Eigen::Vector3d> west = {{1.5, 2.0, 1.3}, {1.5, 3.5, 1.3}};
    const Eigen::Isometry3d truth = pose(8.5, 2.0, 1.3, 160);
    Localizer l(atNextSweep(), roomPrior(west), pose(8.0, 2.6, 1.3, 150));
    TimeNs t = 1000 * kNsPerSec;
    feed(l, 5, t, truth, Eigen::Isometry3d::Identity());
    EXPECT_TRUE(l.settle());
    ASSERT_TRUE(l.locked());
    for (int i = 0; i < 3; ++i) {
        feed(l, 4, t, truth, Eigen::Isometry3d::Identity());
        EXPECT_TRUE(l.settle());
    }
    EXPECT_GT(l.stats().new_points, 10u);  // it did see what the earlier session did not
    for (const ChangeCell& c : l.changes())
        ADD_FAILURE() << (c.kind == ChangeKind::kAppeared ? "appeared" : "vanished") << " at "
                      << c.centre.transpose() << " (" << c.points << " points)";
}

TEST(LocalizerTest, EachMatchTakesOutTheOdometrysDrift) {
    const Eigen::Isometry3d start = pose(3.2, 2.4, 1.3, 40);
    Localizer l(atNextSweep(), roomPrior(), start);
    TimeNs t = 1000 * kNsPerSec;
    feed(l, 5, t, start, Eigen::Isometry3d::Identity());
    EXPECT_TRUE(l.settle());
    ASSERT_TRUE(l.locked());
    // Walking 2 m along x; the odometry drifted 2 cm and 0.3 deg by then.
    const Eigen::Isometry3d truth = pose(5.2, 2.4, 1.3, 40);
    const Eigen::Isometry3d odom = start.inverse() * truth * pose(0.02, -0.01, 0.0, 0.3);
    feed(l, 4, t, truth, odom);
    EXPECT_TRUE(l.settle());
    EXPECT_EQ(l.stats().updates, 1u);
    const Eigen::Isometry3d est = l.priorFromOdom() * odom;
    EXPECT_LT((est.translation() - truth.translation()).norm(), 0.005);
    // (0.07 deg left of the 0.3: the sweeps hide what the furniture hides, fewer planes to
    // pin the heading than the room's every surface)
    EXPECT_LT(angleDeg(est, truth), 0.1);
    EXPECT_GT(l.stats().max_correction_m, 0.015);
}

TEST(LocalizerTest, AppliedWhenReadyTheLockDoesNotHoldUpTheSweeps) {
    const Eigen::Isometry3d truth = pose(3.2, 2.4, 1.3, 40);
    LocalizerConfig c;  // kWhenReady, as on the device
    Localizer l(c, roomPrior(), pose(3.2 + 0.8, 2.4 + 0.6, 1.3, 55));
    TimeNs t = 1000 * kNsPerSec;
    feed(l, 5, t, truth, Eigen::Isometry3d::Identity());
    ASSERT_TRUE(l.matchRunning());
    // Sweeps go on while it runs (no second match starts); it takes effect once done. The
    // search takes ~0.5 s here, several under ASan on a loaded machine (6.7 s seen): up to 60 s.
    for (int i = 0; i < 3000 && !l.locked(); ++i) {
        feed(l, 1, t, truth, Eigen::Isometry3d::Identity());
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    ASSERT_TRUE(l.locked());
    EXPECT_EQ(l.stats().lock_attempts, 1u);
    EXPECT_GT(l.stats().max_apply_delay_s, 0.0);
    EXPECT_LT((l.priorFromOdom().translation() - truth.translation()).norm(), 0.01);
}

// The localizer's thread against the worker's (run under ThreadSanitizer by tools/test): a small
// search, so that the lock and a tracking match run while sweeps keep coming, each applied when
// ready; then a localizer destroyed with a match still running (cancelled and waited for).
TEST(LocalizerThreadTest, MatchesRunBesideTheSweepsAndEndWithTheLocalizer) {
    LocalizerConfig c;  // kWhenReady, as on the device
    c.search_radius_m = 0.5;
    c.search_yaw_deg = 10.0;
    c.search_points = 100;
    c.refine_candidates = 1;
    c.period_s = 0.5;
    const Eigen::Isometry3d truth = pose(3.2, 2.4, 1.3, 40);
    const auto prior = roomPrior();
    {
        Localizer l(c, prior, pose(3.4, 2.5, 1.3, 45));
        TimeNs t = 1000 * kNsPerSec;
        for (int i = 0; i < 3000 && l.stats().updates < 1; ++i) {
            feed(l, 1, t, truth, Eigen::Isometry3d::Identity());
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
        }
        ASSERT_TRUE(l.locked());
        EXPECT_GE(l.stats().updates, 1u);
        EXPECT_LT((l.priorFromOdom().translation() - truth.translation()).norm(), 0.01);
        EXPECT_TRUE(l.changes().empty());  // nothing moved
    }
    Localizer running(c, prior, pose(3.4, 2.5, 1.3, 45));
    TimeNs t = 1000 * kNsPerSec;
    feed(running, 3, t, truth, Eigen::Isometry3d::Identity());
    EXPECT_TRUE(running.matchRunning());  // and it goes out of scope so
}

TEST(LocalizerTest, AHintGivesPositionAndHeadingTheOdometryKeepsItsTilt) {
    // The body tilted 10 deg about its x axis and heading 30 deg in the odometry's world; a level
    // hint (the operator's tap) heading 100 deg at (4, 2, 1.3).
    Eigen::Isometry3d odom = pose(0.5, -0.2, 1.1, 30);
    odom.linear() = odom.linear() * Eigen::AngleAxisd(0.1745, Eigen::Vector3d::UnitX());
    const Eigen::Isometry3d T = priorFromOdomAtHint(pose(4, 2, 1.3, 100), odom);
    // Only a turn about the vertical between the worlds, of 70 deg.
    EXPECT_NEAR(T.linear()(2, 2), 1.0, 1e-12);
    EXPECT_NEAR(Eigen::AngleAxisd(T.linear()).angle() * 180.0 / M_PI, 70.0, 1e-9);
    const Eigen::Isometry3d body = T * odom;
    EXPECT_TRUE(body.translation().isApprox(Eigen::Vector3d(4, 2, 1.3), 1e-12));
    const Eigen::Vector3d x = body.linear().col(0);
    EXPECT_NEAR(std::atan2(x.y(), x.x()) * 180.0 / M_PI, 100.0, 1e-9);
    EXPECT_NEAR(body.linear().col(2).z(), odom.linear().col(2).z(), 1e-12);  // tilt kept
}

// Confirmation (LocalizerConfig::confirm_margin): a place no single search wins by
// lock_margin locks when the next search, on another stack, puts the odometry's world there too.
TEST(LocalizerTest, TwoSearchesAgreeingOnThePlaceLock) {
    const Eigen::Isometry3d truth = pose(3.2, 2.4, 1.3, 40);
    LocalizerConfig c = atNextSweep();
    c.lock_margin = 2.0;  // no search locks on its own
    {
        Localizer alone(c, roomPrior(), pose(4.0, 3.0, 1.3, 55));
        TimeNs t = 1000 * kNsPerSec;
        feed(alone, 9, t, truth, Eigen::Isometry3d::Identity());
        alone.settle();
        EXPECT_EQ(alone.stats().lock_attempts, 2u);
        EXPECT_FALSE(alone.locked());  // confirmation off
    }
    c.confirm_margin = 0.05;
    Localizer l(c, roomPrior(), pose(4.0, 3.0, 1.3, 55));
    TimeNs t = 1000 * kNsPerSec;
    feed(l, 5, t, truth, Eigen::Isometry3d::Identity());
    EXPECT_FALSE(l.settle());  // the first search alone
    EXPECT_FALSE(l.locked());
    feed(l, 4, t, truth, Eigen::Isometry3d::Identity());
    EXPECT_TRUE(l.settle());  // the second agrees
    ASSERT_TRUE(l.locked());
    EXPECT_EQ(l.stats().lock_attempts, 2u);
    EXPECT_LT((l.priorFromOdom().translation() - truth.translation()).norm(), 0.01);
    EXPECT_LT(angleDeg(l.priorFromOdom(), truth), 0.2);
}

TEST(LocalizerTest, TwoSearchesPuttingTheOdometryInDifferentPlacesDoNotLock) {
    // The odometry says it stood still, but the second stack was seen 2 m away: the searches
    // place the odometry's world 2 m apart; neither is confirmed.
    LocalizerConfig c = atNextSweep();
    c.lock_margin = 2.0;
    c.confirm_margin = 0.05;
    Localizer l(c, roomPrior(), pose(4.0, 3.0, 1.3, 40));
    TimeNs t = 1000 * kNsPerSec;
    feed(l, 5, t, pose(3.2, 2.4, 1.3, 40), Eigen::Isometry3d::Identity());
    EXPECT_FALSE(l.settle());
    feed(l, 4, t, pose(5.2, 2.4, 1.3, 40), Eigen::Isometry3d::Identity());
    EXPECT_FALSE(l.settle());
    EXPECT_EQ(l.stats().lock_attempts, 2u);
    EXPECT_FALSE(l.locked());
}

// Every lock confirmed (confirm_always, confirm_margin = lock_margin): a search that wins clearly
// on its own does not lock until the next one agrees, and meanwhile the localizer says it is
// searching (not "not locked": the screen would send the operator back to the start); two that
// place the odometry's world apart never lock.
TEST(LocalizerTest, ConfirmedLocksWaitForTheNextSearchAndSaySearchingMeanwhile) {
    LocalizerConfig c = atNextSweep();
    c.confirm_margin = c.lock_margin;
    c.confirm_always = true;
    const Eigen::Isometry3d truth = pose(3.2, 2.4, 1.3, 40);
    {
        Localizer l(c, roomPrior(), pose(4.0, 3.0, 1.3, 55));
        TimeNs t = 1000 * kNsPerSec;
        feed(l, 5, t, truth, Eigen::Isometry3d::Identity());
        EXPECT_FALSE(l.settle());  // on the map, clearly best: alone it would lock
        EXPECT_GT(l.stats().lock_on_map - l.stats().lock_runner_up, c.lock_margin);
        EXPECT_FALSE(l.locked());
        EXPECT_EQ(l.lockState(), LockState::kSearching);  // found, not yet confirmed
        feed(l, 4, t, truth, Eigen::Isometry3d::Identity());
        EXPECT_TRUE(l.settle());
        ASSERT_TRUE(l.locked());
        EXPECT_EQ(l.stats().lock_attempts, 2u);
        EXPECT_LT((l.priorFromOdom().translation() - truth.translation()).norm(), 0.01);
    }
    Localizer l(c, roomPrior(), pose(4.0, 3.0, 1.3, 40));
    TimeNs t = 1000 * kNsPerSec;
    feed(l, 5, t, truth, Eigen::Isometry3d::Identity());
    EXPECT_FALSE(l.settle());
    feed(l, 4, t, pose(5.2, 2.4, 1.3, 40), Eigen::Isometry3d::Identity());  // seen 2 m away
    EXPECT_FALSE(l.settle());
    EXPECT_FALSE(l.locked());
}

// search_turns_about_first: the hint's heading 50 deg off at the first sweep, the operator 6 m
// on since; turned about the newest sweep the candidates miss it by 5 m, about the first sweep's
// place they reach it.
TEST(LocalizerTest, AHeadingLostAtTheFirstSweepIsSearchedAboutItsPlace) {
    const Eigen::Isometry3d first = pose(2.0, 3.5, 1.3, 0);
    const Eigen::Isometry3d now = pose(8.0, 3.5, 1.3, 0);
    const Eigen::Isometry3d odom_now = first.inverse() * now;  // the odometry started at `first`
    const Eigen::Isometry3d hint = pose(2.3, 3.3, 1.3, 50);
    for (const bool about_first : {false, true}) {
        LocalizerConfig c = atNextSweep();
        c.search_radius_m = 1.5;
        c.search_yaw_deg = 60.0;
        c.search_turns_about_first = about_first;
        Localizer l(c, roomPrior(), hint);
        TimeNs t = 1000 * kNsPerSec;
        feed(l, 1, t, first, Eigen::Isometry3d::Identity());
        feed(l, 4, t, now, odom_now);
        l.settle();
        EXPECT_EQ(l.stats().lock_attempts, 1u);
        ASSERT_EQ(l.locked(), about_first);
        if (!about_first) continue;
        const Eigen::Isometry3d est = l.priorFromOdom() * odom_now;
        EXPECT_LT((est.translation() - now.translation()).norm(), 0.01);
        EXPECT_LT(angleDeg(est, now), 0.2);
    }
}

// score_min_covered: half of the stack new ground (a room the prior map never saw) halves the
// share on the map; scored where the map reaches it is whole again, and a pose putting the stack
// beside the map scores nothing.
TEST(PriorMatchTest, ScoredWhereThePriorMapReachesNewGroundDoesNotCount) {
    const auto prior = roomPrior();
    const Eigen::Isometry3d truth = pose(3.2, 2.4, 1.3, 40);
    const std::vector<Eigen::Vector3d> seen = samplePoints(test::sweepAt(truth), 300);
    std::vector<Eigen::Vector3d> pts = seen;
    for (const Eigen::Vector3d& p : seen)  // as much again, 30 m beyond the room
        pts.push_back(p + truth.linear().transpose() * Eigen::Vector3d(30.0, 0.0, 0.0));
    LocalizerConfig c;
    EXPECT_NEAR(shareOnMap(c, *prior, pts, truth), 0.5, 0.05);
    c.score_min_covered = 0.3;
    EXPECT_GT(shareOnMap(c, *prior, pts, truth), 0.9);
    EXPECT_LT(shareOnMap(c, *prior, pts, pose(40.0, 2.4, 1.3, 40)), 0.01);
    // Few points covered (a sixth here, under 30 %) are scored against 30 % of them all.
    const std::size_t n_seen = seen.size() / 5;
    std::vector<Eigen::Vector3d> mostly_new(seen.begin(), seen.begin() + n_seen);
    mostly_new.insert(mostly_new.end(), pts.begin() + seen.size(), pts.end());
    EXPECT_LT(shareOnMap(c, *prior, mostly_new, truth),
              static_cast<double>(n_seen) / (0.3 * mostly_new.size()) + 1e-9);
    EXPECT_GT(shareOnMap(c, *prior, mostly_new, truth),
              0.9 * static_cast<double>(n_seen) / (0.3 * mostly_new.size()));
}

TEST(SweepStackTest, StacksIntoTheNewestSweepsFrameThinnedAndWithinItsSpan) {
    SweepStack stack({.span_s = 2.0, .edge_leaf_m = 0.1, .planar_leaf_m = 0.2});
    auto cloud = [](const Eigen::Vector3d& p) {
        auto c = std::make_shared<scan::FeatureCloud>();
        c->planars = {p, p + Eigen::Vector3d(0.01, 0, 0)};  // the second shares the leaf
        c->planar_origins = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
        c->edges = {p};
        return c;
    };
    const TimeNs t0 = 100 * kNsPerSec;
    stack.add(t0, pose(0, 0, 0, 0), cloud({5.05, 0.05, 0.05}));
    stack.add(t0 + kNsPerSec, pose(1, 0, 0, 90), cloud({0.05, 5.05, 0.05}));
    const scan::FeatureCloud s = stack.stack();
    ASSERT_EQ(s.planars.size(), 2u);
    ASSERT_EQ(s.planar_origins.size(), 2u);
    // The newest first, as it is; the older one's point (world 5.05,0.05) in the newest frame
    // (at 1,0,0 turned 90 deg): x' = y, y' = -(x - 1). Leaves are not cut by the points.
    EXPECT_TRUE(s.planars[0].isApprox(Eigen::Vector3d(0.05, 5.05, 0.05)));
    EXPECT_TRUE(s.planars[1].isApprox(Eigen::Vector3d(0.05, -4.05, 0.05), 1e-9));
    EXPECT_TRUE(s.planar_origins[1].isApprox(Eigen::Vector3d(0, 1, 0), 1e-9));
    stack.add(t0 + 3 * kNsPerSec + kHalfSecond, pose(0, 0, 0, 0), cloud({1, 1, 1}));
    EXPECT_EQ(stack.size(), 1u);  // the others are more than 2 s older
}

TEST(PriorMapTest, QueriesSeeNeighboursAcrossACoarseVoxelsFace) {
    scan::FeatureMapPoints m;
    m.planars = {{9.95f, 1.0f, 1.0f}};
    m.planar_origins = {Eigen::Vector3f::Zero()};
    m.edges = {{-5.0f, 1.0f, 1.0f}};
    const PriorMap prior(m, Eigen::Isometry3d::Identity());
    EXPECT_NEAR(prior.nearestDistance({10.05, 1.0, 1.0}), 0.1, 1e-5);  // the next voxel over
    EXPECT_NEAR(prior.nearestDistance({-5.0, 1.5, 1.0}), 0.5, 1e-5);
    EXPECT_TRUE(std::isinf(prior.nearestDistance({40.0, 40.0, 40.0})));
    EXPECT_EQ(prior.size(), 2u);
}

}  // namespace
}  // namespace handscan::localize

namespace handscan::localize {
namespace {

TEST(SeenSpaceTest, ARayClaimsTheSpaceItWentThroughInItsDirectionShortOfItsReturn) {
    SeenSpace seen(Eigen::AlignedBox3d(Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(9, 9, 9)));
    std::vector<SeenSpace::Crossing> cells;
    seen.cellsAlong({0.05, 0.05, 0.05}, {5.05, 0.05, 0.05}, cells);
    seen.add(cells);
    const Eigen::Vector3d facing_it(-1, 0, 0);  // a surface the ray would go into
    EXPECT_TRUE(seen.seenThrough({2.0, 0.05, 0.05}, facing_it));
    EXPECT_TRUE(seen.seenThrough({4.6, 0.05, 0.05}, facing_it));
    EXPECT_FALSE(seen.seenThrough({4.85, 0.05, 0.05}, facing_it));  // within 0.3 m of its return
    EXPECT_FALSE(seen.seenThrough({2.0, 0.05, 0.05}, {0, 1, 0}));   // it only skims that one
    EXPECT_FALSE(seen.seenThrough({2.0, 0.05, 0.05}, {1, 0, 0}));   // seen from its back
    EXPECT_FALSE(seen.seenThrough({2.0, 0.35, 0.05}, facing_it));   // a cell over
    EXPECT_TRUE(seen.crossed({2.0, 0.05, 0.05}));
    EXPECT_FALSE(seen.crossed({20.0, 0.05, 0.05}));  // outside the box
    EXPECT_FALSE(seen.crossed({1e30, 0.05, 0.05}));  // far outside: no int overflow
    EXPECT_FALSE(seen.crossed({std::nan(""), 0.05, 0.05}));
}

}  // namespace
}  // namespace handscan::localize
