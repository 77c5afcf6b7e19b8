// The receive side shared by HokuyoDevice and replay: replies and faults come back in stream order
// for the state machine, the PP reply both sets the geometry and reaches the state machine, and
// scans become LaserScans as soon as their frame is complete.
#include "handscan/hokuyo/scan_stream_decoder.hpp"

#include <gtest/gtest.h>

#include <variant>

namespace handscan::hokuyo {
namespace {

std::span<const std::uint8_t> bytesOf(const std::string& s) {
    return {reinterpret_cast<const std::uint8_t*>(s.data()), s.size()};
}

ScanPayload scanAt(std::uint32_t t_ms) {
    ScanPayload p;
    p.timestamp_ms = t_ms;
    for (int i = 0; i < 1081; ++i) {
        p.ranges.push_back(static_cast<std::uint32_t>(1000 + i));
        p.intensities.push_back(100);
    }
    return p;
}

TEST(ScanStreamDecoder, RepliesAndFaultsComeBackInOrderScansAreDecoded) {
    const ScanRequest me;  // ME0000108001000
    const std::string pp = encodeKeyValueReply("PP", "00",
                                               {{"MODL", "UTM-30LX-EW"},
                                                {"DMIN", "23"},
                                                {"DMAX", "60000"},
                                                {"ARES", "1440"},
                                                {"AMIN", "0"},
                                                {"AMAX", "1080"},
                                                {"AFRT", "540"},
                                                {"SCAN", "2400"}});
    std::string early = encodeScanFrame(me, scanAt(975));  // before the geometry is known
    std::string stream = early + pp + encodeReply("BM", "00") + encodeScanAck(me);
    for (std::uint32_t k = 0; k < 4; ++k) {
        if (k == 2) continue;  // lost: the next scan's timestamp shows the gap
        stream += encodeScanFrame(me, scanAt(1000 + 25 * k));
    }
    ScanStreamDecoder dec;
    std::vector<LaserScan> scans;
    std::vector<ScipEvent> events;
    const TimeNs t_rx = 20 * kNsPerSec;
    dec.feed(t_rx, bytesOf(stream), scans, events);
    ASSERT_EQ(scans.size(), 3u);
    EXPECT_EQ(scans[2].t_device_ms, 1075u);
    // The last scan's last step lies before its arrival by at least its frame's transmission.
    EXPECT_LT(scans[2].stepTime(scans[2].size() - 1), t_rx);
    ASSERT_EQ(events.size(), 4u);
    ASSERT_TRUE(std::holds_alternative<ScipFault>(events[0]));
    EXPECT_NE(std::get<ScipFault>(events[0]).message.find("before the PP reply"),
              std::string::npos);
    EXPECT_EQ(std::get<ScipFrame>(events[1]).command, "PP");
    EXPECT_EQ(std::get<ScipFrame>(events[2]).command, "BM");
    EXPECT_EQ(std::get<ScipFrame>(events[3]).echo, "ME0000108001000");
    ASSERT_TRUE(dec.parameters());
    EXPECT_EQ(dec.parameters()->amax, 1080);
    const ScanStreamStats s = dec.stats();
    EXPECT_EQ(s.scans, 3u);
    EXPECT_EQ(s.missed_scans, 1u);
    EXPECT_EQ(s.parser.checksum_failures, 0u);
}

}  // namespace
}  // namespace handscan::hokuyo
