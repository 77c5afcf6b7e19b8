// IncidentWatch: a covered laser and a silent IMU are seen from the streams themselves, within a
// fraction of a second, once per incident; a laser that sees a little (a narrow corridor, the
// sky above an open field) is not blind.
#include "handscan/lio/incident_watch.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace handscan::lio {
namespace {

constexpr TimeNs kScanPeriod = 25 * kNsPerSec / 1000;

LaserScan scan(TimeNs t, double valid_fraction) {
    LaserScan s;
    s.t_host = t;
    s.ranges_m.assign(1081, std::nanf(""));
    const auto valid = static_cast<std::size_t>(valid_fraction * 1081.0);
    for (std::size_t i = 0; i < valid; ++i) s.ranges_m[i] = 3.0f;
    return s;
}

ImuSample imu(TimeNs t) {
    ImuSample m;
    m.t_host = t;
    m.accel_mps2_imu = Eigen::Vector3d(0.3, -0.2, 9.7);
    return m;
}

TEST(IncidentWatch, ACoveredLaserIsBlindAfterAQuarterSecondOnce) {
    IncidentWatch w;
    TimeNs t = kNsPerSec;
    for (int k = 0; k < 40; ++k, t += kScanPeriod) {
        (void)w.addImu(imu(t));
        EXPECT_FALSE(w.addScan(scan(t, 0.05)));  // a little seen: not blind
    }
    const TimeNs covered = t;
    std::optional<Incident> seen;
    int reports = 0;
    for (int k = 0; k < 80; ++k, t += kScanPeriod) {
        (void)w.addImu(imu(t));
        if (auto i = w.addScan(scan(t, 0.0))) {
            ++reports;
            if (!seen) seen = i;
        }
    }
    ASSERT_TRUE(seen);
    EXPECT_EQ(reports, 1);
    EXPECT_EQ(seen->reason, fusion::LostReason::kLaserBlind);
    EXPECT_EQ(seen->t, covered);
    EXPECT_NEAR(toSeconds(seen->t_seen - covered), 0.25, 0.03);
    // Uncovered, then covered again: a second incident.
    (void)w.addScan(scan(t, 0.8));
    t += kScanPeriod;
    int again = 0;
    for (int k = 0; k < 20; ++k, t += kScanPeriod) {
        (void)w.addImu(imu(t));
        again += w.addScan(scan(t, 0.0)).has_value();
    }
    EXPECT_EQ(again, 1);
}

TEST(IncidentWatch, AnImuSilentWhileTheLaserRunsIsSeenOnce) {
    IncidentWatch w;
    TimeNs t = kNsPerSec;
    for (int k = 0; k < 40; ++k, t += kScanPeriod) {
        (void)w.addImu(imu(t));
        EXPECT_FALSE(w.addScan(scan(t, 0.9)));
    }
    const TimeNs last_imu = t - kScanPeriod;
    std::optional<Incident> seen;
    int reports = 0;
    for (int k = 0; k < 80; ++k, t += kScanPeriod) {  // 2 s without the IMU
        if (auto i = w.addScan(scan(t, 0.9))) {
            ++reports;
            seen = i;
        }
    }
    ASSERT_TRUE(seen);
    EXPECT_EQ(reports, 1);
    EXPECT_EQ(seen->reason, fusion::LostReason::kImuSilent);
    EXPECT_EQ(seen->t, last_imu);
    EXPECT_LT(toSeconds(seen->t_seen - last_imu), 0.2);
    EXPECT_GT(toSeconds(seen->t_seen - last_imu), 0.15);
    // Back, then silent again: a second incident.
    (void)w.addImu(imu(t));
    int again = 0;
    for (int k = 0; k < 20; ++k) again += w.addScan(scan(t += kScanPeriod, 0.9)).has_value();
    EXPECT_EQ(again, 1);
}

TEST(IncidentWatch, DisabledSeesNothing) {
    IncidentWatchConfig c;
    c.enabled = false;
    IncidentWatch w(c);
    TimeNs t = kNsPerSec;
    (void)w.addImu(imu(t));
    for (int k = 0; k < 80; ++k) EXPECT_FALSE(w.addScan(scan(t += kScanPeriod, 0.0)));
}

}  // namespace
}  // namespace handscan::lio
