// E57: our reader on files written by other software (libE57Format, CloudCompare; the e57 crate's
// test data in ../shared/data/e57; tiny_spherical.e57 lists 360 records, not the 180 its
// SOURCE.txt says), and our writer read back by it, point for point.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>

#include "export_test_support.hpp"
#include "handscan/export/e57_reader.hpp"
#include "handscan/export/exporter.hpp"
#include "handscan/journal/journal_writer.hpp"

namespace handscan::exporter::testing {
namespace {

namespace fs = std::filesystem;

fs::path sharedE57(const std::string& name) {
    return fs::path(HANDSCAN_SHARED_DATA_DIR) / "e57" / name;
}

struct Decoded {
    std::vector<std::vector<double>> columns;
    std::size_t records = 0;
};

Decoded decodeAll(const E57Reader& r, const E57CompressedVector& v) {
    Decoded d;
    d.columns.resize(v.fields.size());
    const Status s = r.read(v, [&](const std::vector<std::vector<double>>& c, std::size_t n) {
        for (std::size_t f = 0; f < c.size(); ++f)
            d.columns[f].insert(d.columns[f].end(), c[f].begin(), c[f].begin() + n);
        d.records += n;
    });
    EXPECT_TRUE(s.isOk()) << s.message();
    return d;
}

#define SKIP_WITHOUT_SHARED_DATA() \
    if (!fs::exists(sharedE57("SOURCE.txt"))) GTEST_SKIP() << "no ../shared/data/e57"

TEST(E57Reader, ReadsOtherWritersFiles) {
    SKIP_WITHOUT_SHARED_DATA();
    struct Case {
        const char* file;
        std::uint64_t records;
        const char* first_field;
    } cases[] = {{"tinyCartesianFloatRgb.e57", 2090, "cartesianX"},
                 {"bunnyInt21.e57", 30571, "cartesianX"},
                 {"bunnyDouble.e57", 30571, "cartesianX"},
                 {"tiny_spherical.e57", 360, "sphericalRange"},
                 {"integer_intensity.e57", 2, "cartesianX"}};
    for (const Case& c : cases) {
        auto r = E57Reader::open(sharedE57(c.file).string());
        ASSERT_TRUE(r.isOk()) << c.file << ": " << r.status().message();
        ASSERT_EQ(r->file().scans.size(), 1u) << c.file;
        const E57CompressedVector& v = r->file().scans[0].points;
        EXPECT_EQ(v.records, c.records) << c.file;
        EXPECT_GE(v.field(c.first_field), 0) << c.file;
        EXPECT_EQ(decodeAll(*r, v).records, c.records) << c.file;
    }
}

// The same bunny as 21-bit scaled integers and as doubles: the bitpack decoder agrees with the
// plain one to the integers' resolution.
TEST(E57Reader, ScaledIntegersMatchDoubles) {
    SKIP_WITHOUT_SHARED_DATA();
    auto ints = E57Reader::open(sharedE57("bunnyInt21.e57").string());
    auto dbls = E57Reader::open(sharedE57("bunnyDouble.e57").string());
    ASSERT_TRUE(ints.isOk() && dbls.isOk());
    const auto& vi = ints->file().scans[0].points;
    const auto& vd = dbls->file().scans[0].points;
    ASSERT_EQ(vi.fields[vi.field("cartesianX")].kind, E57Field::Kind::kScaledInteger);
    EXPECT_EQ(vi.fields[vi.field("cartesianX")].bits, 21u);
    const Decoded a = decodeAll(*ints, vi), b = decodeAll(*dbls, vd);
    ASSERT_EQ(a.records, b.records);
    double worst = 0;
    for (const char* axis : {"cartesianX", "cartesianY", "cartesianZ"}) {
        const auto& ca = a.columns[vi.field(axis)];
        const auto& cb = b.columns[vd.field(axis)];
        for (std::size_t i = 0; i < ca.size(); ++i)
            worst = std::max(worst, std::abs(ca[i] - cb[i]));
    }
    EXPECT_LT(worst, 1e-6);                                   // scale 1e-6 m
    EXPECT_GT(a.columns[vi.field("cartesianX")][100], -0.1);  // a bunny, not noise
}

TEST(E57Reader, NamesTheCorruptPage) {
    SKIP_WITHOUT_SHARED_DATA();
    auto r = E57Reader::open(sharedE57("corrupt_crc.e57").string());
    ASSERT_FALSE(r.isOk());
    EXPECT_EQ(r.status().code(), StatusCode::kChecksumError);
    EXPECT_NE(r.status().message().find("E57 page 33 (bytes 33792..34815) is corrupt"),
              std::string::npos)
        << r.status().message();
}

TEST(E57Reader, RefusesTruncatedAndForeignFiles) {
    SKIP_WITHOUT_SHARED_DATA();
    const fs::path dir = fs::temp_directory_path() / ("e57_trunc_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    fs::copy_file(sharedE57("tiny_spherical.e57"), dir / "t.e57");
    fs::resize_file(dir / "t.e57", 5000);
    auto r = E57Reader::open((dir / "t.e57").string());
    ASSERT_FALSE(r.isOk());
    EXPECT_EQ(r.status().code(), StatusCode::kTruncated) << r.status().message();
    std::ofstream(dir / "x.e57") << "ply\n";
    EXPECT_EQ(E57Reader::open((dir / "x.e57").string()).status().code(),
              StatusCode::kProtocolError);
    fs::remove_all(dir);
}

// Our export, read back by our reader: every field of every point, the trajectory extension, the
// sensor strings; more than one packet and a partial last packet (2500 points, 1024 a packet).
TEST_F(ExportTest, E57RoundTrip) {
    const std::string journal = (dir_ / "j.hsj").string();
    std::vector<journal::MapPoint> pts(2500);
    {
        auto w = journal::JournalWriter::create(journal, R"({"serial": "HS-0042"})");
        ASSERT_TRUE(w.isOk());
        for (std::size_t i = 0; i < pts.size(); ++i) {
            // Every 7th point unseen by the camera: in its laser grey (journal::laserGrey).
            const auto intensity = static_cast<std::uint16_t>(i * 13);
            const auto c =
                static_cast<std::uint8_t>(i % 7 == 0 ? journal::laserGrey(intensity) : i % 251);
            pts[i] = {100.0 + i * 1e-3, i * 0.01f, -0.5f * i, 1.25f, c, c, c, intensity};
        }
        ASSERT_TRUE((*w)->appendPoints(pts).isOk());
        for (int k = 0; k < 700; ++k)
            ASSERT_TRUE(
                (*w)->appendPose({100.0 + k * 0.005, k * 0.1, 0, 1.5, 0, 0, 0.6, 0.8}).isOk());
        ASSERT_TRUE((*w)->finish().isOk());
    }
    auto report = exportScan(journal, dir_.string(), {{"e57"}, 0.0, "out", {}, {}, true, ""});
    ASSERT_TRUE(report.isOk()) << report.status().message();
    const std::string path = (dir_ / "out" / "cloud.e57").string();
    ASSERT_EQ(fs::file_size(path) % 1024, 0u);
    auto r = E57Reader::open(path);
    ASSERT_TRUE(r.isOk()) << r.status().message();
    ASSERT_EQ(r->file().scans.size(), 1u);
    const E57Scan& scan = r->file().scans[0];
    EXPECT_EQ(scan.name, "out");
    EXPECT_EQ(scan.sensor_serial, "HS-0042");
    EXPECT_EQ(scan.sensor_vendor, "handscan");
    EXPECT_EQ(scan.guid.size(), 38u);
    EXPECT_EQ(scan.rotation_wxyz[0], 1.0);
    const Decoded d = decodeAll(*r, scan.points);
    ASSERT_EQ(d.records, pts.size());
    const auto col = [&](const char* name) { return d.columns[scan.points.field(name)]; };
    const auto x = col("cartesianX"), y = col("cartesianY"), z = col("cartesianZ");
    const auto red = col("colorRed"), invalid = col("isColorInvalid"), t = col("timeStamp");
    const auto intensity = col("intensity");
    for (std::size_t i = 0; i < pts.size(); ++i) {
        ASSERT_EQ(x[i], pts[i].x) << i;
        ASSERT_EQ(y[i], pts[i].y) << i;
        ASSERT_EQ(z[i], pts[i].z) << i;
        ASSERT_EQ(red[i], pts[i].r) << i;
        ASSERT_EQ(invalid[i], i % 7 == 0 ? 1.0 : 0.0) << i;
        ASSERT_EQ(intensity[i], pts[i].intensity) << i;
        ASSERT_EQ(t[i], pts[i].t_s) << i;
    }
    ASSERT_TRUE(scan.trajectory.has_value());
    const Decoded traj = decodeAll(*r, *scan.trajectory);
    ASSERT_EQ(traj.records, 700u);
    EXPECT_DOUBLE_EQ(traj.columns[scan.trajectory->field("handscan:x")][699], 69.9);
    EXPECT_DOUBLE_EQ(traj.columns[scan.trajectory->field("handscan:qw")][3], 0.8);
}

// ScaledInteger coordinates (0.1 mm, 32-bit raw values): read back within half a step, the
// prototype says so, the file is smaller; a point beyond the 32-bit range refuses the export.
TEST_F(ExportTest, E57ScaledIntegerCoordinates) {
    const std::string journal = makeJournal(5000);
    ExportOptions opt{{"e57"}, 0.0, "doubles", {}, {}, true, ""};
    ASSERT_TRUE(exportScan(journal, dir_.string(), opt).isOk());
    opt.scan_name = "scaled";
    opt.e57_scale_m = 1e-4;
    auto report = exportScan(journal, dir_.string(), opt);
    ASSERT_TRUE(report.isOk()) << report.status().message();
    const std::string path = (dir_ / "scaled" / "cloud.e57").string();
    EXPECT_LT(fs::file_size(path), fs::file_size(dir_ / "doubles" / "cloud.e57"));
    auto r = E57Reader::open(path);
    ASSERT_TRUE(r.isOk()) << r.status().message();
    const E57CompressedVector& v = r->file().scans[0].points;
    const E57Field& fx = v.fields[v.field("cartesianX")];
    EXPECT_EQ(fx.kind, E57Field::Kind::kScaledInteger);
    EXPECT_EQ(fx.bits, 32u);
    EXPECT_DOUBLE_EQ(fx.scale, 1e-4);
    const Decoded d = decodeAll(*r, v);
    ASSERT_EQ(d.records, 5000u);
    const auto& x = d.columns[v.field("cartesianX")];
    const auto& z = d.columns[v.field("cartesianZ")];
    for (std::size_t i = 0; i < d.records; ++i) {
        ASSERT_NEAR(x[i], static_cast<double>(static_cast<float>(i)), 0.5e-4 + 1e-9) << i;
        ASSERT_NEAR(z[i], -1.0, 0.5e-4 + 1e-9) << i;
    }
    opt.scan_name = "far";
    opt.e57_scale_m = 1e-6;  // ±2.1 km: the 5000 m point does not fit
    auto far = exportScan(journal, dir_.string(), opt);
    ASSERT_FALSE(far.isOk());
    EXPECT_NE(far.status().message().find("beyond the 32-bit range"), std::string::npos)
        << far.status().message();
    EXPECT_FALSE(fs::exists(dir_ / "far" / "cloud.e57"));
}

// A medium that flips a bit after the write: the read-back's per-page CRC-32C names the page, and
// no cloud.e57 is left that looks complete.
TEST_F(ExportTest, E57ReadBackNamesADamagedPage) {
    const std::string journal = makeJournal(5000);
    ExportOptions opt{{"e57"}, 0.0, "out", {}, {}, true, ""};
    opt.faults.before_verify = [](const std::string& partial) {
        std::fstream f(partial, std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(3 * 1024 + 100);
        f.put('\x5a');
    };
    auto r = exportScan(journal, dir_.string(), opt);
    ASSERT_FALSE(r.isOk());
    EXPECT_NE(r.status().message().find("E57 page 3 (bytes 3072..4095) is corrupt"),
              std::string::npos)
        << r.status().message();
    EXPECT_FALSE(fs::exists(dir_ / "out" / "cloud.e57"));
}

}  // namespace
}  // namespace handscan::exporter::testing
