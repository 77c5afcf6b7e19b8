// Throughput of the Xsens codec on the real MTi-G-710 captures and on the 200 Hz IMU packets the
// driver configures: Xbus framing alone, framing + MTData2 decode, and the device state machine
// end to end over the in-memory fake (virtual clock, so only CPU time is measured).
#include <benchmark/benchmark.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include "handscan/xsens/mtdata2.hpp"
#include "handscan/xsens/xbus_parser.hpp"
#include "handscan/xsens/xsens_device.hpp"
#include "handscan/xsens_fake/fake_xsens_stream.hpp"

namespace {

using namespace handscan;
using namespace handscan::xsens;

std::vector<std::uint8_t> capture(int n) {
    const auto p = std::filesystem::path(HANDSCAN_SHARED_DATA_DIR) / "xsens/mtig710" /
                   std::to_string(n) / "output.bin";
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::vector<std::uint8_t> imuStream(int packets) {
    std::vector<std::uint8_t> out;
    for (int i = 0; i < packets; ++i) {
        MtData2Builder b;
        b.packetCounter(static_cast<std::uint16_t>(i))
            .sampleTimeFine(static_cast<std::uint32_t>(i * 50))
            .acceleration({0.1, 0.2, 9.81})
            .rateOfTurn({0.01, -0.02, 0.3})
            .statusWord(3);
        const auto f = b.frame();
        out.insert(out.end(), f.begin(), f.end());
    }
    return out;
}

void BM_XbusFraming(benchmark::State& state, std::vector<std::uint8_t> bytes) {
    if (bytes.empty()) {
        state.SkipWithError("capture absent");
        return;
    }
    std::int64_t frames = 0;
    for (auto _ : state) {
        XbusParser p;
        p.feed(bytes);
        while (auto f = p.next()) {
            benchmark::DoNotOptimize(f->payload.data());
            ++frames;
        }
    }
    state.SetBytesProcessed(state.iterations() * static_cast<std::int64_t>(bytes.size()));
    state.SetItemsProcessed(frames);
}

void BM_FramingAndMtData2(benchmark::State& state, std::vector<std::uint8_t> bytes) {
    if (bytes.empty()) {
        state.SkipWithError("capture absent");
        return;
    }
    std::int64_t frames = 0;
    for (auto _ : state) {
        XbusParser p;
        p.feed(bytes);
        while (auto f = p.next()) {
            auto packet = decodeMtData2(f->payload);
            benchmark::DoNotOptimize(packet);
            ++frames;
        }
    }
    state.SetBytesProcessed(state.iterations() * static_cast<std::int64_t>(bytes.size()));
    state.SetItemsProcessed(frames);
}

BENCHMARK_CAPTURE(BM_XbusFraming, mtig710_1, capture(1));
BENCHMARK_CAPTURE(BM_FramingAndMtData2, mtig710_1_float32, capture(1));
BENCHMARK_CAPTURE(BM_FramingAndMtData2, mtig710_3_fp1632, capture(3));
BENCHMARK_CAPTURE(BM_FramingAndMtData2, imu_200hz_1000_packets, imuStream(1000));

// Samples per second the device state machine hands out (200 Hz is the requirement).
void BM_DeviceSamples(benchmark::State& state) {
    VirtualClock clock;
    FakeXsens fake;
    FakeXsensStream stream(fake, clock);
    XsensDeviceConfig cfg;
    cfg.clock = [&clock] { return clock.now; };
    XsensDevice device(stream, cfg);
    if (!device.configure()) {
        state.SkipWithError("configure failed");
        return;
    }
    std::vector<ImuSample> out;
    for (auto _ : state) {
        out.clear();
        (void)device.poll(out, 10 * kNsPerMs);
        benchmark::DoNotOptimize(out.data());
    }
    state.SetItemsProcessed(static_cast<std::int64_t>(device.stats().samples));
}
BENCHMARK(BM_DeviceSamples);

}  // namespace
