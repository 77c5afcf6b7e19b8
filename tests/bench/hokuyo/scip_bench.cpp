// SCIP 2.0 codec speed: parsing and encoding full UTM-30LX-EW ME scans (1081 steps, range +
// intensity, 6.7 kB per frame; the sensor sends 40 per second).
#include <benchmark/benchmark.h>

#include "handscan/hokuyo/scip_codec.hpp"
#include "handscan/hokuyo/scip_stream_parser.hpp"

namespace {

using namespace handscan::hokuyo;

const ScanRequest kMe{'M', ScanEncoding::kThreeCharWithIntensity, 0, 1080, 1, 0, 0, ""};

ScanPayload makeScan(std::uint32_t t) {
    ScanPayload p;
    p.timestamp_ms = t;
    for (std::uint32_t i = 0; i < 1081; ++i) {
        p.ranges.push_back((i * 7919u + t) % 60000u);
        p.intensities.push_back((i * 31u) % 8000u);
    }
    return p;
}

void BM_ParseMeScans(benchmark::State& state) {
    std::string stream;
    for (std::uint32_t k = 0; k < 40; ++k) stream += encodeScanFrame(kMe, makeScan(k * 25));
    std::vector<ScipEvent> events;
    for (auto _ : state) {
        ScipStreamParser parser;
        events.clear();
        // TCP-sized pieces.
        for (std::size_t pos = 0; pos < stream.size(); pos += 1448) {
            parser.feed(std::string_view(stream).substr(pos, 1448), events);
        }
        benchmark::DoNotOptimize(events.data());
    }
    state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * stream.size()));
    state.SetItemsProcessed(state.iterations() * 40);  // scans
}
BENCHMARK(BM_ParseMeScans);

void BM_EncodeMeScan(benchmark::State& state) {
    const ScanPayload scan = makeScan(1000);
    std::size_t bytes = 0;
    for (auto _ : state) {
        const std::string frame = encodeScanFrame(kMe, scan);
        bytes += frame.size();
        benchmark::DoNotOptimize(frame.data());
    }
    state.SetBytesProcessed(static_cast<std::int64_t>(bytes));
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_EncodeMeScan);

}  // namespace
