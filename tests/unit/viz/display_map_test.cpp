// The /map and /sweep point records and the display map behind /map (firmware/viz point_cloud).
#include <gtest/gtest.h>

#include <cstring>

#include "handscan/viz/point_cloud.hpp"

namespace handscan::viz {
namespace {

journal::MapPoint point(float x, float y, float z, std::uint8_t r = 0, std::uint16_t i = 0) {
    journal::MapPoint p;
    p.x = x;
    p.y = y;
    p.z = z;
    p.r = r;
    p.intensity = i;
    return p;
}

float floatAt(const std::string& s, std::size_t offset) {
    float v;
    std::memcpy(&v, s.data() + offset, sizeof(v));
    return v;
}

std::uint32_t rgbAt(const std::string& s, std::size_t record) {
    std::uint32_t v;
    std::memcpy(&v, s.data() + record * kPointStride + 16, sizeof(v));
    return v;
}

TEST(PointRecord, LaysOutXyzIntensityAndPackedRgb) {
    std::string out;
    appendPointRecord(point(1.5f, -2.0f, 3.25f, 200, 1000), out);
    ASSERT_EQ(out.size(), kPointStride);
    EXPECT_EQ(floatAt(out, 0), 1.5f);
    EXPECT_EQ(floatAt(out, 4), -2.0f);
    EXPECT_EQ(floatAt(out, 8), 3.25f);
    EXPECT_EQ(floatAt(out, 12), 1000.0f);
    EXPECT_EQ(rgbAt(out, 0), 200u << 16);  // 0x00RRGGBB: red in bits 16..23
    // Bytes b, g, r, 0 as PCL packs them.
    EXPECT_EQ(static_cast<std::uint8_t>(out[18]), 200);
    EXPECT_EQ(out[19], 0);
}

TEST(PointRecord, UncolouredPointKeepsItsLaserGrey) {
    // The worker journals an unseen point in its laser grey (journal::laserGrey): 1600 / 16.
    journal::MapPoint p = point(0, 0, 0, 0, 1600);
    p.r = p.g = p.b = journal::laserGrey(p.intensity);
    ASSERT_FALSE(journal::hasColour(p));
    std::string out;
    appendPointRecord(p, out);
    EXPECT_EQ(rgbAt(out, 0), (100u << 16) | (100u << 8) | 100u);
    EXPECT_EQ(journal::laserGrey(60000), 255);  // saturates
}

TEST(DisplayMap, KeepsTheFirstPointOfEachVoxel) {
    DisplayMap map(0.05f, 1000);
    const journal::MapPoint a = point(0.01f, 0.01f, 0.01f, 10);
    const journal::MapPoint same_voxel = point(0.04f, 0.02f, 0.03f, 20);
    const journal::MapPoint next_voxel = point(0.06f, 0.01f, 0.01f, 30);
    map.add(std::vector{a, same_voxel});
    map.add(std::vector{next_voxel, same_voxel});
    EXPECT_EQ(map.size(), 2u);
    std::string snap;
    map.snapshot(snap);
    ASSERT_EQ(snap.size(), 2 * kPointStride);
    EXPECT_EQ(rgbAt(snap, 0), 10u << 16);  // the first seen, not the later one
    EXPECT_EQ(rgbAt(snap, 1), 30u << 16);
}

TEST(DisplayMap, ThinsEvenlyToTheBudgetAsItGrows) {
    DisplayMap map(0.05f, 100);
    std::vector<journal::MapPoint> line;
    for (int i = 0; i < 1000; ++i) line.push_back(point(0.1f * static_cast<float>(i), 0, 0));
    map.add(line);
    EXPECT_EQ(map.size(), 1000u);
    EXPECT_EQ(map.snapshotSize(), 100u);
    std::string snap;
    map.snapshot(snap);
    ASSERT_EQ(snap.size(), 100 * kPointStride);
    // Every tenth voxel: the thinned map spans the whole line evenly.
    for (std::size_t j = 0; j < 100; ++j)
        EXPECT_FLOAT_EQ(floatAt(snap, j * kPointStride), 0.1f * static_cast<float>(10 * j));
    // A little more map: still 100 points, not a sudden halving.
    map.add(std::vector{point(-5.0f, 0, 0)});
    map.snapshot(snap);
    EXPECT_EQ(snap.size(), 100 * kPointStride);
}

}  // namespace
}  // namespace handscan::viz
