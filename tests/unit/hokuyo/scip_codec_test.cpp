// SCIP 2.0 codec: the specification's worked examples and a real UTM-30LX-EW PP reply / URG-04LX
// VV+BM transcript (../shared/data/hokuyo), plus byte-exact layout of the frames we encode.
#include "handscan/hokuyo/scip_codec.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "handscan/hokuyo/scip_stream_parser.hpp"

namespace handscan::hokuyo {
namespace {

const std::filesystem::path kGolden =
    std::filesystem::path(HANDSCAN_SHARED_DATA_DIR) / "hokuyo" / "scip2_golden_vectors.txt";

// Reads the golden vector file: directive lines ("DECODE3 ...") and transcripts (a line that is a
// bare command, up to and including the next empty line), keyed by the command.
struct GoldenFile {
    std::vector<std::string> directives;
    std::map<std::string, std::string> transcripts;
};

GoldenFile readGolden() {
    GoldenFile g;
    std::ifstream in(kGolden);
    std::string line;
    std::string current;
    std::string transcript;
    while (std::getline(in, line)) {
        if (!current.empty()) {
            transcript += line + "\n";
            if (line.empty()) {
                g.transcripts[current] = transcript;
                current.clear();
            }
            continue;
        }
        if (line.empty() || line[0] == '#') continue;
        if (line == "PP" || line == "VV" || line == "BM") {
            current = line;
            transcript = line + "\n";
            continue;
        }
        g.directives.push_back(line);
    }
    return g;
}

// The quoted string of a directive: CHECKSUM  "Hokuyo" -> 'o'.
std::string quotedField(const std::string& line) {
    const auto a = line.find('"');
    const auto b = line.find('"', a + 1);
    return line.substr(a + 1, b - a - 1);
}

TEST(ScipGolden, ChecksumAndDecodersFromTheSpecification) {
    if (!std::filesystem::exists(kGolden)) GTEST_SKIP() << kGolden << " absent";
    const GoldenFile g = readGolden();
    int checked = 0;
    for (const auto& d : g.directives) {
        std::istringstream s(d);
        std::string kind;
        s >> kind;
        const std::string text = quotedField(d);
        const std::string rhs = d.substr(d.find("->") + 3);
        if (kind == "CHECKSUM") {
            EXPECT_EQ(scipChecksum(text), rhs[1]) << d;
            ++checked;
        } else if (kind.rfind("DECODE", 0) == 0) {
            const std::uint32_t want = std::stoul(rhs);
            auto got = decodeScipChars(text);
            ASSERT_TRUE(got) << got.status().message();
            EXPECT_EQ(*got, want) << d;
            EXPECT_EQ(encodeScipChars(want, static_cast<int>(text.size())), text) << d;
            ++checked;
        } else if (kind == "PARAMLINE") {
            auto kv = parseKeyValueLine(
                d.substr(d.find('"') + 1, d.find('"', d.find('"') + 1) - d.find('"') - 1));
            ASSERT_TRUE(kv) << kv.status().message();
            EXPECT_EQ(kv->first, "PROT");
            EXPECT_EQ(kv->second, "SCIP 2.0");
            ++checked;
        }
    }
    EXPECT_EQ(checked, 5);
}

std::vector<ScipFrame> parseAll(const std::string& bytes, ScipStreamParser& parser) {
    std::vector<ScipEvent> events;
    parser.feed(bytes, events);
    std::vector<ScipFrame> frames;
    for (auto& e : events) {
        if (auto* f = std::get_if<ScipFrame>(&e)) {
            frames.push_back(std::move(*f));
        } else {
            ADD_FAILURE() << std::get<ScipFault>(e).message;
        }
    }
    return frames;
}

TEST(ScipGolden, RealUtm30lxPpReplyParsesAndReencodesByteExact) {
    if (!std::filesystem::exists(kGolden)) GTEST_SKIP() << kGolden << " absent";
    const GoldenFile g = readGolden();
    ASSERT_TRUE(g.transcripts.count("PP"));
    const std::string& pp = g.transcripts.at("PP");
    ScipStreamParser parser;
    auto frames = parseAll(pp, parser);
    ASSERT_EQ(frames.size(), 1u);
    const ScipFrame& f = frames[0];
    EXPECT_EQ(f.command, "PP");
    EXPECT_EQ(f.status, "00");
    EXPECT_TRUE(f.ok());
    EXPECT_EQ(f.item("MODL"), "UTM-30LX-EW");
    EXPECT_EQ(f.item("DMIN"), "23");
    EXPECT_EQ(f.item("DMAX"), "60000");
    EXPECT_EQ(f.item("ARES"), "1440");
    EXPECT_EQ(f.item("AMIN"), "0");
    EXPECT_EQ(f.item("AMAX"), "1080");
    EXPECT_EQ(f.item("AFRT"), "540");
    EXPECT_EQ(f.item("SCAN"), "2400");
    // The encoder (used by the simulator and the fake sensor) reproduces the sensor's bytes.
    EXPECT_EQ(encodeKeyValueReply("PP", "00", f.items), pp);
    EXPECT_EQ(parser.stats().checksum_failures, 0u);
}

TEST(ScipGolden, RealVvAndBmTranscript) {
    if (!std::filesystem::exists(kGolden)) GTEST_SKIP() << kGolden << " absent";
    const GoldenFile g = readGolden();
    ScipStreamParser parser;
    auto frames = parseAll(g.transcripts.at("VV") + g.transcripts.at("BM"), parser);
    ASSERT_EQ(frames.size(), 2u);
    EXPECT_EQ(frames[0].command, "VV");
    EXPECT_EQ(frames[0].item("VEND"), "Hokuyo Automatic Co.,Ltd.");
    EXPECT_EQ(frames[0].item("SERI"), "H1510998");
    EXPECT_EQ(frames[0].item("FIRM"), "3.4.03(17/Dec./2012)");
    EXPECT_EQ(frames[0].item("PROT"), "SCIP 2.0");
    EXPECT_EQ(encodeKeyValueReply("VV", "00", frames[0].items), g.transcripts.at("VV"));
    EXPECT_EQ(frames[1].command, "BM");
    EXPECT_EQ(frames[1].status, "02");
    EXPECT_TRUE(frames[1].ok());  // laser already on is fine
    EXPECT_NE(frames[1].statusText().find("already on"), std::string::npos);
    EXPECT_EQ(encodeReply("BM", "02"), g.transcripts.at("BM"));
}

TEST(ScipCodec, StatusSums) {
    EXPECT_EQ(scipChecksum("00"), 'P');
    EXPECT_EQ(scipChecksum("99"), 'b');
    EXPECT_EQ(scipChecksum("02"), 'R');
    EXPECT_EQ(encodeReply("QT", "00"), "QT\n00P\n\n");
}

TEST(ScipCodec, CharEncodingRoundTripsAtEveryWidthAndBoundary) {
    for (int w = 2; w <= 4; ++w) {
        const std::uint32_t max = (1u << (6 * w)) - 1;
        for (std::uint32_t v : {0u, 1u, 63u, 64u, 4095u, 4096u, 60000u, 65533u, max - 1, max}) {
            if (v > max) continue;
            const std::string s = encodeScipChars(v, w);
            ASSERT_EQ(s.size(), static_cast<std::size_t>(w));
            auto back = decodeScipChars(s);
            ASSERT_TRUE(back);
            EXPECT_EQ(*back, v) << "width " << w;
        }
        EXPECT_EQ(encodeScipChars(max + 1, w), encodeScipChars(max, w)) << "clamped";
    }
    EXPECT_FALSE(decodeScipChars("0\x7F"));
    EXPECT_FALSE(decodeScipChars("0/"));
    EXPECT_FALSE(decodeScipChars(""));
    EXPECT_FALSE(decodeScipChars("00000"));
}

TEST(ScipCodec, CommandsAreByteExact) {
    EXPECT_EQ(encodeScip20Command(), "SCIP2.0\n");
    EXPECT_EQ(encodeVersionCommand(), "VV\n");
    EXPECT_EQ(encodeParametersCommand(), "PP\n");
    EXPECT_EQ(encodeStatusInfoCommand(), "II\n");
    EXPECT_EQ(encodeLaserOnCommand(), "BM\n");
    EXPECT_EQ(encodeQuitCommand(), "QT\n");
    EXPECT_EQ(encodeResetCommand(), "RS\n");
    EXPECT_EQ(encodeTimeAdjustCommand(1), "TM1\n");
    EXPECT_EQ(encodeCommand("VV", "abc"), "VV;abc\n");
    ScanRequest md{'M', ScanEncoding::kThreeChar, 0, 1080, 1, 0, 0, ""};
    EXPECT_EQ(encodeScanCommand(md), "MD0000108001000\n");  // the spec's example
    ScanRequest me{'M', ScanEncoding::kThreeCharWithIntensity, 44, 725, 3, 2, 15, "t1"};
    EXPECT_EQ(encodeScanCommand(me), "ME0044072503215;t1\n");
    ScanRequest gs{'G', ScanEncoding::kTwoChar, 100, 200, 0, 0, 0, ""};
    EXPECT_EQ(encodeScanCommand(gs), "GS0100020000\n");
    for (const auto& r : {md, me, gs}) {
        auto back = parseScanEcho(encodeScanEcho(r));
        ASSERT_TRUE(back) << back.status().message();
        EXPECT_EQ(*back, r);
    }
    EXPECT_EQ(me.valuesPerScan(), (725 - 44) / 3 + 1);
    EXPECT_FALSE(parseScanEcho("ME00001080010"));    // too short
    EXPECT_FALSE(parseScanEcho("ME00X0108001000"));  // not digits
    EXPECT_FALSE(parseScanEcho("MX0000108001000"));  // not a scan symbol
}

TEST(ScipCodec, MeFrameLayoutBlocksSumsAndStraddlingValues) {
    ScanRequest me{'M', ScanEncoding::kThreeCharWithIntensity, 0, 1080, 1, 0, 0, ""};
    ScanPayload scan;
    scan.timestamp_ms = 0xABCDEF;
    for (std::uint32_t i = 0; i < 1081; ++i) {
        scan.ranges.push_back(i < 5 ? i + 1
                                    : 100 + i * 53);  // first steps carry error codes < DMIN
        scan.intensities.push_back(1000 + i);
    }
    const std::string frame = encodeScanFrame(me, scan);
    std::vector<std::string> lines;
    std::istringstream s(frame);
    for (std::string l; std::getline(s, l);) lines.push_back(l);
    ASSERT_GE(lines.size(), 5u);
    EXPECT_EQ(lines[0], "ME0000108001000");
    EXPECT_EQ(lines[1], "99b");
    ASSERT_EQ(lines[2].size(), 5u);
    EXPECT_EQ(*decodeScipChars(lines[2].substr(0, 4)), 0xABCDEFu);
    // 1081 x 6 = 6486 characters = 101 full blocks + one of 22.
    const std::size_t blocks = lines.size() - 4;
    EXPECT_EQ(blocks, 102u);
    std::string data;
    for (std::size_t i = 3; i < 3 + blocks; ++i) {
        auto p = stripDataLineSum(lines[i]);
        ASSERT_TRUE(p) << p.status().message();
        EXPECT_EQ(p->size(), i + 1 < 3 + blocks ? 64u : 22u);
        data.append(*p);
    }
    EXPECT_TRUE(lines.back().empty());
    EXPECT_EQ(frame.substr(frame.size() - 2), "\n\n");
    // Value 10 starts at character 60 and straddles the first two blocks.
    EXPECT_EQ(*decodeScipChars(std::string_view(data).substr(60, 3)), scan.ranges[10]);
    EXPECT_EQ(data, encodeScanData(me.encoding, scan));
}

TEST(ScipCodec, KeyValueSumOverNMinus1OrNMinus2) {
    // UTM-30LX-EW style: sum over "KEY:VALUE" (n-2); other sensors: sum including ';' (n-1).
    const std::string kv = "DMIN:23";
    auto a = parseKeyValueLine(kv + ";" + scipChecksum(kv));
    auto b = parseKeyValueLine(kv + ";" + scipChecksum(kv + ";"));
    ASSERT_TRUE(a);
    ASSERT_TRUE(b);
    EXPECT_EQ(a->second, "23");
    EXPECT_EQ(b->second, "23");
    auto c = parseKeyValueLine("DMIN:23;x");
    ASSERT_FALSE(c);
    EXPECT_EQ(c.status().code(), StatusCode::kChecksumError);
    EXPECT_NE(c.status().message().find("DMIN:23"), std::string::npos);
}

TEST(ScipCodec, StatusCodesAreExplained) {
    EXPECT_TRUE(isSuccessStatus("ME", "99"));
    EXPECT_TRUE(isSuccessStatus("SCIP2.0", "0E"));
    EXPECT_FALSE(isSuccessStatus("GD", "99"));
    EXPECT_FALSE(isSuccessStatus("ME", "04"));
    EXPECT_NE(describeStatus("ME", "04").find("end step out of the sensor's range"),
              std::string::npos);
    EXPECT_NE(describeStatus("GD", "10").find("send BM"), std::string::npos);
    EXPECT_NE(describeStatus("MD", "55").find("hardware fault"), std::string::npos);
    EXPECT_NE(describeStatus("BM", "01").find("laser malfunction"), std::string::npos);
    EXPECT_NE(describeStatus("ME", "30").find("stopped"), std::string::npos);
}

}  // namespace
}  // namespace handscan::hokuyo
