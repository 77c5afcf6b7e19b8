#include "export_test_support.hpp"

#include <sys/mount.h>
#include <unistd.h>

#include <fstream>
#include <iterator>

#include "handscan/journal/journal_writer.hpp"

namespace handscan::exporter::testing {

namespace fs = std::filesystem;

std::vector<std::uint8_t> readFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void ExportTest::SetUp() {
    dir_ = fs::temp_directory_path() /
           ("handscan_export_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
}

void ExportTest::TearDown() {
    for (auto it = mounts_.rbegin(); it != mounts_.rend(); ++it) ::umount2(it->c_str(), MNT_DETACH);
    fs::remove_all(dir_);
}

std::string ExportTest::makeJournal(std::size_t n, const std::string& name) {
    const std::string path = (dir_ / name).string();
    auto w = journal::JournalWriter::create(path, R"({"device":"test"})");
    EXPECT_TRUE(w.isOk()) << w.status().message();
    std::vector<journal::MapPoint> pts;
    for (std::size_t i = 0; i < n; ++i) {
        pts.push_back({static_cast<double>(i), static_cast<float>(i), 0.5f, -1.0f,
                       static_cast<std::uint8_t>(i), static_cast<std::uint8_t>(2 * i),
                       static_cast<std::uint8_t>(3 * i), static_cast<std::uint16_t>(i)});
        // Every 256th point was not seen by the camera: it carries its laser grey.
        if (i % 256 == 0)
            pts.back().r = pts.back().g = pts.back().b = journal::laserGrey(pts.back().intensity);
    }
    EXPECT_TRUE((*w)->appendPoints(pts).isOk());
    EXPECT_TRUE((*w)->appendPose({0.0, 0, 0, 0, 0, 0, 0, 1}).isOk());
    EXPECT_TRUE((*w)->finish().isOk());
    return path;
}

std::string ExportTest::mountTmpfs(const std::string& size, bool read_only) {
    const fs::path m = dir_ / ("mnt" + std::to_string(mounts_.size()));
    fs::create_directories(m);
    if (::mount("tmpfs", m.c_str(), "tmpfs", 0, ("size=" + size).c_str()) != 0) return "";
    mounts_.push_back(m.string());
    if (read_only && ::mount(nullptr, m.c_str(), nullptr, MS_REMOUNT | MS_RDONLY, nullptr) != 0)
        return "";
    return m.string();
}

}  // namespace handscan::exporter::testing
