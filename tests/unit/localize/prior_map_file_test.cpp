// feature_map.hsf round trip and its errors; an earlier scan's directory as a prior map; the
// --initial-pose parser.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "handscan/prior_map/feature_map_file.hpp"
#include "handscan/prior_map/prior_map_loader.hpp"
#include "handscan/tum/tum_file.hpp"

namespace handscan::prior_map {
namespace {

namespace fs = std::filesystem;

class PriorMapFileTest : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() /
               ("handscan_prior_map_" +
                std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
                ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }

    static scan::FeatureMapPoints sample(int n) {
        scan::FeatureMapPoints m;
        for (int i = 0; i < n; ++i) {
            m.edges.emplace_back(0.1f * i, 1.0f, 2.0f);
            m.planars.emplace_back(1.0f, 0.1f * i, -2.0f);
            m.planar_origins.emplace_back(i % 2 ? std::nanf("") : 0.5f, 0.0f, 1.3f);
        }
        return m;
    }
    fs::path dir_;
};

TEST_F(PriorMapFileTest, RoundTripKeepsEveryPointAndUnknownOrigins) {
    const scan::FeatureMapPoints m = sample(7);
    const std::string path = (dir_ / kFeatureMapFile).string();
    ASSERT_TRUE(writeFeatureMap(path, m).isOk());
    auto r = readFeatureMap(path);
    ASSERT_TRUE(r.isOk()) << r.status().message();
    EXPECT_EQ(r->edges, m.edges);
    EXPECT_EQ(r->planars, m.planars);
    ASSERT_EQ(r->planar_origins.size(), 7u);
    EXPECT_TRUE(std::isnan(r->planar_origins[1].x()));
    EXPECT_EQ(r->planar_origins[2], m.planar_origins[2]);
}

TEST_F(PriorMapFileTest, DamagedOrTruncatedFilesAreNamed) {
    const std::string path = (dir_ / kFeatureMapFile).string();
    ASSERT_TRUE(writeFeatureMap(path, sample(5)).isOk());
    {
        std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(30);
        f.put('\x7f');
    }
    auto r = readFeatureMap(path);
    ASSERT_FALSE(r.isOk());
    EXPECT_NE(r.status().message().find("CRC mismatch"), std::string::npos);
    EXPECT_NE(r.status().message().find(path), std::string::npos);
    fs::resize_file(path, 40);
    r = readFeatureMap(path);
    ASSERT_FALSE(r.isOk());
    EXPECT_NE(r.status().message().find("truncated"), std::string::npos) << r.status().message();
    EXPECT_FALSE(readFeatureMap((dir_ / "none.hsf").string()).isOk());
    scan::FeatureMapPoints bad = sample(3);
    bad.planar_origins.pop_back();
    EXPECT_FALSE(writeFeatureMap(path, bad).isOk());
}

TEST_F(PriorMapFileTest, ScanDirectoryStartsWhereItsTrajectoryStarts) {
    ASSERT_TRUE(writeFeatureMap((dir_ / kFeatureMapFile).string(), sample(80)).isOk());
    tum::Trajectory t(2);
    t[0].t_s = 1.0;
    t[0].T.translation() = Eigen::Vector3d(1, 2, 3);
    t[1].t_s = 2.0;
    ASSERT_TRUE(tum::writeTum((dir_ / "trajectory.tum").string(), t).isOk());
    auto prior = loadPriorMap(dir_.string());
    ASSERT_TRUE(prior.isOk()) << prior.status().message();
    EXPECT_TRUE((*prior)->start().translation().isApprox(Eigen::Vector3d(1, 2, 3)));
    EXPECT_EQ((*prior)->size(), 160u);
    auto missing = loadPriorMap((dir_ / "nothing").string());
    ASSERT_FALSE(missing.isOk());
    EXPECT_NE(missing.status().message().find("not a directory"), std::string::npos);
}

TEST(ParsePoseTest, TumOrderAndErrors) {
    auto p = parsePose("1,2,3,0,0,0.7071068,0.7071068");
    ASSERT_TRUE(p.isOk());
    EXPECT_TRUE(p->translation().isApprox(Eigen::Vector3d(1, 2, 3)));
    EXPECT_TRUE((p->linear() * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitY(), 1e-6));
    EXPECT_NE(parsePose("1,2,3").status().message().find("7 numbers"), std::string::npos);
    EXPECT_NE(parsePose("1,2,x,0,0,0,1").status().message().find("'x' is not a number"),
              std::string::npos);
    EXPECT_NE(parsePose("1,2,3,0,0,0,2").status().message().find("unit length"), std::string::npos);
}

}  // namespace
}  // namespace handscan::prior_map
