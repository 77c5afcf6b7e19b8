// The receive side shared by XsensDevice and replay: samples on the host clock from any chunking,
// a device restart (WakeUp) starting the time mapping afresh, and frames left over behind a reply
// stamped with the time they arrived.
#include "handscan/xsens/imu_stream_decoder.hpp"

#include <gtest/gtest.h>

#include "handscan/xsens/mtdata2.hpp"
#include "handscan/xsens/xbus_messages.hpp"

namespace handscan::xsens {
namespace {

std::vector<std::uint8_t> packet(std::uint16_t counter, std::uint32_t stf) {
    MtData2Builder b;
    b.packetCounter(counter)
        .sampleTimeFine(stf)
        .acceleration({0.1, 0.2, 9.81})
        .rateOfTurn({0.01, 0.02, 0.03});
    b.statusByte(0x03);
    return b.frame();
}

void append(std::vector<std::uint8_t>& to, const std::vector<std::uint8_t>& bytes) {
    to.insert(to.end(), bytes.begin(), bytes.end());
}

TEST(ImuStreamDecoder, RestartStartsTheTimeMappingAfresh) {
    ImuStreamDecoder dec("Xsens test");
    std::vector<std::string> problems;
    dec.onProblem([&](const std::string& p) { problems.push_back(p); });
    std::vector<ImuSample> out;
    const TimeNs t0 = 50 * kNsPerSec;
    for (std::uint16_t k = 0; k < 200; ++k) {  // 200 Hz, 1 ms after each sample instant
        dec.feed(t0 + k * 5 * kNsPerMs + kNsPerMs, packet(k, 1'000'000u + 50u * k), out);
    }
    // Power glitch: WakeUp, then counters and SampleTimeFine from 0, one second later.
    const TimeNs t1 = t0 + 2 * kNsPerSec;
    dec.feed(t1, encodeFrame(MessageId::kWakeUp), out);
    for (std::uint16_t k = 0; k < 50; ++k)
        dec.feed(t1 + k * 5 * kNsPerMs + kNsPerMs, packet(k, 50u * k), out);
    ASSERT_EQ(out.size(), 250u);
    const ImuStreamStats s = dec.stats();
    EXPECT_EQ(s.restarts, 1u);
    EXPECT_EQ(s.gaps, 0u);               // the counter restarting at 0 is not a gap
    EXPECT_EQ(dec.clock().resets(), 0);  // a fresh mapping, not a clock fault
    EXPECT_EQ(out[249].t_host, t1 + kNsPerMs + 49 * 5 * kNsPerMs);  // on the new device clock
    EXPECT_EQ(out[249].status_word, 0x03u);  // from StatusByte when there is no StatusWord
    ASSERT_EQ(problems.size(), 1u);
    EXPECT_NE(problems[0].find("Xsens test restarted (WakeUp)"), std::string::npos) << problems[0];
    EXPECT_EQ(dec.lastProblem(), problems[0]);
}

TEST(ImuStreamDecoder, FramesBehindAReplyKeepTheirArrivalTime) {
    // A state machine waiting for GoToMeasurementAck reads it together with the first packets.
    ImuStreamDecoder dec;
    std::vector<std::uint8_t> chunk = encodeFrame(MessageId::kGoToMeasurementAck);
    append(chunk, packet(7, 20'000));
    append(chunk, packet(8, 20'050));
    const TimeNs t_rx = 3 * kNsPerSec;
    dec.feedRaw(chunk);
    auto ack = dec.nextFrame();
    ASSERT_TRUE(ack);
    EXPECT_EQ(ack->mid, toByte(MessageId::kGoToMeasurementAck));
    std::vector<ImuSample> out;
    dec.decodePending(t_rx, out);
    ASSERT_EQ(out.size(), 2u);
    EXPECT_EQ(out[0].t_host, t_rx);
    EXPECT_EQ(out[1].t_host, t_rx);
    EXPECT_EQ(out[1].packet_counter, 8);
    // Split anywhere, the same samples come out.
    ImuStreamDecoder whole, pieces;
    std::vector<std::uint8_t> stream;
    for (std::uint16_t k = 0; k < 40; ++k) append(stream, packet(k, 50u * k));
    std::vector<ImuSample> a, b;
    whole.feed(t_rx, stream, a);
    for (std::size_t i = 0; i < stream.size(); i += 7) {
        pieces.feed(t_rx, std::span(stream).subspan(i, std::min<std::size_t>(7, stream.size() - i)),
                    b);
    }
    ASSERT_EQ(a.size(), 40u);
    ASSERT_EQ(b.size(), a.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
        EXPECT_EQ(a[i].t_host, b[i].t_host);
        EXPECT_EQ(a[i].t_device_ticks, b[i].t_device_ticks);
    }
}

}  // namespace
}  // namespace handscan::xsens
