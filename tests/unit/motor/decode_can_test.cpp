// `handscan decode --device can` on the real traces: one JSON line per frame + summary.
#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace {

std::vector<std::string> run(const std::string& args) {
    const std::string cmd =
        std::string(HANDSCAN_BINARY_DIR) + "/firmware/cli/handscan decode " + args + " 2>/dev/null";
    std::vector<std::string> lines;
    FILE* p = popen(cmd.c_str(), "r");
    if (p == nullptr) return lines;
    std::string cur;
    std::array<char, 4096> buf{};
    while (fgets(buf.data(), buf.size(), p) != nullptr) {
        cur += buf.data();
        if (!cur.empty() && cur.back() == '\n') {
            cur.pop_back();
            lines.push_back(cur);
            cur.clear();
        }
    }
    pclose(p);
    return lines;
}

const std::filesystem::path kCan = std::filesystem::path(HANDSCAN_SHARED_DATA_DIR) / "can";

TEST(DecodeCan, DecodesTheRealCiA402BringUp) {
    const auto path = kCan / "ros2_canopen_issue331_candump-L.log";
    if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " not present";
    const auto out = run("--device can " + path.string());
    ASSERT_EQ(out.size(), 29u);
    EXPECT_EQ(out[0],
              "{\"t_host_ns\":null,\"t_log_ns\":1730301035277560000,\"interface\":\"can0\",\"id\":"
              "\"701\",\"extended\":false,"
              "\"remote\":false,\"error_frame\":false,\"fd\":false,\"len\":1,\"data\":\"00\","
              "\"canopen\":{\"function\":\"heartbeat\","
              "\"node\":1,\"state\":\"boot_up\"}}");
    EXPECT_NE(out[21].find(
                  "\"sdo\":\"write\",\"index\":\"60FF\",\"subindex\":0,\"value\":2000,\"size\":4"),
              std::string::npos)
        << out[21];
    EXPECT_NE(out[24].find("\"statusword\":\"0x0237\",\"cia402_state\":\"operation_enabled\""),
              std::string::npos)
        << out[24];
    EXPECT_EQ(out.back(),
              "{\"summary\":{\"device\":\"can\",\"messages\":28,\"checksum_failures\":0,"
              "\"resyncs\":0,\"gaps\":0}}");
}

TEST(DecodeCan, ReportsBadLinesAndTpdoGaps) {
    const auto file = std::filesystem::temp_directory_path() /
                      ("decode_can_test_" + std::to_string(::getpid()) + ".log");
    {
        std::ofstream o(file);
        o << "(1700000000.000000) can0 181#00000000\n"
          << "(1700000000.001000) can0 181#10000000\n"
          << "(1700000000.002000) can0 181#2000000\n"   // odd digit count: bad line
          << "(1700000000.005000) can0 181#50000000\n"  // 4 ms after the last good one: a gap
          << "(1700000000.006000) can0 081#1000010000000000\n";
    }
    const auto out = run("--device can " + file.string());
    std::filesystem::remove(file);
    ASSERT_EQ(out.size(), 6u);
    EXPECT_NE(out[1].find("\"position\":16"), std::string::npos) << out[1];
    EXPECT_NE(out[2].find("\"line\":3,\"error\":\"candump frame: data must be pairs of hex digits"),
              std::string::npos)
        << out[2];
    EXPECT_NE(out[4].find("\"error_code\":\"0x0010\",\"error_register\":\"0x01\""),
              std::string::npos)
        << out[4];
    EXPECT_EQ(out.back(),
              "{\"summary\":{\"device\":\"can\",\"messages\":4,\"checksum_failures\":0,\"resyncs\":"
              "1,\"gaps\":1}}");
}

}  // namespace
