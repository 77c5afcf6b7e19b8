// `handscan eval` end to end: files in, figures and exit codes out.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>

#include "handscan/core/se3.hpp"
#include "handscan/eval/tum.hpp"

namespace handscan::eval {
namespace {

struct CliResult {
    int code;
    std::string out;
};

CliResult handscan(const std::string& args) {
    const std::string cmd =
        std::string(HANDSCAN_BINARY_DIR) + "/firmware/cli/handscan eval " + args + " 2>&1";
    std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(cmd.c_str(), "r"), pclose);
    std::string out;
    char buf[512];
    while (pipe && std::fgets(buf, sizeof buf, pipe.get())) out += buf;
    const int status = pclose(pipe.release());
    return {WEXITSTATUS(status), out};
}

class EvalCli : public ::testing::Test {
protected:
    void SetUp() override {
        // One directory per test: CTest runs the tests of this fixture in parallel.
        dir_ = std::filesystem::path(HANDSCAN_BINARY_DIR) / "eval_cli_test" /
               ::testing::UnitTest::GetInstance()->current_test_info()->name();
        std::filesystem::create_directories(dir_);
        if (!std::filesystem::exists(std::string(HANDSCAN_BINARY_DIR) + "/firmware/cli/handscan")) {
            GTEST_SKIP() << "handscan not built";
        }
    }
    void TearDown() override { std::filesystem::remove_all(dir_); }
    std::filesystem::path dir_;
};

TEST_F(EvalCli, TrajectoryFiguresAndPlot) {
    // A 30 m straight walk; the estimate is 2 % long and offset by a rigid transform.
    Trajectory gt, est;
    Eigen::Isometry3d offset = Eigen::Isometry3d::Identity();
    offset.linear() = expSO3(Eigen::Vector3d(0, 0, 0.7));
    offset.translation() = Eigen::Vector3d(3, 4, 5);
    for (int k = 0; k <= 300; ++k) {
        StampedPose p;
        p.t_s = 100.0 + 0.1 * k;
        p.T.translation() = Eigen::Vector3d(0.1 * k, 0, 0);
        gt.push_back(p);
        p.T.translation() *= 1.02;
        p.T = offset * p.T;
        est.push_back(p);
    }
    ASSERT_TRUE(writeTum((dir_ / "gt.tum").string(), gt).isOk());
    ASSERT_TRUE(writeTum((dir_ / "est.tum").string(), est).isOk());
    const CliResult r =
        handscan("--gt " + (dir_ / "gt.tum").string() + " --est " + (dir_ / "est.tum").string() +
                 " --plot " + (dir_ / "top.png").string());
    EXPECT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find("drift    5 m: 2.000 %"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("drift   40 m: no segment"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("end point: 0.6000 m (2.000 % of path)"), std::string::npos) << r.out;
    EXPECT_TRUE(std::filesystem::exists(dir_ / "top.png"));
}

TEST_F(EvalCli, MapErrorAndBadInput) {
    std::ofstream(dir_ / "floor.ply")
        << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
           "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
           "end_header\n0 0 0\n10 0 0\n0 10 0\n3 0 1 2\n";
    std::ofstream(dir_ / "map.ply")
        << "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
           "property float z\nend_header\n1 1 0.02\n2 2 0.02\n";
    CliResult r = handscan("--map " + (dir_ / "map.ply").string() + " --mesh " +
                           (dir_ / "floor.ply").string());
    EXPECT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find("median 0.0200"), std::string::npos) << r.out;

    r = handscan("--gt " + (dir_ / "missing.tum").string() + " --est " +
                 (dir_ / "missing.tum").string());
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.out.find("missing.tum: cannot open"), std::string::npos) << r.out;
    r = handscan("--gt " + (dir_ / "x.tum").string());
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.out.find("give --gt and --est"), std::string::npos) << r.out;
}

// The pipeline's map is in its own start frame: with --gt/--est the map is moved into the ground
// truth's frame by the trajectory alignment before measuring. Here the estimate (and its map) is
// the truth seen from a frame turned 90 deg and shifted 5 m: unaligned the map is metres off the
// floor, aligned it is 2 cm above it.
TEST_F(EvalCli, MapAlignedByTheTrajectory) {
    std::ofstream(dir_ / "floor.ply")
        << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
           "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
           "end_header\n-50 -50 0\n150 -50 0\n-50 150 0\n3 0 1 2\n";
    Eigen::Isometry3d T_est_gt = Eigen::Isometry3d::Identity();
    T_est_gt.linear() = expSO3(Eigen::Vector3d(M_PI / 2, 0, 0));  // the floor becomes a wall
    T_est_gt.translation() = Eigen::Vector3d(0, 0, 5);
    Trajectory gt, est;
    for (int k = 0; k <= 200; ++k) {
        StampedPose p;
        p.t_s = 10.0 + 0.05 * k;
        p.T.translation() =
            Eigen::Vector3d(0.1 * k, 0.5 * std::sin(0.1 * k), 1.5 + 0.2 * std::cos(0.07 * k));
        gt.push_back(p);
        p.T = T_est_gt * p.T;
        est.push_back(p);
    }
    ASSERT_TRUE(writeTum((dir_ / "gt.tum").string(), gt).isOk());
    ASSERT_TRUE(writeTum((dir_ / "est.tum").string(), est).isOk());
    std::ofstream map(dir_ / "map.ply");
    map << "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty "
           "float z\nend_header\n";
    for (const Eigen::Vector3d& q : {Eigen::Vector3d(1, 1, 0.02), Eigen::Vector3d(2, 3, 0.02)}) {
        const Eigen::Vector3d m = T_est_gt * q;
        map << m.x() << " " << m.y() << " " << m.z() << "\n";
    }
    map.close();
    const std::string files =
        "--map " + (dir_ / "map.ply").string() + " --mesh " + (dir_ / "floor.ply").string();
    CliResult r = handscan(files);
    EXPECT_EQ(r.code, 0) << r.out;
    EXPECT_EQ(r.out.find("median 0.0200"), std::string::npos) << r.out;
    r = handscan(files + " --gt " + (dir_ / "gt.tum").string() + " --est " +
                 (dir_ / "est.tum").string());
    EXPECT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find("ATE (SE(3)-aligned) [m]: rmse 0.0000"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("map error (map aligned by the trajectory) over 2 points"),
              std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find("median 0.0200"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace handscan::eval
