// `handscan decode --device xsens` output: one JSON line per message, items named as in the XDI
// table, values in SI units, golden values reproduced digit for digit, summary counts.
#include "handscan/xsens/xsens_json.hpp"

#include <gtest/gtest.h>

#include <sstream>

#include "handscan/xsens/mtdata2.hpp"
#include "handscan/xsens/xbus_messages.hpp"
#include "xsens_test_files.hpp"

namespace handscan::xsens {
namespace {

std::vector<std::string> splitLines(const std::string& text) {
    std::vector<std::string> lines;
    std::istringstream in(text);
    for (std::string l; std::getline(in, l);) lines.push_back(l);
    return lines;
}

// The golden value of `key` (e.g. "X") in item `item` of every block that has it.
std::vector<std::string> goldenValues(const std::filesystem::path& file, const std::string& item,
                                      const std::string& key) {
    std::vector<std::string> values;
    bool in_item = false;
    for (const auto& line : test::readLines(file)) {
        if (line.rfind("  ", 0) != 0) {
            in_item = line.rfind(item + "(", 0) == 0;
            continue;
        }
        if (in_item && line.rfind("  " + key + ":", 0) == 0)
            values.push_back(line.substr(3 + key.size()));
    }
    return values;
}

class XsensJsonCapture : public ::testing::TestWithParam<int> {};

TEST_P(XsensJsonCapture, EveryMessageIsALineWithTheGoldenDigits) {
    const auto dir = test::xsensDataDir() / "mtig710" / std::to_string(GetParam());
    if (!std::filesystem::exists(dir)) GTEST_SKIP() << dir << " absent";
    XsensJsonDecoder decoder;
    std::ostringstream out;
    const auto bytes = test::readBytes(dir / "output.bin");
    // Fed in odd-sized chunks, as a recording's messages would be.
    for (std::size_t off = 0; off < bytes.size(); off += 333) {
        decoder.feed(static_cast<TimeNs>(off),
                     std::span(bytes).subspan(off, std::min<std::size_t>(333, bytes.size() - off)),
                     out);
    }
    const auto lines = splitLines(out.str());
    ASSERT_EQ(lines.size(), 100u);
    const auto s = decoder.summary();
    EXPECT_EQ(s.messages, 100u);
    EXPECT_EQ(s.checksum_failures, 0u);
    EXPECT_EQ(s.resyncs, 0u);
    EXPECT_EQ(s.gaps, 0u);
    std::vector<std::string> acc_lines;
    for (const auto& l : lines) {
        EXPECT_EQ(l.front(), '{');
        EXPECT_EQ(l.back(), '}');
        EXPECT_NE(l.find("\"message\":\"MTData2\""), std::string::npos);
        EXPECT_NE(l.find("\"t_device_s\":"), std::string::npos);
        EXPECT_NE(l.find("\"PacketCounter\":"), std::string::npos);
        EXPECT_EQ(l.find("Unknown"), std::string::npos) << l;
        EXPECT_EQ(l.find("problem"), std::string::npos) << l;
        if (l.find("\"Acceleration\":") != std::string::npos) acc_lines.push_back(l);
    }
    // Acceleration is in m/s^2 on the wire already: the golden digits must appear verbatim.
    for (const std::string axis : {"X", "Y", "Z"}) {
        const auto golden = goldenValues(dir / "output.golden", "Acceleration", axis);
        if (GetParam() == 5) {
            EXPECT_TRUE(golden.empty());
            continue;
        }
        ASSERT_EQ(golden.size(), acc_lines.size());
        const std::string key =
            "\"" + std::string(1, static_cast<char>(std::tolower(axis[0]))) + "\":";
        for (std::size_t i = 0; i < golden.size(); ++i) {
            const auto at = acc_lines[i].find("\"Acceleration\":");
            EXPECT_NE(acc_lines[i].find(key + golden[i], at), std::string::npos)
                << golden[i] << "\n"
                << acc_lines[i];
        }
    }
}

INSTANTIATE_TEST_SUITE_P(MtiG710, XsensJsonCapture, ::testing::Values(1, 2, 3, 5));

TEST(XsensJson, DamageIsCountedInTheSummary) {
    const auto file = test::xsensDataDir() / "mtig710" / "1" / "output.bin";
    if (!std::filesystem::exists(file)) GTEST_SKIP();
    auto bytes = test::readBytes(file);
    bytes.erase(bytes.begin() + 1000);  // inside the 7th frame
    XsensJsonDecoder decoder;
    std::ostringstream out;
    decoder.feed(0, bytes, out);
    const auto s = decoder.summary();
    EXPECT_EQ(s.messages, 99u);
    EXPECT_EQ(s.gaps, 1u);
    EXPECT_EQ(s.lost_packets, 1u);
    EXPECT_GE(s.resyncs, 1u);
    EXPECT_NE(out.str().find("\"gap\":1"), std::string::npos);
}

TEST(XsensJson, ControlMessagesUnknownItemsAndSiUnits) {
    std::vector<std::uint8_t> stream;
    auto add = [&](const std::vector<std::uint8_t>& f) {
        stream.insert(stream.end(), f.begin(), f.end());
    };
    add(encodeFrame(MessageId::kGoToConfigAck));
    add(encodeFrame(MessageId::kDeviceId, encodeDeviceId(0x037003F8)));
    add(encodeErrorFrame(ErrorCode::kInvalidPeriod));
    const std::vector<OutputConfigEntry> cfg{{0x1020, 0xFFFF}, {0x4020, 200}};
    add(encodeFrame(MessageId::kSetOutputConfigurationAck, encodeOutputConfiguration(cfg)));
    MtData2Builder b;
    const double euler_deg[3] = {90.0, -45.0, 180.0};
    const std::vector<std::uint8_t> junk{0xDE, 0xAD};
    b.packetCounter(1)
        .sampleTimeFine(10000)
        .reals(withFormat(xdi::kEulerAngles, Precision::kFloat64, CoordSys::kNed), euler_deg)
        .raw(0x9990, junk);
    add(b.frame());
    XsensJsonDecoder decoder;
    std::ostringstream out;
    decoder.feed(123, stream, out);
    const auto lines = splitLines(out.str());
    ASSERT_EQ(lines.size(), 5u);
    EXPECT_EQ(lines[0], R"({"t_host_ns":123,"message":"GoToConfigAck"})");
    EXPECT_EQ(lines[1], R"({"t_host_ns":123,"message":"DeviceID","device_id":"037003F8"})");
    EXPECT_NE(lines[2].find(R"("message":"Error","code":3,"error":"InvalidPeriod (0x03))"),
              std::string::npos);
    EXPECT_NE(lines[3].find(
                  R"("outputs":[{"name":"PacketCounter","xdi":"0x1020","rate_hz":"every packet"},)"
                  R"({"name":"Acceleration","xdi":"0x4020","rate_hz":200}])"),
              std::string::npos)
        << lines[3];
    EXPECT_NE(lines[4].find(R"("t_device_s":1,)"), std::string::npos) << lines[4];
    EXPECT_NE(
        lines[4].find(R"("EulerAngles":{"roll":1.5707963267948966,"pitch":-0.7853981633974483,)"
                      R"("yaw":3.141592653589793,"unit":"rad","format":"Float64","coords":"NED"})"),
        std::string::npos)
        << lines[4];
    EXPECT_NE(lines[4].find(R"("Unknown_0x9990":{"xdi":"0x9990","raw":"dead","problem":)"),
              std::string::npos)
        << lines[4];
}

}  // namespace
}  // namespace handscan::xsens

namespace handscan::xsens {
namespace {

// Found by fuzz_xbus_parser: a UtcTime with nanoseconds >= 2^31 overflowed an int conversion.
TEST(XsensJson, UtcTimeWithHugeNanosecondsIsPrintedNotUndefined) {
    MtData2Builder b;
    const std::vector<std::uint8_t> utc{0xFF, 0xFF, 0xFF, 0xFF, 0x07, 0xE3,
                                        1,    20,   13,   47,   24,   0x37};
    b.raw(xdi::kUtcTime, utc);
    XsensJsonDecoder decoder;
    std::ostringstream out;
    decoder.feed(0, b.frame(), out);
    EXPECT_NE(out.str().find(R"("ns":4294967295,)"), std::string::npos) << out.str();
    EXPECT_NE(out.str().find(R"("iso":"2019-01-20T13:47:24.4294967295Z")"), std::string::npos)
        << out.str();
}

}  // namespace
}  // namespace handscan::xsens
