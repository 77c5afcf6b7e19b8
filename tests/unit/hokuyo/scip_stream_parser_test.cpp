// ScipStreamParser: fragments split at every point, corrupted blocks, dropped bytes, garbage.
#include "handscan/hokuyo/scip_stream_parser.hpp"

#include <gtest/gtest.h>

#include <random>

#include "handscan/hokuyo/scip_codec.hpp"

namespace handscan::hokuyo {
namespace {

const ScanRequest kMe{'M', ScanEncoding::kThreeCharWithIntensity, 0, 1080, 1, 0, 0, ""};

ScanPayload makeScan(std::uint32_t t_ms, std::uint32_t seed) {
    ScanPayload s;
    s.timestamp_ms = t_ms;
    std::mt19937 rng(seed);
    for (int i = 0; i < 1081; ++i) {
        const std::uint32_t r = rng() % 61000;
        s.ranges.push_back(r);  // includes values < 23 (error codes)
        s.intensities.push_back(rng() % 10000);
    }
    return s;
}

struct Parsed {
    std::vector<ScipFrame> frames;
    std::vector<ScipFault> faults;
};

Parsed collect(std::vector<ScipEvent>& events) {
    Parsed p;
    for (auto& e : events) {
        if (auto* f = std::get_if<ScipFrame>(&e)) {
            p.frames.push_back(std::move(*f));
        } else {
            p.faults.push_back(std::get<ScipFault>(e));
        }
    }
    return p;
}

Parsed parse(const std::string& bytes, ScipStreamParser* parser_out = nullptr) {
    ScipStreamParser parser;
    std::vector<ScipEvent> events;
    parser.feed(bytes, events);
    if (parser_out) *parser_out = parser;
    return collect(events);
}

std::string handshakeReplies() {
    return encodeReply("SCIP2.0", "0E") +
           encodeKeyValueReply("VV", "00",
                               {{"VEND", "Hokuyo Automatic Co.,Ltd."},
                                {"PROD", "SOKUIKI Sensor TOP-URG UTM-30LX-EW"},
                                {"FIRM", "1.1.0(2012-12-06)"},
                                {"PROT", "SCIP 2.0"},
                                {"SERI", "H1234567"}}) +
           encodeKeyValueReply("PP", "00",
                               {{"MODL", "UTM-30LX-EW"},
                                {"DMIN", "23"},
                                {"DMAX", "60000"},
                                {"ARES", "1440"},
                                {"AMIN", "0"},
                                {"AMAX", "1080"},
                                {"AFRT", "540"},
                                {"SCAN", "2400"}}) +
           encodeReply("BM", "00") + encodeScanAck(kMe);
}

TEST(ScipStreamParser, HandshakeAndStreamInOneChunk) {
    const ScanPayload s1 = makeScan(1000, 1);
    const ScanPayload s2 = makeScan(1025, 2);
    const std::string bytes = handshakeReplies() + encodeScanFrame(kMe, s1) +
                              encodeScanFrame(kMe, s2) + encodeReply("QT", "00");
    ScipStreamParser parser;
    Parsed p = parse(bytes, &parser);
    ASSERT_TRUE(p.faults.empty()) << p.faults[0].message;
    ASSERT_EQ(p.frames.size(), 8u);
    EXPECT_EQ(p.frames[0].command, "SCIP2.0");
    EXPECT_TRUE(p.frames[0].ok());
    EXPECT_EQ(p.frames[2].item("SCAN"), "2400");
    EXPECT_EQ(p.frames[4].command, "ME");
    EXPECT_EQ(p.frames[4].status, "00");
    EXPECT_FALSE(p.frames[4].scan);
    ASSERT_TRUE(p.frames[5].scan);
    EXPECT_EQ(p.frames[5].scan->timestamp_ms, 1000u);
    EXPECT_EQ(p.frames[5].scan->ranges, s1.ranges);
    EXPECT_EQ(p.frames[5].scan->intensities, s1.intensities);
    EXPECT_EQ(p.frames[6].scan->ranges, s2.ranges);
    EXPECT_EQ(p.frames[7].command, "QT");
    EXPECT_EQ(parser.stats().scans, 2u);
    EXPECT_EQ(parser.stats().checksum_failures, 0u);
    EXPECT_EQ(parser.stats().resyncs, 0u);
}

// The TCP stream may split anywhere: every split point in two pieces gives the same frames.
TEST(ScipStreamParser, EverySplitPointGivesTheSameFrames) {
    const std::string bytes = encodeKeyValueReply("PP", "00", {{"DMIN", "23"}, {"SCAN", "2400"}}) +
                              encodeScanFrame(kMe, makeScan(77, 3));
    const Parsed whole = parse(bytes);
    ASSERT_EQ(whole.frames.size(), 2u);
    for (std::size_t cut = 0; cut <= bytes.size(); ++cut) {
        ScipStreamParser parser;
        std::vector<ScipEvent> events;
        parser.feed(std::string_view(bytes).substr(0, cut), events);
        parser.feed(std::string_view(bytes).substr(cut), events);
        Parsed p = collect(events);
        ASSERT_TRUE(p.faults.empty()) << "cut " << cut << ": " << p.faults[0].message;
        ASSERT_EQ(p.frames.size(), 2u) << "cut " << cut;
        ASSERT_EQ(p.frames[1].scan->ranges, whole.frames[1].scan->ranges) << "cut " << cut;
        ASSERT_EQ(p.frames[1].scan->intensities, whole.frames[1].scan->intensities);
    }
}

TEST(ScipStreamParser, ByteAtATimeAndRandomFragments) {
    std::string bytes = handshakeReplies();
    std::vector<ScanPayload> scans;
    for (std::uint32_t i = 0; i < 5; ++i) {
        scans.push_back(makeScan(i * 25, 10 + i));
        ScanRequest r = kMe;
        bytes += encodeScanFrame(r, scans.back());
    }
    std::mt19937 rng(42);
    for (int trial = 0; trial < 20; ++trial) {
        ScipStreamParser parser;
        std::vector<ScipEvent> events;
        std::size_t pos = 0;
        while (pos < bytes.size()) {
            const std::size_t n = trial == 0 ? 1 : 1 + rng() % 1500;
            parser.feed(std::string_view(bytes).substr(pos, n), events);
            pos += n;
        }
        Parsed p = collect(events);
        ASSERT_TRUE(p.faults.empty());
        ASSERT_EQ(p.frames.size(), 10u);
        for (int i = 0; i < 5; ++i) EXPECT_EQ(p.frames[5 + i].scan->ranges, scans[i].ranges);
        EXPECT_TRUE(parser.idle());
    }
}

// Returns the offset of the n-th data block line of `frame` (0 = first block after the timestamp).
std::size_t blockOffset(const std::string& frame, int n) {
    std::size_t pos = 0;
    for (int lf = 0; lf < 3 + n; ++lf) pos = frame.find('\n', pos) + 1;
    return pos;
}

TEST(ScipStreamParser, CorruptedBlockLosesOnlyThatScan) {
    const ScanPayload a = makeScan(0, 1), b = makeScan(25, 2), c = makeScan(50, 3);
    std::string fb = encodeScanFrame(kMe, b);
    fb[blockOffset(fb, 40) + 10] ^= 0x01;  // one bit in block 40
    ScipStreamParser parser;
    Parsed p = parse(encodeScanFrame(kMe, a) + fb + encodeScanFrame(kMe, c), &parser);
    ASSERT_EQ(p.frames.size(), 2u);
    EXPECT_EQ(p.frames[0].scan->ranges, a.ranges);
    EXPECT_EQ(p.frames[1].scan->ranges, c.ranges);
    ASSERT_EQ(p.faults.size(), 1u);
    EXPECT_EQ(p.faults[0].code, StatusCode::kChecksumError);
    EXPECT_NE(p.faults[0].message.find("after 2560 of 6486 data characters"), std::string::npos)
        << p.faults[0].message;
    EXPECT_EQ(parser.stats().checksum_failures, 1u);
    EXPECT_EQ(parser.stats().resyncs, 1u);
}

TEST(ScipStreamParser, DroppedByteInABlockLosesOnlyThatScan) {
    const ScanPayload a = makeScan(0, 1), b = makeScan(25, 2), c = makeScan(50, 3);
    std::string fb = encodeScanFrame(kMe, b);
    fb.erase(blockOffset(fb, 7) + 33, 1);
    Parsed p = parse(encodeScanFrame(kMe, a) + fb + encodeScanFrame(kMe, c));
    ASSERT_EQ(p.frames.size(), 2u);
    EXPECT_EQ(p.frames[1].scan->timestamp_ms, 50u);
    EXPECT_EQ(p.faults.size(), 1u);
}

TEST(ScipStreamParser, DroppedLineFeedInsideAScanLosesOnlyThatScan) {
    const ScanPayload a = makeScan(0, 1), b = makeScan(25, 2), c = makeScan(50, 3);
    std::string fb = encodeScanFrame(kMe, b);
    fb.erase(blockOffset(fb, 5) - 1, 1);  // two blocks merge into one overlong line
    Parsed p = parse(encodeScanFrame(kMe, a) + fb + encodeScanFrame(kMe, c));
    ASSERT_EQ(p.frames.size(), 2u);
    EXPECT_EQ(p.frames[1].scan->ranges, c.ranges);
    EXPECT_EQ(p.faults.size(), 1u);
}

TEST(ScipStreamParser, LostTerminatorLosesNothing) {
    const ScanPayload a = makeScan(0, 1), b = makeScan(25, 2);
    std::string fa = encodeScanFrame(kMe, a);
    fa.pop_back();  // the empty line that ends the frame
    ScipStreamParser parser;
    Parsed p = parse(fa + encodeScanFrame(kMe, b), &parser);
    EXPECT_TRUE(p.faults.empty());
    ASSERT_EQ(p.frames.size(), 2u);
    EXPECT_EQ(p.frames[0].scan->ranges, a.ranges);
    EXPECT_EQ(p.frames[1].scan->ranges, b.ranges);
    EXPECT_EQ(parser.stats().missing_terminators, 1u);
}

TEST(ScipStreamParser, GarbageAndPartialFramesThenResync) {
    const ScanPayload b = makeScan(25, 2);
    const std::string full = encodeScanFrame(kMe, b);
    // Connect mid-stream: the tail of a frame, binary garbage, a frame cut short, then a good one.
    std::string bytes = full.substr(3000) + std::string("\x00\xff\x13garbage\n\n", 13) +
                        full.substr(0, 2000) + "\n" + full;
    ScipStreamParser parser;
    Parsed p = parse(bytes, &parser);
    ASSERT_EQ(p.frames.size(), 1u);
    EXPECT_EQ(p.frames[0].scan->ranges, b.ranges);
    EXPECT_GE(p.faults.size(), 2u);
    EXPECT_GE(parser.stats().discarded_bytes, 100u);
}

TEST(ScipStreamParser, OverlongLineIsBoundedAndRecovered) {
    std::string bytes(100000, 'A');
    bytes += "\n\n" + encodeReply("QT", "00");
    ScipStreamParser parser;
    Parsed p = parse(bytes, &parser);
    ASSERT_EQ(p.frames.size(), 1u);
    EXPECT_EQ(p.frames[0].command, "QT");
    EXPECT_EQ(p.faults.size(), 1u);
}

TEST(ScipStreamParser, ErrorStatusAndRemainingCountEcho) {
    ScanRequest bad = kMe;
    bad.end_step = 2000;
    ScanRequest counted = kMe;
    counted.count = 3;
    std::string bytes = encodeScanAck(bad, "04") + encodeScanAck(counted);
    for (int remaining = 2; remaining >= 0; --remaining) {
        ScanRequest r = counted;
        r.count = remaining;
        bytes += encodeScanFrame(r, makeScan(static_cast<std::uint32_t>(remaining), 5));
    }
    Parsed p = parse(bytes);
    ASSERT_TRUE(p.faults.empty());
    ASSERT_EQ(p.frames.size(), 5u);
    EXPECT_FALSE(p.frames[0].ok());
    EXPECT_NE(p.frames[0].statusText().find("out of the sensor's range"), std::string::npos);
    EXPECT_EQ(p.frames[2].scan_request->count, 2);
    EXPECT_EQ(p.frames[4].scan_request->count, 0);
}

TEST(ScipStreamParser, GdAndMsFramesAndTimeReply) {
    ScanRequest gd{'G', ScanEncoding::kThreeChar, 0, 1080, 1, 0, 0, ""};
    ScanRequest ms{'M', ScanEncoding::kTwoChar, 100, 300, 2, 0, 0, "x"};
    ScanPayload s = makeScan(5, 6);
    s.intensities.clear();
    ScanPayload s2 = s;
    s2.ranges.resize(static_cast<std::size_t>(ms.valuesPerScan()));
    for (auto& r : s2.ranges) r %= 4096;
    const std::string bytes = encodeScanFrame(gd, s) + encodeScanFrame(ms, s2) +
                              encodeReply("TM1", "00", {encodeScipChars(123456, 4)});
    Parsed p = parse(bytes);
    ASSERT_TRUE(p.faults.empty()) << p.faults[0].message;
    ASSERT_EQ(p.frames.size(), 3u);
    EXPECT_EQ(p.frames[0].scan->ranges, s.ranges);
    EXPECT_TRUE(p.frames[0].scan->intensities.empty());
    EXPECT_EQ(p.frames[1].scan->ranges, s2.ranges);
    EXPECT_EQ(p.frames[1].scan_request->tag, "x");
    EXPECT_EQ(p.frames[2].command, "TM");
    ASSERT_EQ(p.frames[2].lines.size(), 1u);
    EXPECT_EQ(*decodeScipChars(p.frames[2].lines[0]), 123456u);
}

}  // namespace
}  // namespace handscan::hokuyo
