// SafeFileWriter on its own: the O_DIRECT and the buffered paths write the same bytes (several
// I/O buffers, an unaligned tail, a header patched after the data went out), and the read-back
// catches a file that differs on the medium from what was written.
#include "handscan/export/safe_file.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <numeric>

#include "export_test_support.hpp"

namespace handscan::exporter::testing {
namespace {

namespace fs = std::filesystem;

// 9 MiB + 1234 bytes of a pattern after a 375-byte header: three 4 MiB buffers, the last one
// partial and not a multiple of 4 KiB.
std::vector<std::uint8_t> pattern() {
    std::vector<std::uint8_t> v((9u << 20) + 1234);
    for (std::size_t i = 0; i < v.size(); ++i)
        v[i] = static_cast<std::uint8_t>((i * 2654435761u) >> 13);
    return v;
}

Status writeWithHeader(const fs::path& path, WriteFaults faults, bool* direct = nullptr) {
    SafeFileWriter f(path.string(), std::move(faults));
    if (Status s = f.open(); !s.isOk()) return s;
    if (Status s = f.reserveHeader(375); !s.isOk()) return s;
    const auto data = pattern();
    // Odd-sized pieces, so buffer boundaries fall inside them.
    for (std::size_t done = 0; done < data.size();) {
        const std::size_t n = std::min<std::size_t>(100'003, data.size() - done);
        if (Status s = f.write(std::span(data.data() + done, n)); !s.isOk()) return s;
        done += n;
    }
    std::vector<std::uint8_t> header(375);
    std::iota(header.begin(), header.end(), std::uint8_t{1});
    if (Status s = f.patchHeader(header); !s.isOk()) return s;
    EXPECT_EQ(f.bytesWritten(), 375 + data.size());
    if (direct) *direct = f.directIo();
    return f.commit();
}

TEST_F(ExportTest, DirectAndBufferedPathsWriteTheSameBytes) {
    bool direct = false;
    ASSERT_TRUE(writeWithHeader(dir_ / "direct.bin", {}, &direct).isOk());
    WriteFaults buffered;
    buffered.buffered_only = true;
    bool buffered_direct = true;
    ASSERT_TRUE(writeWithHeader(dir_ / "buffered.bin", buffered, &buffered_direct).isOk());
    EXPECT_FALSE(buffered_direct);
    RecordProperty("temp_dir_o_direct", direct ? "yes" : "no");
    const auto a = readFile((dir_ / "direct.bin").string());
    const auto b = readFile((dir_ / "buffered.bin").string());
    const auto data = pattern();
    ASSERT_EQ(a.size(), 375 + data.size());
    EXPECT_TRUE(a == b) << "the two paths differ";
    EXPECT_EQ(a[0], 1);
    EXPECT_EQ(a[374], static_cast<std::uint8_t>(375));
    EXPECT_TRUE(std::equal(data.begin(), data.end(), a.begin() + 375));
    EXPECT_FALSE(fs::exists(dir_ / ".direct.bin.partial"));
}

TEST_F(ExportTest, ReadBackCatchesWhatTheMediumGotWrong) {
    for (const bool buffered_only : {false, true}) {
        WriteFaults faults;
        faults.buffered_only = buffered_only;
        // What a fake-capacity stick does: the data reads back different from what was written.
        faults.before_verify = [](const std::string& partial) {
            std::fstream f(partial, std::ios::in | std::ios::out | std::ios::binary);
            f.seekp(5u << 20);
            f.put('\x5a');
            f.put('\xa5');
        };
        const Status s = writeWithHeader(dir_ / "cloud.bin", faults);
        ASSERT_FALSE(s.isOk()) << "buffered_only " << buffered_only;
        EXPECT_NE(s.message().find("verification failed"), std::string::npos) << s.message();
        EXPECT_FALSE(fs::exists(dir_ / "cloud.bin"));
        EXPECT_FALSE(fs::exists(dir_ / ".cloud.bin.partial"));
    }
}

TEST_F(ExportTest, FailureOnTheIoThreadReachesTheCallerWithItsOffset) {
    WriteFaults faults;
    faults.before_write = [](std::uint64_t written) { return written >= (4u << 20) ? ENODEV : 0; };
    const Status s = writeWithHeader(dir_ / "cloud.bin", faults);
    ASSERT_FALSE(s.isOk());
    EXPECT_NE(s.message().find("write failed at byte 4194304"), std::string::npos) << s.message();
    EXPECT_NE(s.message().find("stick pulled?"), std::string::npos) << s.message();
    EXPECT_TRUE(fs::is_empty(dir_)) << "a partial file was left behind";
}

}  // namespace
}  // namespace handscan::exporter::testing
