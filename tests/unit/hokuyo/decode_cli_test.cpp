// `handscan decode --device hokuyo FILE` against a golden output. The capture
// (tests/data/hokuyo/decode_small/capture.scip) is a short SCIP session made with the codec: the
// handshake replies, an ME acknowledgement, three 21-step scans of which the second has a corrupted
// block, and a fourth scan after a 50 ms gap. Regenerate both files with
//   HANDSCAN_UPDATE_GOLDEN=1 build/ci/tests/unit/hokuyo/hokuyo_decode_cli_tests
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "handscan/hokuyo/scip_codec.hpp"

namespace handscan::hokuyo {
namespace {

const std::filesystem::path kDir =
    std::filesystem::path(HANDSCAN_TEST_DATA_DIR) / "hokuyo" / "decode_small";
const std::filesystem::path kTool =
    std::filesystem::path(HANDSCAN_BINARY_DIR) / "firmware" / "cli" / "handscan";

std::string makeCapture() {
    const ScanRequest me{'M', ScanEncoding::kThreeCharWithIntensity, 530, 550, 1, 0, 0, ""};
    std::string raw =
        encodeReply("SCIP2.0", "0E") +
        encodeKeyValueReply("VV", "00",
                            {{"VEND", "Hokuyo Automatic Co.,Ltd."}, {"SERI", "H0000001"}}) +
        encodeKeyValueReply("PP", "00",
                            {{"MODL", "UTM-30LX-EW"},
                             {"DMIN", "23"},
                             {"DMAX", "60000"},
                             {"ARES", "1440"},
                             {"AMIN", "0"},
                             {"AMAX", "1080"},
                             {"AFRT", "540"},
                             {"SCAN", "2400"}}) +
        encodeReply("BM", "00") + encodeScanAck(me);
    const std::uint32_t times[] = {1000, 1025, 1050, 1100};
    for (int k = 0; k < 4; ++k) {
        ScanPayload p;
        p.timestamp_ms = times[k];
        for (int i = 0; i < me.valuesPerScan(); ++i) {
            p.ranges.push_back(i == 3 ? 7u : static_cast<std::uint32_t>(1000 + 10 * i + k));
            p.intensities.push_back(static_cast<std::uint32_t>(2000 + i));
        }
        std::string frame = encodeScanFrame(me, p);
        if (k == 1) frame[frame.find("\n", 26) - 5] ^= 0x02;  // corrupt the first data block
        raw += frame;
    }
    return raw + encodeReply("QT", "00");
}

std::string readFile(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

std::string runTool(const std::filesystem::path& capture) {
    const std::string cmd =
        kTool.string() + " decode --device hokuyo " + capture.string() + " 2>/dev/null";
    FILE* p = ::popen(cmd.c_str(), "r");
    if (p == nullptr) return {};
    std::string out;
    char buf[4096];
    for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, p)) > 0;) out.append(buf, n);
    EXPECT_EQ(::pclose(p), 0) << cmd;
    return out;
}

TEST(HokuyoDecodeCli, MatchesTheGoldenJsonLines) {
    if (!std::filesystem::exists(kTool)) GTEST_SKIP() << kTool << " not built";
    if (std::getenv("HANDSCAN_UPDATE_GOLDEN") != nullptr) {
        std::filesystem::create_directories(kDir);
        std::ofstream(kDir / "capture.scip", std::ios::binary) << makeCapture();
        std::ofstream(kDir / "expected.jsonl", std::ios::binary) << runTool(kDir / "capture.scip");
    }
    ASSERT_EQ(readFile(kDir / "capture.scip"), makeCapture())
        << "capture differs from the codec's output";
    const std::string out = runTool(kDir / "capture.scip");
    EXPECT_EQ(out, readFile(kDir / "expected.jsonl"));
    // Independent of the golden file: what must be in it.
    EXPECT_NE(out.find("\"command\":\"PP\""), std::string::npos);
    EXPECT_NE(out.find("\"t_device_ms\":1000"), std::string::npos);
    EXPECT_EQ(out.find("\"t_device_ms\":1025"), std::string::npos);  // the damaged scan is dropped
    EXPECT_NE(out.find("\"ranges_mm\":[1000,1010,1020,7,"), std::string::npos);
    EXPECT_NE(out.find("\"fault\""), std::string::npos);
    EXPECT_NE(out.find("{\"summary\":{\"device\":\"hokuyo\",\"messages\":9,\"checksum_failures\":1,"
                       "\"resyncs\":1,\"gaps\":2}}"),
              std::string::npos)
        << out.substr(out.rfind("{\"summary"));
}

}  // namespace
}  // namespace handscan::hokuyo
