// The recorded-stream decoders give back what the codecs' encode side (what the devices and the
// simulator send) put in, with host times from the devices' clocks.
#include <gtest/gtest.h>

#include <random>

#include "handscan/hokuyo/scan_stream_decoder.hpp"
#include "handscan/hokuyo/scip_codec.hpp"
#include "handscan/xsens/imu_stream_decoder.hpp"
#include "handscan/xsens/mtdata2.hpp"

namespace handscan::sources {
namespace {

std::span<const std::uint8_t> bytesOf(const std::string& s) {
    return {reinterpret_cast<const std::uint8_t*>(s.data()), s.size()};
}

std::string utm30PpReply() {
    return hokuyo::encodeKeyValueReply("PP", "00",
                                       {{"MODL", "UTM-30LX-EW"},
                                        {"DMIN", "23"},
                                        {"DMAX", "60000"},
                                        {"ARES", "1440"},
                                        {"AMIN", "0"},
                                        {"AMAX", "1080"},
                                        {"AFRT", "540"},
                                        {"SCAN", "2400"}});
}

TEST(RecordedHokuyoStream, ScansFromAStreamSplitAnywhere) {
    hokuyo::ScanRequest req;  // ME0000108001000
    std::string stream = utm30PpReply() + hokuyo::encodeScanAck(req);
    std::vector<hokuyo::ScanPayload> sent;
    for (int k = 0; k < 20; ++k) {
        hokuyo::ScanPayload p;
        p.timestamp_ms = 1000 + 25 * static_cast<std::uint32_t>(k);
        for (int i = 0; i < 1081; ++i) {
            p.ranges.push_back(
                i == 7 ? 5 : static_cast<std::uint32_t>(1000 + i + k));  // 5 < DMIN: error code
            p.intensities.push_back(static_cast<std::uint32_t>(2000 + i));
        }
        sent.push_back(p);
        stream += hokuyo::encodeScanFrame(req, p);
    }
    hokuyo::ScanStreamDecoder dec;
    std::vector<LaserScan> out;
    std::mt19937 rng(5);
    std::size_t pos = 0;
    TimeNs t = 10 * kNsPerSec;
    while (pos < stream.size()) {  // TCP segments of random size
        const std::size_t n = std::min<std::size_t>(stream.size() - pos, 1 + rng() % 1500);
        dec.feed(t, bytesOf(stream).subspan(pos, n), out);
        pos += n;
        t += kNsPerMs;
    }
    ASSERT_EQ(out.size(), sent.size());
    ASSERT_TRUE(dec.parameters().has_value());
    EXPECT_EQ(dec.parameters()->afrt, 540);
    for (std::size_t k = 0; k < out.size(); ++k) {
        ASSERT_EQ(out[k].ranges_m.size(), 1081u);
        EXPECT_EQ(out[k].t_device_ms, sent[k].timestamp_ms);
        EXPECT_FLOAT_EQ(out[k].ranges_m[100], (1000 + 100 + static_cast<float>(k)) * 1e-3f);
        EXPECT_TRUE(std::isnan(out[k].ranges_m[7]));
        EXPECT_EQ(out[k].error_codes[7], 5);
        EXPECT_EQ(out[k].intensities[3], 2003);
        EXPECT_NEAR(out[k].angle_min_rad, -540 * 2 * M_PI / 1440, 1e-12);
        EXPECT_NEAR(static_cast<double>(out[k].step_period_ns), 60e9 / 2400 / 1440, 1.0);
    }
    const StreamCounters c = dec.counters();
    EXPECT_EQ(c.messages, 20u);
    EXPECT_EQ(c.checksum_failures, 0u);
    EXPECT_EQ(c.gaps, 0u);
}

TEST(RecordedHokuyoStream, CorruptBlockLosesOnlyThatScanAndCountsTheGap) {
    hokuyo::ScanRequest req;
    std::string stream = utm30PpReply();
    for (int k = 0; k < 3; ++k) {
        hokuyo::ScanPayload p;
        p.timestamp_ms = 25 * static_cast<std::uint32_t>(k);
        p.ranges.assign(1081, 1234);
        p.intensities.assign(1081, 99);
        std::string frame = hokuyo::encodeScanFrame(req, p);
        if (k == 1) frame[frame.size() / 2] ^= 0x01;  // a flipped bit in a data block
        stream += frame;
    }
    hokuyo::ScanStreamDecoder dec;
    std::vector<LaserScan> out;
    dec.feed(kNsPerSec, bytesOf(stream), out);
    ASSERT_EQ(out.size(), 2u);
    EXPECT_EQ(out[1].t_device_ms, 50u);
    EXPECT_GE(dec.counters().checksum_failures, 1u);
    EXPECT_EQ(dec.counters().gaps, 1u);
}

TEST(RecordedHokuyoStream, ScanBeforeParametersIsReportedNotGuessed) {
    hokuyo::ScanRequest req;
    hokuyo::ScanPayload p;
    p.ranges.assign(1081, 1000);
    p.intensities.assign(1081, 1);
    hokuyo::ScanStreamDecoder dec;
    std::vector<LaserScan> out;
    dec.feed(0, bytesOf(hokuyo::encodeScanFrame(req, p)), out);
    EXPECT_TRUE(out.empty());
    EXPECT_EQ(dec.counters().errors, 1u);
    EXPECT_NE(dec.counters().last_error.find("before the PP reply"), std::string::npos);
}

TEST(RecordedXsensStream, SamplesOnTheHostClockWithGapsAndADroppedByte) {
    std::vector<std::uint8_t> stream;
    std::vector<std::size_t> frame_starts;
    for (std::uint16_t k = 0; k < 400; ++k) {
        if (k == 100) continue;  // a packet lost on the device side: counter gap
        xsens::MtData2Builder b;
        b.packetCounter(k)
            .sampleTimeFine(50'000u + 50u * k)
            .acceleration({0.1, 0.2, 9.81})
            .rateOfTurn({0.01, -0.02, 0.03})
            .statusWord(3);
        const auto f = b.frame();
        frame_starts.push_back(stream.size());
        stream.insert(stream.end(), f.begin(), f.end());
    }
    stream.erase(stream.begin() +
                 static_cast<std::ptrdiff_t>(frame_starts[200] + 10));  // a byte lost on the wire
    xsens::ImuStreamDecoder dec;
    std::vector<ImuSample> out;
    // Received in 8-packet bursts 1-3 ms after the sample instants.
    const TimeNs t0 = 100 * kNsPerSec;
    const std::size_t per_chunk = stream.size() / 50;
    for (std::size_t i = 0; i < 50; ++i) {
        const std::size_t a = i * per_chunk, b = i == 49 ? stream.size() : (i + 1) * per_chunk;
        const TimeNs rx = t0 + static_cast<TimeNs>((i + 1) * 8) * 5 * kNsPerMs + 2 * kNsPerMs;
        dec.feed(rx, std::span(stream).subspan(a, b - a), out);
    }
    EXPECT_EQ(out.size(), 398u);  // 400 - the lost packet - the damaged one
    const StreamCounters c = dec.counters();
    EXPECT_EQ(c.gaps, 2u);
    EXPECT_GE(c.resyncs, 1u);
    EXPECT_DOUBLE_EQ(out[5].accel_mps2_imu.z(), static_cast<double>(9.81f));
    EXPECT_EQ(out[5].status_word, 3u);
    // 200 Hz on the device clock stays 5 ms apart on the host clock.
    EXPECT_NEAR(toSeconds(out[300].t_host - out[299].t_host), 0.005, 1e-6);
}

// A serial MTi's frame reaches the host a fixed latency (output processing, USB-serial bridge)
// plus its own wire time after the sample, plus jitter. The clock fit follows the lower envelope
// of the receive times, so without the timing the samples come out 1.5 ms late: at the 370 deg/s
// of aggressive hand motion that turned every sweep and output pose by 0.5 deg (drift 0.7 %).
TEST(RecordedXsensStream, SampleTimesFreeOfTheFramesLatencyAndWireTime) {
    const xsens::ImuFrameTiming timing{1 * kNsPerMs, 921600};
    xsens::ImuStreamDecoder timed("Xsens", timing), untimed;
    std::vector<ImuSample> out_timed, out_untimed;
    std::vector<TimeNs> sampled;
    std::mt19937 rng(5);
    std::exponential_distribution<double> jitter_per_ms(1.0 / 0.3);  // mean 0.3 ms
    const TimeNs t0 = 70 * kNsPerSec;
    TimeNs wire_ns = 0;
    for (std::uint32_t k = 0; k < 2000; ++k) {
        xsens::MtData2Builder b;
        b.packetCounter(static_cast<std::uint16_t>(k))
            .sampleTimeFine(123'000u + 50u * k)
            .acceleration({0.1, 0.2, 9.81})
            .rateOfTurn({1.0, -2.0, 3.0})
            .statusWord(3);
        const auto f = b.frame();
        wire_ns = static_cast<TimeNs>(static_cast<double>(f.size()) * 10.0 * 1e9 / 921600.0);
        const TimeNs t_k = t0 + static_cast<TimeNs>(k) * 5 * kNsPerMs;
        const TimeNs rx = t_k + kNsPerMs + wire_ns + static_cast<TimeNs>(jitter_per_ms(rng) * 1e6);
        sampled.push_back(t_k);
        timed.feed(rx, f, out_timed);
        untimed.feed(rx, f, out_untimed);
    }
    ASSERT_EQ(out_timed.size(), sampled.size());
    ASSERT_EQ(out_untimed.size(), sampled.size());
    EXPECT_GT(wire_ns, 400'000);  // a ~50-byte frame at 921600 baud: ~0.55 ms on the wire
    EXPECT_EQ(timing.delayOf(50), kNsPerMs + 542'534);
    // Once the fit has a few seconds of envelope: the sample's own time, within 50 us.
    for (std::size_t k = 600; k < sampled.size(); ++k) {
        ASSERT_NEAR(toSeconds(out_timed[k].t_host - sampled[k]), 0.0, 50e-6) << "sample " << k;
        ASSERT_GT(toSeconds(out_untimed[k].t_host - sampled[k]), 1.4e-3) << "sample " << k;
    }
    // USB (baud 0): the fixed latency only.
    EXPECT_EQ(xsens::ImuFrameTiming({2 * kNsPerMs, 0}).delayOf(50), 2 * kNsPerMs);
}

}  // namespace
}  // namespace handscan::sources
