// Real captures from other spinning / tilting 2D-laser scanners (../shared/data/laser3d, see each
// SOURCE.txt). Skipped when the shared data directory is absent.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

#include "handscan/scan/laser_odometry.hpp"
#include "handscan/scan/sweep_assembler.hpp"
#include "spin_sim.hpp"

namespace handscan::scan {
namespace {

using testing::poseError;
using testing::PoseError;
using testing::toWorld;

const std::string kData = std::string(HANDSCAN_SHARED_DATA_DIR) + "/laser3d";

// ---- 3DTK tilting scans: 226 profiles x 360 beams (0.5 deg), centimetres ----------------------

Sweep load3dtk(const std::string& path) {
    std::ifstream in(path);
    Sweep s;
    double x, y, z;
    std::size_t i = 0;
    while (in >> x >> y >> z) {
        if (i % 360 == 0) s.lines.push_back({s.points.size(), s.points.size(), 0.5 * M_PI / 180.0});
        SweepPoint p;
        p.p_start = Eigen::Vector3d(x, y, z) / 100.0;
        p.range_m = static_cast<float>(p.p_start.norm());
        p.step = static_cast<std::uint16_t>(i % 360);
        // The scanner reports ~0.1 m for no return; those are not surface points.
        if (p.range_m > 0.3) {
            s.points.push_back(p);
        }
        s.lines.back().end = s.points.size();
        ++i;
    }
    return s;
}

// scan00N.pose: "x y z" (cm) and "rx ry rz" (deg); 3DTK's rotation is Rx * Ry * Rz.
Eigen::Isometry3d load3dtkPose(const std::string& path) {
    std::ifstream in(path);
    double v[6];
    for (double& d : v) in >> d;
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    const double k = M_PI / 180.0;
    T.linear() = (Eigen::AngleAxisd(v[3] * k, Eigen::Vector3d::UnitX()) * Eigen::AngleAxisd(v[4] * k, Eigen::Vector3d::UnitY()) *
                  Eigen::AngleAxisd(v[5] * k, Eigen::Vector3d::UnitZ()))
                     .toRotationMatrix();
    T.translation() = Eigen::Vector3d(v[0], v[1], v[2]) / 100.0;
    return T;
}

// scan00N.frames: one column-major 4x4 (cm) + a tag per ICP step; the last line is the result.
Eigen::Isometry3d load3dtkFinalFrame(const std::string& path) {
    std::ifstream in(path);
    std::string line, last;
    while (std::getline(in, line)) {
        if (!line.empty()) last = line;
    }
    std::istringstream ss(last);
    Eigen::Matrix4d M;
    for (int c = 0; c < 4; ++c) {
        for (int r = 0; r < 4; ++r) ss >> M(r, c);
    }
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = M.topLeftCorner<3, 3>();
    T.translation() = M.topRightCorner<3, 1>() / 100.0;
    return T;
}


// Dense alignment of `cloud` (posed by T) against `map_cloud`: median point-to-plane distance to
// planar 8-point patches of the full-resolution reference scan.
double densePointToPlaneMedian(const std::vector<Eigen::Vector3d>& map_cloud, const std::vector<Eigen::Vector3d>& cloud,
                               const Eigen::Isometry3d& T) {
    VoxelMapConfig vc;
    vc.planar_leaf_m = 0.02;
    VoxelMap dense(vc);
    dense.recenter(Eigen::Vector3d::Zero());
    dense.insert(FeatureKind::kPlanar, map_cloud);
    const std::vector<Eigen::Vector3d> w = toWorld(T, cloud);
    const LocalMap local = dense.extract({}, w);
    std::vector<double> d;
    for (const auto& q : w) {
        Eigen::Vector3d nb[8];
        double d2[8];
        if (local.nearest(FeatureKind::kPlanar, q, 8, nb, d2) < 8 || d2[7] > 0.04) continue;
        Eigen::Vector3d c = Eigen::Vector3d::Zero();
        for (const auto& x : nb) c += x;
        c /= 8;
        Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
        for (const auto& x : nb) C += (x - c) * (x - c).transpose();
        const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(C);
        if (es.eigenvalues()[0] > 0.05 * es.eigenvalues()[1]) continue;
        d.push_back(std::abs(es.eigenvectors().col(0).dot(q - c)));
    }
    std::nth_element(d.begin(), d.begin() + static_cast<std::ptrdiff_t>(d.size() / 2), d.end());
    return d[d.size() / 2];
}

// scan001 against scan000 (the published registration of scan002 is against scan000 + scan001
// merged by slam6d, which this test does not reproduce).
TEST(Laser3dReal, Tilting3dtkScanPairFromOdometry) {
    const std::string dir = kData + "/tilting-3dtk";
    if (!std::filesystem::exists(dir + "/scan000.3d")) GTEST_SKIP() << dir << " is absent";
    const Sweep s0 = load3dtk(dir + "/scan000.3d");
    const Sweep s1 = load3dtk(dir + "/scan001.3d");
    ASSERT_EQ(s0.lines.size(), 226U);
    ASSERT_EQ(s1.lines.size(), 226U);
    const FeatureConfig fc;
    const FeatureCloud f0 = extractFeatures(s0, fc);
    const FeatureCloud f1 = extractFeatures(s1, fc);
    VoxelMap map;
    map.recenter(Eigen::Vector3d::Zero());
    map.insert(FeatureKind::kEdge, f0.edges);
    map.insert(FeatureKind::kPlanar, f0.planars);
    const Eigen::Isometry3d odom = load3dtkPose(dir + "/scan001.pose");
    const Eigen::Isometry3d published = load3dtkFinalFrame(dir + "/scan001.frames");
    // The odometry of these stop-and-go scans is centimetres and degrees off: a weak prior.
    PosePrior prior;
    prior.T_world_body = odom;
    prior.information.setZero();
    prior.information.diagonal() << 1, 1, 1, 0.01, 0.01, 0.01;
    ScanMatcherConfig mc;
    mc.max_associations = 20;
    mc.kernel_scale_m = 0.05;
    // The weakest direction (mostly vertical: the floor is barely in view) has an eigenvalue of
    // ~45 here (std ~4.5 mm at the default laser sigma): solvable under the default threshold.
    const auto t0 = std::chrono::steady_clock::now();
    const LocalMap local = map.extract(toWorld(odom, f1.edges), toWorld(odom, f1.planars));
    const MatchResult r = ScanMatcher(mc).match(f1, local, {prior});
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();

    std::vector<Eigen::Vector3d> ref;
    std::vector<Eigen::Vector3d> cloud;
    for (const auto& p : s0.points) ref.push_back(p.p_start);
    for (std::size_t i = 0; i < s1.points.size(); i += 5) cloud.push_back(s1.points[i].p_start);
    const double d_odom = densePointToPlaneMedian(ref, cloud, odom);
    const double d_pub = densePointToPlaneMedian(ref, cloud, published);
    const double d_ours = densePointToPlaneMedian(ref, cloud, r.T_world_body);
    const PoseError before = poseError(published, odom);
    const PoseError after = poseError(published, r.T_world_body);
    std::printf("3dtk scan001: odometry %.1f cm %.2f deg from the published registration -> matched %.1f cm %.2f deg "
                "(%zu/%zu features, %d/%d matches, mask 0x%02x, %.0f ms); dense point-to-plane median: odometry "
                "%.2f cm, published %.2f cm, ours %.2f cm; eigenvalues %s\n",
                before.trans_m * 100, before.rot_deg, after.trans_m * 100, after.rot_deg, f1.edges.size(),
                f1.planars.size(), r.edge_matches, r.plane_matches, r.degeneracy.solved_dof_mask, ms, d_odom * 100,
                d_pub * 100, d_ours * 100, (std::ostringstream() << r.degeneracy.eigenvalues.transpose()).str().c_str());
    // Measured: odometry 1.78 cm, published 0.97 cm, ours 0.83 cm. Our pose aligns the full
    // clouds better than the published one, yet lies ~5 cm / 3.7 deg (about x) from it: the
    // issue's "within a few cm and tenths of a degree of the published pose" is not met, and the
    // published .frames (from historical 3DTK commits, see SOURCE.txt) fit these points worse.
    EXPECT_LT(d_ours, 0.85 * d_odom);
    EXPECT_LT(d_ours, d_pub);
    EXPECT_LT(after.trans_m, 0.07);
    EXPECT_LT(after.rot_deg, 4.0);
    EXPECT_EQ(r.degeneracy.solved_dof_mask, kAllDof);
}

// ---- LongarmLiDAR: 41 scan lines of a motor-rotated URG-class laser on a 0.18 m arm ----------

TEST(Laser3dReal, RotatingLongarmBoardIsPlanar) {
    const std::string path = kData + "/rotating-longarm/batchScanned20191114103039.txt";
    if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is absent";
    std::ifstream in(path);
    std::string line;
    std::vector<std::vector<double>> rows;
    while (std::getline(in, line)) {
        std::vector<double> row;
        std::stringstream ss(line);
        std::string cell;
        while (std::getline(ss, cell, ',')) row.push_back(std::stod(cell));
        rows.push_back(row);
    }
    ASSERT_EQ(rows.size(), 42U);
    ASSERT_EQ(rows[0].size(), 685U);
    // That rig, from the upstream MATLAB (range2points.m): x = r sin(th) cos(ph) + R sin(ph),
    // y = -r sin(th) sin(ph) + R cos(ph), z = r cos(th), th = beam angle + Dtheta, ph = motor
    // angle. In our terms: the laser sits R along the shaft's y, its front beam along the shaft
    // axis z, its +beam side along x; the beam offset Dtheta is a yaw of the laser; the motor
    // angle turns the shaft by -ph about z.
    const double R = 0.18;
    const double dtheta = -2.6 * M_PI / 180.0;
    SpinGeometry g;
    Eigen::Matrix3d axes;
    axes.col(0) = Eigen::Vector3d::UnitZ();  // laser x (front beam) -> shaft z
    axes.col(1) = Eigen::Vector3d::UnitX();  // laser y -> shaft x
    axes.col(2) = Eigen::Vector3d::UnitY();
    g.T_shaft_laser.linear() = axes * Eigen::AngleAxisd(dtheta, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    g.T_shaft_laser.translation() = Eigen::Vector3d(0, R, 0);

    SweepAssemblerConfig cfg;
    cfg.boundary = SweepBoundary::kFullRevolution;
    cfg.min_range_m = 0.02;
    cfg.max_encoder_gap_ns = 2 * kNsPerSec;
    cfg.max_encoder_latency_ns = 10 * kNsPerSec;  // the whole file's encoder stream comes first
    SweepAssembler a(g, cfg, [](TimeNs) { return Eigen::Isometry3d::Identity(); });
    const double beam0 = rows[0][3] * M_PI / 180.0;
    const double inc = (rows[0][4] - rows[0][3]) * M_PI / 180.0;
    // The encoder: one sample per line at its timestamp (ms); the line itself is treated as
    // instantaneous (the 100 ms URG scan is short next to the motor's 0.07 deg per line).
    for (std::size_t i = 1; i < rows.size(); ++i) {
        EncoderSample e;
        e.t_host = static_cast<TimeNs>(rows[i][1]) * kNsPerMs;
        e.angle_rad = -rows[i][2] * M_PI / 180.0;
        ASSERT_TRUE(a.addEncoder(e).isOk());
    }
    for (std::size_t i = 1; i < rows.size(); ++i) {
        LaserScan s;
        s.t_host = static_cast<TimeNs>(rows[i][1]) * kNsPerMs;
        s.step_period_ns = 0;
        s.angle_min_rad = beam0;
        s.angle_increment_rad = inc;
        // The board: beams 292..428 (MATLAB, 1-based) as in main_calibratetheta2.m.
        s.first_step = 291;
        for (std::size_t b = 291; b < 428; ++b) {
            s.ranges_m.push_back(static_cast<float>(rows[i][3 + b]));
        }
        s.angle_min_rad = beam0 + 291 * inc;
        ASSERT_TRUE(a.addScan(s).isOk());
    }
    const Sweep sweep = a.flush();
    ASSERT_GT(sweep.points.size(), 41U * 100U);
    EXPECT_EQ(sweep.lines.size(), 41U);
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (const auto& p : sweep.points) c += p.p_start;
    c /= static_cast<double>(sweep.points.size());
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (const auto& p : sweep.points) cov += (p.p_start - c) * (p.p_start - c).transpose();
    cov /= static_cast<double>(sweep.points.size());
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
    const double rms = std::sqrt(es.eigenvalues()[0]);
    const Eigen::Vector3d n = es.eigenvectors().col(0);
    std::printf("longarm board: %zu points, plane rms %.2f mm, extent %.2f x %.2f m, normal (%.3f %.3f %.3f)\n",
                sweep.points.size(), rms * 1000, 2 * std::sqrt(es.eigenvalues()[2]) * 1.732,
                2 * std::sqrt(es.eigenvalues()[1]) * 1.732, n.x(), n.y(), n.z());
    // The URG-04LX's range noise is ~1 cm at 1 m; a wrong geometry bends the board by more.
    EXPECT_LT(rms, 0.012);
    // Upstream's own fit: the board is parallel to the sensor, i.e. its normal is the shaft z.
    EXPECT_GT(std::abs(n.z()), 0.99);
}

}  // namespace
}  // namespace handscan::scan
