// The out-of-core map equals the in-memory voxel filter byte for byte (on a stream that leaves
// and revisits tiles under a budget that forces flushing), stays within its budget, and leaves no
// scratch file behind, whether it succeeds or fails.
#include "handscan/replay/tiled_voxel_map.hpp"

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <csignal>
#include <cstring>
#include <filesystem>
#include <random>

#include "../common/scratch_dir.hpp"
#include "handscan/export/voxel_filter.hpp"

namespace handscan::replay {
namespace {

namespace fs = std::filesystem;
using exporter::VoxelFilter;
using journal::MapPoint;

// A walk around a 60 m x 40 m loop, three laps, seeing points within 12 m: every tile is left and
// revisited. One "sweep" of points per step, with the sensor position.
struct Step {
    Eigen::Vector3d sensor;
    std::vector<MapPoint> points;
};

std::vector<Step> loopWalk(int laps, int steps_per_lap, int points_per_step, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::uniform_int_distribution<int> colour(0, 255);
    std::vector<Step> steps;
    double t = 1000.0;
    for (int lap = 0; lap < laps; ++lap) {
        for (int k = 0; k < steps_per_lap; ++k) {
            const double a = 2.0 * M_PI * k / steps_per_lap;
            Step s;
            s.sensor = {30.0 * std::cos(a), 20.0 * std::sin(a), 1.5};
            for (int i = 0; i < points_per_step; ++i) {
                t += 1.7e-5;
                // Walls and floor around the sensor, on a coarse lattice so that voxels get many
                // hits from several laps (exact sums are what is tested), plus noise.
                const double dx = std::round(u(rng) * 120.0) / 10.0,
                             dy = std::round(u(rng) * 120.0) / 10.0;
                const double z = (i % 3 == 0) ? 0.0 : std::round((u(rng) + 1.0) * 15.0) / 10.0;
                s.points.push_back(
                    {t, static_cast<float>(s.sensor.x() + dx + 0.01 * u(rng)),
                     static_cast<float>(s.sensor.y() + dy + 0.01 * u(rng)),
                     static_cast<float>(z + 0.01 * u(rng)), static_cast<std::uint8_t>(colour(rng)),
                     static_cast<std::uint8_t>(colour(rng)), static_cast<std::uint8_t>(colour(rng)),
                     static_cast<std::uint16_t>(colour(rng) * 100)});
            }
            steps.push_back(std::move(s));
        }
    }
    return steps;
}

void expectSamePoints(const std::vector<MapPoint>& a, const std::vector<MapPoint>& b) {
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
        // Every field, bit for bit (the padding of the struct is not compared).
        const bool same = std::memcmp(&a[i].t_s, &b[i].t_s, 8) == 0 &&
                          std::memcmp(&a[i].x, &b[i].x, 4) == 0 &&
                          std::memcmp(&a[i].y, &b[i].y, 4) == 0 &&
                          std::memcmp(&a[i].z, &b[i].z, 4) == 0 && a[i].r == b[i].r &&
                          a[i].g == b[i].g && a[i].b == b[i].b && a[i].intensity == b[i].intensity;
        ASSERT_TRUE(same) << "point " << i << ": (" << a[i].t_s << ", " << a[i].x << ", " << a[i].y
                          << ", " << a[i].z << ") vs (" << b[i].t_s << ", " << b[i].x << ", "
                          << b[i].y << ", " << b[i].z << ")";
    }
}

class TiledVoxelMapTest : public ::testing::Test {
protected:
    bool dirEmpty(const fs::path& d) const { return fs::is_empty(d); }

    static Result<std::vector<MapPoint>> drainAll(TiledVoxelMap& map) {
        std::vector<MapPoint> out;
        std::uint64_t announced = 0;
        auto n = map.drain(
            [&](std::uint64_t total) {
                announced = total;
                out.reserve(total);
                return Status::ok();
            },
            [&](std::span<const MapPoint> pts) {
                out.insert(out.end(), pts.begin(), pts.end());
                return Status::ok();
            });
        if (!n.isOk()) return n.status();
        EXPECT_EQ(*n, announced);
        EXPECT_EQ(out.size(), announced);
        return out;
    }

    handscan::testing::ScratchDir scratch_{"handscan_tiled_map_"};
    const fs::path dir_ = scratch_.path();
};

TEST(VoxelFilterExactSums, OrderAndGroupingDoNotChangeTheResult) {
    // 60000 points in a 2 m cube around a corner of the axes (negative coordinates and ones
    // close to zero included), 64 voxels: each sum has about a thousand terms.
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    std::vector<MapPoint> all;
    for (int i = 0; i < 60000; ++i) {
        all.push_back({1.0e6 + i * 1.3e-4, u(rng), u(rng) * 1e-3f, 100.0f + u(rng),
                       static_cast<std::uint8_t>(i % 256), static_cast<std::uint8_t>(i % 7), 3,
                       static_cast<std::uint16_t>(i % 6000)});
    }
    VoxelFilter forward(0.5);
    forward.add(all);
    // Reversed order, and in two halves merged: the same bits.
    std::vector<MapPoint> reversed(all.rbegin(), all.rend());
    VoxelFilter backward(0.5);
    backward.add(reversed);
    VoxelFilter first(0.5), second(0.5), merged(0.5);
    first.add(std::span(all).first(all.size() / 3));
    second.add(std::span(all).subspan(all.size() / 3));
    second.forEachCell([&](const VoxelFilter::Cell& c) { merged.merge(c); });
    first.forEachCell([&](const VoxelFilter::Cell& c) { merged.merge(c); });
    const auto expected = forward.take();
    EXPECT_EQ(expected.size(), 4u * 2u * 4u);  // y straddles zero: two voxels
    expectSamePoints(backward.take(), expected);
    expectSamePoints(merged.take(), expected);
}

TEST(VoxelFilterExactSums, CentroidMeanTimeAndColour) {
    VoxelFilter f(0.1);
    const std::vector<MapPoint> pts{{1.0, 0.02f, -0.01f, 3.01f, 100, 0, 10, 10},
                                    {4.0, 0.06f, -0.03f, 3.03f, 201, 0, 20, 31},
                                    {5.0, 0.55f, 0.01f, 0.01f, 50, 50, 50, 5}};
    f.add(pts);
    const auto out = f.take();
    ASSERT_EQ(out.size(), 2u);
    EXPECT_DOUBLE_EQ(out[0].t_s, 2.5);
    EXPECT_NEAR(out[0].x, 0.04f, 1e-7);
    EXPECT_NEAR(out[0].y, -0.02f, 1e-7);
    EXPECT_NEAR(out[0].z, 3.02f, 1e-6);
    EXPECT_EQ(out[0].r, 151);  // 150.5 rounds away from zero
    EXPECT_EQ(out[0].b, 15);
    EXPECT_EQ(out[0].intensity, 21);  // 20.5
    EXPECT_DOUBLE_EQ(out[1].t_s, 5.0);
    EXPECT_FLOAT_EQ(out[1].x, 0.55f);
}

TEST_F(TiledVoxelMapTest, EqualsTheInMemoryFilterWithRevisitsAndFlushing) {
    const auto steps = loopWalk(3, 40, 4000, 7);
    VoxelFilter reference(0.1);
    TiledMapConfig cfg;
    cfg.voxel_m = 0.1;
    cfg.tile_m = 8.0;
    cfg.memory_budget_bytes = 3u << 20;  // a fraction of the map: tiles are flushed and revisited
    cfg.spill_dir = dir_.string();
    TiledVoxelMap map(cfg);
    for (const Step& s : steps) {
        reference.add(s.points);
        ASSERT_TRUE(map.add(s.points, s.sensor).isOk());
        EXPECT_LE(map.stats().resident_bytes, cfg.memory_budget_bytes);
        EXPECT_TRUE(dirEmpty(dir_)) << "the scratch file is unlinked at once";
    }
    const TiledMapStats st = map.stats();
    EXPECT_GT(reference.memoryBytes(), 4 * cfg.memory_budget_bytes);
    EXPECT_GT(st.fragments_flushed, st.tiles)
        << "tiles must have been flushed more than once (revisited)";
    auto out = drainAll(map);
    ASSERT_TRUE(out.isOk()) << out.status().message();
    expectSamePoints(*out, reference.take());
    EXPECT_GT(map.stats().peak_spill_bytes, 0u);
    EXPECT_TRUE(dirEmpty(dir_));
}

TEST_F(TiledVoxelMapTest, RepeatedFlushesAreConsolidatedAndTheScratchFileStaysNearTheMapSize) {
    // Eight laps under a budget far below the map: the same tiles are flushed over and over.
    const auto steps = loopWalk(8, 40, 2000, 17);
    VoxelFilter reference(0.1);
    TiledMapConfig cfg{0.1, 8.0, 2u << 20, dir_.string()};
    cfg.spill_slack_bytes = 1u << 20;
    TiledVoxelMap map(cfg);
    for (const Step& s : steps) {
        reference.add(s.points);
        Status added = map.add(s.points, s.sensor);
        ASSERT_TRUE(added.isOk()) << added.message();
    }
    const TiledMapStats st = map.stats();
    EXPECT_GT(st.consolidations, 0u);
    EXPECT_GT(st.compactions, 0u);
    const std::uint64_t map_bytes = reference.size() * sizeof(VoxelFilter::Cell);
    EXPECT_GT(st.spill_written_bytes, 3 * map_bytes)
        << "the test must flush the map several times over";
    // Live fragments hold each voxel at most kMaxFragments (4) times; dead ones at most as much
    // again (plus the slack) before a rewrite.
    EXPECT_LE(st.peak_spill_bytes, 2 * 4 * map_bytes + 2 * cfg.spill_slack_bytes);
    auto out = drainAll(map);
    ASSERT_TRUE(out.isOk()) << out.status().message();
    expectSamePoints(*out, reference.take());
    EXPECT_TRUE(dirEmpty(dir_));
}

TEST_F(TiledVoxelMapTest, WithoutPressureNothingIsFlushedAndTheResultIsTheSame) {
    const auto steps = loopWalk(1, 30, 2000, 11);
    VoxelFilter reference(0.05);
    TiledMapConfig cfg;
    cfg.voxel_m = 0.05;
    cfg.spill_dir = dir_.string();
    TiledVoxelMap map(cfg);
    for (const Step& s : steps) {
        reference.add(s.points);
        ASSERT_TRUE(map.add(s.points, s.sensor).isOk());
    }
    EXPECT_EQ(map.stats().fragments_flushed, 0u);
    auto out = drainAll(map);
    ASSERT_TRUE(out.isOk()) << out.status().message();
    expectSamePoints(*out, reference.take());
}

TEST_F(TiledVoxelMapTest, EmptyMapDrainsToNothing) {
    TiledMapConfig cfg;
    cfg.spill_dir = dir_.string();
    TiledVoxelMap map(cfg);
    auto out = drainAll(map);
    ASSERT_TRUE(out.isOk());
    EXPECT_TRUE(out->empty());
}

TEST_F(TiledVoxelMapTest, AFailingSinkLeavesNoScratchFile) {
    const auto steps = loopWalk(2, 20, 4000, 5);
    TiledMapConfig cfg{0.1, 8.0, 1u << 20, dir_.string()};
    TiledVoxelMap map(cfg);
    for (const Step& s : steps) ASSERT_TRUE(map.add(s.points, s.sensor).isOk());
    ASSERT_GT(map.stats().fragments_flushed, 0u);
    auto r = map.drain([](std::uint64_t) { return Status::ok(); },
                       [](std::span<const MapPoint>) {
                           return Status(StatusCode::kIoError, "map.ply: disk gone");
                       });
    ASSERT_FALSE(r.isOk());
    EXPECT_EQ(r.status().message(), "map.ply: disk gone");
    EXPECT_TRUE(dirEmpty(dir_));
}

TEST_F(TiledVoxelMapTest, AMissingSpillDirectoryIsAClearError) {
    const auto steps = loopWalk(1, 20, 4000, 5);
    const std::string missing = (dir_ / "no" / "such").string();
    TiledVoxelMap map({0.1, 8.0, 256u << 10, missing});
    Status s = Status::ok();
    for (const Step& step : steps) {
        s = map.add(step.points, step.sensor);
        if (!s.isOk()) break;
    }
    ASSERT_FALSE(s.isOk());
    EXPECT_NE(s.message().find("map spill file " + missing + "/.map-fragments.spill"),
              std::string::npos)
        << s.message();
    EXPECT_NE(s.message().find("cannot create"), std::string::npos) << s.message();
}

TEST_F(TiledVoxelMapTest, AFullDiskIsAnErrorNamingTheSpillFile) {
    const fs::path disk = scratch_.mountSmallDisk("1m");
    if (disk.empty()) GTEST_SKIP() << "mounting a tmpfs is not permitted here";
    const auto steps = loopWalk(3, 40, 4000, 9);
    TiledVoxelMap map({0.1, 8.0, 1u << 20, disk.string()});
    Status s = Status::ok();
    for (const Step& step : steps) {
        s = map.add(step.points, step.sensor);
        if (!s.isOk()) break;
    }
    ASSERT_FALSE(s.isOk()) << "1 MiB of disk cannot hold the flushed tiles";
    EXPECT_EQ(s.code(), StatusCode::kNoSpace);
    EXPECT_NE(s.message().find(disk.string() + "/.map-fragments.spill"), std::string::npos)
        << s.message();
    EXPECT_NE(s.message().find("No space left on device"), std::string::npos) << s.message();
    EXPECT_TRUE(dirEmpty(disk));
}

TEST_F(TiledVoxelMapTest, AFileSizeLimitFailsTheWriteWithTheFileNamed) {
    // A write error without a special filesystem: the process's file size limit (EFBIG).
    const auto steps = loopWalk(3, 40, 4000, 13);
    TiledVoxelMap map({0.1, 8.0, 1u << 20, dir_.string()});
    rlimit old{};
    ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &old), 0);
    auto* previous = std::signal(SIGXFSZ, SIG_IGN);
    rlimit small = old;
    small.rlim_cur = 512 * 1024;
    ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &small), 0);
    Status s = Status::ok();
    for (const Step& step : steps) {
        s = map.add(step.points, step.sensor);
        if (!s.isOk()) break;
    }
    ::setrlimit(RLIMIT_FSIZE, &old);
    std::signal(SIGXFSZ, previous);
    ASSERT_FALSE(s.isOk());
    EXPECT_NE(s.message().find((dir_ / ".map-fragments.spill").string()), std::string::npos)
        << s.message();
    EXPECT_NE(s.message().find("File too large"), std::string::npos) << s.message();
    EXPECT_TRUE(dirEmpty(dir_));
}

}  // namespace
}  // namespace handscan::replay
