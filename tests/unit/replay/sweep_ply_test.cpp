// replay::writeSweepPly (--dump-sweeps): a sweep through the export's PLY writer.
#include "handscan/replay/sweep_ply.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

namespace handscan::replay {
namespace {

scan::Sweep threePoints() {
    scan::Sweep s;
    s.index = 42;
    s.t_start = 5 * kNsPerSec;
    for (int i = 0; i < 3; ++i) {
        scan::SweepPoint p;
        p.t = s.t_start + i * 25 * kNsPerMs;
        p.p_start = Eigen::Vector3d(1.0 + i, -2.0, 0.5 * i);
        p.intensity = 1000.4f + static_cast<float>(i);
        s.points.push_back(p);
    }
    s.t_end = s.points.back().t;
    return s;
}

TEST(SweepPly, WritesTheExportLayoutInTheSweepFrame) {
    const scan::Sweep s = threePoints();
    const auto path = std::filesystem::temp_directory_path() / "handscan_sweep_ply_test.ply";
    ASSERT_TRUE(writeSweepPly(path.string(), s).isOk());
    std::ifstream in(path, std::ios::binary);
    const std::string content((std::istreambuf_iterator<char>(in)),
                              std::istreambuf_iterator<char>());
    const auto end = content.find("end_header\n");
    ASSERT_NE(end, std::string::npos);
    const std::string header = content.substr(0, end);
    EXPECT_NE(header.find("comment handscan sweep 42\n"), std::string::npos);
    EXPECT_NE(header.find("first point at 5.0"), std::string::npos);
    EXPECT_NE(header.find("element vertex 3\n"), std::string::npos);
    EXPECT_NE(header.find("property ushort intensity\nproperty double time\n"), std::string::npos);
    const std::size_t body = end + std::strlen("end_header\n");
    constexpr std::size_t kRecord = 3 * 4 + 3 + 2 + 8;
    ASSERT_EQ(content.size() - body, 3 * kRecord);
    // The last vertex: x y z float, rgb 0 (no colour), intensity ushort, time double.
    const char* v = content.data() + body + 2 * kRecord;
    float xyz[3];
    std::uint16_t intensity = 0;
    double t = 0.0;
    std::memcpy(xyz, v, 12);
    std::memcpy(&intensity, v + 15, 2);
    std::memcpy(&t, v + 17, 8);
    EXPECT_FLOAT_EQ(xyz[0], 3.0f);
    EXPECT_FLOAT_EQ(xyz[1], -2.0f);
    EXPECT_FLOAT_EQ(xyz[2], 1.0f);
    EXPECT_EQ(v[12] | v[13] | v[14], 0);
    EXPECT_EQ(intensity, 1002);
    EXPECT_NEAR(t, 5.05, 1e-12);
    std::filesystem::remove(path);
}

TEST(SweepPly, NamesTheFileItCannotWrite) {
    const Status bad = writeSweepPly("/nonexistent-dir/x.ply", threePoints());
    EXPECT_FALSE(bad.isOk());
    EXPECT_NE(bad.message().find("/nonexistent-dir/x.ply"), std::string::npos);
}

}  // namespace
}  // namespace handscan::replay
