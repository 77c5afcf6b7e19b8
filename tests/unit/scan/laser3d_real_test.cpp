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
#include <unordered_set>

#include "handscan/scan/laser_odometry.hpp"
#include "handscan/scan/sweep_assembler.hpp"
#include "point_icp.hpp"
#include "spin_sim.hpp"

namespace handscan::scan {
namespace {

using testing::poseError;
using testing::PoseError;
using testing::toWorld;

const std::string kData = std::string(HANDSCAN_SHARED_DATA_DIR) + "/laser3d";

// ---- 3DTK tilting scans: 226 profiles x 360 beams (0.5 deg), centimetres ----------------------

// The SICK scanner reports 32.767 m (0x7FFF mm) for "no echo"; such points lie on a sphere around
// the sensor, not on a surface. It reports ~0.1 m for other failures.
constexpr double kNoEchoRangeM = 32.7;

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
        if (p.range_m > 0.3 && p.range_m < kNoEchoRangeM) {
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
    T.linear() = (Eigen::AngleAxisd(v[3] * k, Eigen::Vector3d::UnitX()) *
                  Eigen::AngleAxisd(v[4] * k, Eigen::Vector3d::UnitY()) *
                  Eigen::AngleAxisd(v[5] * k, Eigen::Vector3d::UnitZ()))
                     .toRotationMatrix();
    T.translation() = Eigen::Vector3d(v[0], v[1], v[2]) / 100.0;
    return T;
}

// One .frames line: a column-major 4x4 (cm) and an algorithm tag.
Eigen::Isometry3d parse3dtkFrame(const std::string& line) {
    std::istringstream ss(line);
    Eigen::Matrix4d M;
    for (int c = 0; c < 4; ++c) {
        for (int r = 0; r < 4; ++r) ss >> M(r, c);
    }
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = M.topLeftCorner<3, 3>();
    T.translation() = M.topRightCorner<3, 1>() / 100.0;
    return T;
}

// scan00N.frames: one matrix per ICP step; the last line is the result.
Eigen::Isometry3d load3dtkFinalFrame(const std::string& path) {
    std::ifstream in(path);
    std::string line, last;
    while (std::getline(in, line)) {
        if (!line.empty()) last = line;
    }
    return parse3dtkFrame(last);
}

// 3DTK published four versions of dat/*.frames in 2009 before deleting them (27cdbeb3). They
// disagree by up to 4 deg. The last one (595b8e1d = svn r66, 2009-09-30; its lines below) is
// slam6D run with its defaults: point-to-point ICP on every point, pairs within 25 cm, scan002
// against the metascan of scan000 + scan001 (Tilting3dtkPublishedPosesAreSlam6dIcp reproduces
// it to 0.1 deg; 0.00 deg offline with every point). Its scan001 pose is that ICP's converged
// minimum. Its scan002 pose is NOT a registration: slam6D writes a frame after the first iteration
// and on convergence only, and its scan002 ICP did not converge in 50 iterations, so the last line
// is the pose after one iteration from the odometry (its 50-iteration pose lies 0.8 deg and 3.6 cm
// further on). The shared .frames (d24c9ed6) is the README's "slam6D --max=500 -r 10.2 -i 20":
// points within 5 m, 10 cm octree cells; it lands 3 deg lower in pitch (reproduced offline to 0.02
// deg / 0.1 cm with the ICP of point_icp.hpp on octree-cell centres, returns under 0.3 m dropped).
const char* const kPublished595b8e1d[3] = {
    "1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1 2",
    "0.999913 -0.00438033 0.0124237 0 0.00421739 0.999905 0.0131114 0 -0.0124799 -0.0130579 "
    "0.999837 0 "
    "-3.6331 -9.08315 156.796 1 2",
    "0.999981 -0.00239338 0.0057155 0 0.00235041 0.999969 0.00751323 0 -0.0057333 -0.00749966 "
    "0.999955 0 "
    "-8.05008 -15.6539 337.786 1 1",
};

// Dense alignment of `cloud` (posed by T) against `map_cloud`: median point-to-plane distance to
// planar 8-point patches of the full-resolution reference scan.
double densePointToPlaneMedian(const std::vector<Eigen::Vector3d>& map_cloud,
                               const std::vector<Eigen::Vector3d>& cloud,
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

// Registers `scan`'s features against `map` with the matcher's default configuration, starting
// from the odometry pose. The odometry of these stop-and-go scans is centimetres and a degree
// off and comes with no covariance: it is a weak prior.
MatchResult register3dtk(const FeatureCloud& scan, const VoxelMap& map,
                         const Eigen::Isometry3d& odom) {
    PosePrior prior;
    prior.T_world_body = odom;
    prior.information.setZero();
    prior.information.diagonal() << 1, 1, 1, 0.01, 0.01, 0.01;
    const LocalMap local = map.extract(toWorld(odom, scan.edges), toWorld(odom, scan.planars));
    return ScanMatcher().match(scan, local, {prior});
}

void insertScan(VoxelMap& map, const FeatureCloud& f, const Eigen::Isometry3d& T) {
    std::vector<Eigen::Vector3d> origins(f.planar_origins.size());
    for (std::size_t i = 0; i < origins.size(); ++i) origins[i] = T * f.planar_origins[i];
    map.insert(FeatureKind::kEdge, toWorld(T, f.edges));
    map.insert(FeatureKind::kPlanar, toWorld(T, f.planars), origins);
}

struct Case3dtk {
    const char* name;
    std::vector<int> map_scans;  // placed at their published poses (scan000 is the identity)
    int scan;
    double max_trans_m;  // measured (see below) plus a margin
    double max_rot_deg;
};

// slam6d registered scan001 against scan000 and scan002 against both (its metascan); the pair
// scan001 -> scan002 is checked on its own too. Each starts from the odometry and is compared
// with the published poses (kPublished595b8e1d): for scan001 slam6D's converged point-to-point
// minimum, for scan002 its pose after one ICP iteration (see above), i.e. near the odometry.
//
// Why scan001 lands 1.1 deg from the published pose (measured offline with PointIcp and a dense
// point-to-plane ICP on the same points): not the start (12 starts 1 deg / 5 cm around the
// odometry, and the published pose itself, all converge to the same pose within 0.03 deg), not a
// bug of the matcher, but the objective. The scans are not rigid copies of one scene: this scanner
// pitches its 2D laser about x (each profile is a half-plane through the x axis), and the surfaces
// disagree in that direction - point-to-plane ICP on the walls alone lands 1.3 deg from the
// published pose, mostly pitch. Which pitch wins then depends on how the objective weighs the
// points, and the minima of reasonable objectives spread over two degrees, mostly in pitch (x):
// dense point-to-point is the published pose (0.07 deg from it with every 3rd scan point), dense
// point-to-plane 0.38 deg from it, point-to-plane and point-to-point at constant density (one point
// per 5, 10, 20 cm, as the paper's maps keep them) 0.9-1.3 deg from it (pitch +0.9 to +1.2 deg),
// walls only 1.3 deg the other way (pitch -1.2 deg). Ours: 1.08 deg (pitch +0.6, roll -0.9 deg),
// 0.6-0.9 deg from the constant-density minima. Raw density weighs the floor next to the robot
// most (points fall off with 1/r^2). Across that range the costs change by a few percent: at
// raw density the published pose costs 2-6% less than ours (point-to-plane truncated at 5 cm:
// 12.40 vs 13.03 cm^2), at constant density (10 cm cells) 0-2% less (18.58 vs 18.76 cm^2;
// point-to-point within 25 cm 202.7 vs 202.8 cm^2), while there the point-to-point minimum,
// 1.16 deg from the published pose, costs 4% less than it (194.0 cm^2). Tenths of a degree
// from the published scan001 would take slam6D's raw-density weighting instead of the paper's
// constant density (6.3); our features are not the minimum of a dense objective either (their
// roll comes from which points the extractor picks: the dense point-to-plane ICP with our
// planar features as the scan lands at roll -0.8 deg like ours), and none of 22 variants of
// the matcher's and extractor's settings (map leaves, cluster sizes, kernel, eigenvalue and
// thickness tests, edge/planar thresholds, incidence, regions, range limit) came closer than
// 0.8 deg (map leaves of 10 cm planar / 5 cm edge: 0.80 deg, and 0.0-0.3 deg nearer the dense
// minima in all three cases; denser maps resemble the dense objectives more, at the cost of
// map size and matching time, and are no nearer the truth, which these data do not have).
//
// Measured with the default matcher (edge clusters of 4), from the published pose (odometry in
// brackets): scan001 2.6 cm 1.08 deg (1.7 cm 0.71 deg), scan001 -> scan002 3.2 cm 0.20 deg
// (0.7 cm 0.08 deg), scan002 against the metascan 3.5 cm 0.45 deg (0.4 cm 0.78 deg); all six
// directions solved. With edge clusters of 5: 3.0 cm 1.50 deg, 4.3 cm 0.30 deg, 4.1 cm 0.45 deg.
// The centimetres left on scan002 are along the corridor (z), its weakest direction.
TEST(Laser3dReal, Tilting3dtkScansFromOdometry) {
    const std::string dir = kData + "/tilting-3dtk";
    if (!std::filesystem::exists(dir + "/scan000.3d")) GTEST_SKIP() << dir << " is absent";
    std::vector<Sweep> sweeps;
    std::vector<FeatureCloud> features;
    std::vector<Eigen::Isometry3d> odom, published, shared_file;
    for (int i = 0; i < 3; ++i) {
        const std::string stem = dir + "/scan00" + std::to_string(i);
        sweeps.push_back(load3dtk(stem + ".3d"));
        ASSERT_EQ(sweeps.back().lines.size(), 226U) << stem;
        features.push_back(extractFeatures(sweeps.back(), FeatureConfig{}));
        odom.push_back(load3dtkPose(stem + ".pose"));
        published.push_back(parse3dtkFrame(kPublished595b8e1d[i]));
        shared_file.push_back(load3dtkFinalFrame(stem + ".frames"));
    }
    const Case3dtk cases[] = {
        {"scan000 -> scan001", {0}, 1, 0.035, 1.3},
        {"scan001 -> scan002", {1}, 2, 0.04, 0.4},
        {"scan000+001 -> scan002", {0, 1}, 2, 0.04, 0.7},
    };
    for (const Case3dtk& c : cases) {
        // The first map scan is the world frame of the case.
        const Eigen::Isometry3d world = published[c.map_scans.front()].inverse();
        VoxelMap map;
        map.recenter(Eigen::Vector3d::Zero());
        std::vector<Eigen::Vector3d> ref;
        for (int m : c.map_scans) {
            insertScan(map, features[m], world * published[m]);
            for (const auto& p : sweeps[m].points) ref.push_back(world * published[m] * p.p_start);
        }
        const int a = c.map_scans.front();
        const Eigen::Isometry3d odom_rel = odom[a].inverse() * odom[c.scan];
        const Eigen::Isometry3d pub_rel = world * published[c.scan];
        const Eigen::Isometry3d file_rel = shared_file[a].inverse() * shared_file[c.scan];
        const auto t0 = std::chrono::steady_clock::now();
        const MatchResult r = register3dtk(features[c.scan], map, odom_rel);
        const double ms =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                .count();

        std::vector<Eigen::Vector3d> cloud;
        for (std::size_t k = 0; k < sweeps[c.scan].points.size(); k += 5)
            cloud.push_back(sweeps[c.scan].points[k].p_start);
        const double d_odom = densePointToPlaneMedian(ref, cloud, odom_rel);
        const double d_pub = densePointToPlaneMedian(ref, cloud, pub_rel);
        const double d_ours = densePointToPlaneMedian(ref, cloud, r.T_world_body);
        const PoseError before = poseError(pub_rel, odom_rel);
        const PoseError after = poseError(pub_rel, r.T_world_body);
        const PoseError vs_file = poseError(file_rel, r.T_world_body);
        std::printf(
            "3dtk %s: odometry %.1f cm %.2f deg from the published registration -> matched %.1f cm "
            "%.2f deg "
            "(%.1f cm %.2f deg from the shared .frames; %zu/%zu features, %d/%d matches, mask "
            "0x%02x, %.0f ms); "
            "dense point-to-plane median: odometry %.2f cm, published %.2f cm, ours %.2f cm; "
            "eigenvalues %s\n",
            c.name, before.trans_m * 100, before.rot_deg, after.trans_m * 100, after.rot_deg,
            vs_file.trans_m * 100, vs_file.rot_deg, features[c.scan].edges.size(),
            features[c.scan].planars.size(), r.edge_matches, r.plane_matches,
            r.degeneracy.solved_dof_mask, ms, d_odom * 100, d_pub * 100, d_ours * 100,
            (std::ostringstream() << r.degeneracy.eigenvalues.transpose()).str().c_str());
        EXPECT_EQ(r.degeneracy.solved_dof_mask, kAllDof) << c.name;
        EXPECT_LT(after.trans_m, c.max_trans_m) << c.name;
        EXPECT_LT(after.rot_deg, c.max_rot_deg) << c.name;
        // Our pose fits the full-resolution points about as well as the published one (measured
        // 0.91, 1.17 and 1.24 times its median; the median is a coarse check of a gross slip only).
        EXPECT_LT(d_ours, 1.4 * d_pub) << c.name;
    }
}

// What the published poses are: slam6D's defaults (every point, pairs within 25 cm, closed-form
// point-to-point steps, stop when the mean squared pair distance changes by < 1e-5 cm^2 twice)
// registered scan001 against scan000 from the odometry and scan002 against the metascan from
// the odometry extrapolated by scan001's correction. Redone here (with every 3rd scan point, for
// speed), scan001 converges onto the published pose, and scan002's FIRST iteration lands on
// the published scan002 while 50 iterations (slam6D's -i default) go on to a pose ~0.8 deg
// away: the published scan002 is one ICP step from the odometry, not a registration. (Offline,
// with every point and the no-echo and near returns kept as slam6D kept them, scan001 meets the
// epsilon after 43 iterations 0.00 deg / 0.01 cm from the published pose, and scan002 does not
// in 50; with every 3rd point here neither meets it, and 50 steps end 0.07 deg from it.)
TEST(Laser3dReal, Tilting3dtkPublishedPosesAreSlam6dIcp) {
    const std::string dir = kData + "/tilting-3dtk";
    if (!std::filesystem::exists(dir + "/scan000.3d")) GTEST_SKIP() << dir << " is absent";
    std::vector<std::vector<Eigen::Vector3d>> pts(3);
    std::vector<Eigen::Isometry3d> odom, published;
    for (int i = 0; i < 3; ++i) {
        const std::string stem = dir + "/scan00" + std::to_string(i);
        for (const SweepPoint& p : load3dtk(stem + ".3d").points) pts[i].push_back(p.p_start);
        odom.push_back(load3dtkPose(stem + ".pose"));
        published.push_back(parse3dtkFrame(kPublished595b8e1d[i]));
    }
    const auto every3rd = [](const std::vector<Eigen::Vector3d>& v) {
        std::vector<Eigen::Vector3d> out;
        for (std::size_t k = 0; k < v.size(); k += 3) out.push_back(v[k]);
        return out;
    };
    constexpr double kMaxPair = 0.25;  // slam6D -d 25 (cm)
    constexpr double kEps = 1e-9;      // --epsICP 1e-5 cm^2
    const testing::PointIcp icp0(pts[0]);
    const auto r1 = icp0.align(every3rd(pts[1]), odom[0].inverse() * odom[1], kMaxPair, 50, kEps);
    std::vector<Eigen::Vector3d> meta = pts[0];
    for (const auto& p : pts[1]) meta.push_back(r1.T * p);
    const testing::PointIcp icp01(meta);
    const Eigen::Isometry3d start2 = r1.T * odom[1].inverse() * odom[2];
    const auto r2 = icp01.align(every3rd(pts[2]), start2, kMaxPair, 50, kEps);
    ASSERT_FALSE(r2.steps.empty());
    const PoseError e1 = poseError(published[1], r1.T);
    const PoseError e2_first = poseError(published[2], r2.steps.front());
    const PoseError e2_start = poseError(published[2], start2);
    const PoseError e2_50 = poseError(published[2], r2.T);
    std::printf(
        "3dtk slam6D redone: scan001 %.2f cm %.3f deg from the published pose (%zu iterations, "
        "%s); scan002 "
        "start %.2f cm %.3f deg, first iteration %.2f cm %.3f deg, after %zu iterations %.2f cm "
        "%.3f deg (%s)\n",
        e1.trans_m * 100, e1.rot_deg, r1.steps.size(), r1.converged ? "converged" : "not converged",
        e2_start.trans_m * 100, e2_start.rot_deg, e2_first.trans_m * 100, e2_first.rot_deg,
        r2.steps.size(), e2_50.trans_m * 100, e2_50.rot_deg,
        r2.converged ? "converged" : "not converged");
    EXPECT_LT(e1.rot_deg, 0.15);
    EXPECT_LT(e1.trans_m, 0.005);
    EXPECT_LT(e2_first.rot_deg, 0.15);
    EXPECT_LT(e2_first.trans_m, 0.005);
    // The ICP had far to go still: the published scan002 is no minimum of its objective.
    EXPECT_GT(e2_50.rot_deg, 0.5);

    // The same ICP with scan001 thinned to constant density (the first point in each 10 cm cell,
    // as our maps keep points) instead of the raw density that crowds the floor next to the
    // robot: the minimum moves more than the 1.08 deg by which our matcher misses the published
    // pose (measured 1.16 deg, nearly all pitch). The data do not pin scan001's pitch to tenths
    // of a degree; the weighting of the points does.
    std::vector<Eigen::Vector3d> thinned;
    std::unordered_set<std::uint64_t> cells;
    for (const auto& p : pts[1]) {
        const auto q = [](double v) {
            return static_cast<std::uint64_t>(std::floor(v / 0.1) + (1 << 20)) & 0x1FFFFF;
        };
        if (cells.insert((q(p.x()) << 42) | (q(p.y()) << 21) | q(p.z())).second)
            thinned.push_back(p);
    }
    const auto r1c = icp0.align(thinned, odom[0].inverse() * odom[1], kMaxPair, 100, kEps);
    const PoseError e1c = poseError(published[1], r1c.T);
    std::printf(
        "3dtk scan001 by point-to-point ICP at constant density (%zu points): %.2f cm %.3f deg "
        "from the published "
        "pose\n",
        thinned.size(), e1c.trans_m * 100, e1c.rot_deg);
    EXPECT_GT(e1c.rot_deg, 0.8);
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
    g.T_shaft_laser.linear() =
        axes * Eigen::AngleAxisd(dtheta, Eigen::Vector3d::UnitZ()).toRotationMatrix();
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
    std::printf(
        "longarm board: %zu points, plane rms %.2f mm, extent %.2f x %.2f m, normal (%.3f %.3f "
        "%.3f)\n",
        sweep.points.size(), rms * 1000, 2 * std::sqrt(es.eigenvalues()[2]) * 1.732,
        2 * std::sqrt(es.eigenvalues()[1]) * 1.732, n.x(), n.y(), n.z());
    // The URG-04LX's range noise is ~1 cm at 1 m; a wrong geometry bends the board by more.
    EXPECT_LT(rms, 0.012);
    // Upstream's own fit: the board is parallel to the sensor, i.e. its normal is the shaft z.
    EXPECT_GT(std::abs(n.z()), 0.99);
}

}  // namespace
}  // namespace handscan::scan
