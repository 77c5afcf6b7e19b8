// Throughput of the motor codec path: one candump -l line parsed and its TPDO1 decoded and
// unwrapped (the per-frame work of replay and of `handscan decode --device can`).
#include <benchmark/benchmark.h>

#include "handscan/motor/candump_format.hpp"
#include "handscan/motor/canopen.hpp"
#include "handscan/motor/position_unwrapper.hpp"

namespace {

using namespace handscan;
using namespace handscan::motor;

void BM_ParseCandumpLogLine(benchmark::State& state) {
    const std::string line = "(1700000000.123456) can0 181#11223344";
    for (auto _ : state) {
        auto r = parseCandumpLogLine(line);
        benchmark::DoNotOptimize(r);
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_ParseCandumpLogLine);

void BM_FormatCandumpLogLine(benchmark::State& state) {
    auto rec = parseCandumpLogLine("(1700000000.123456) can0 601#2B0062000A000000");
    for (auto _ : state) {
        auto s = formatCandumpLogLine(*rec);
        benchmark::DoNotOptimize(s);
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_FormatCandumpLogLine);

void BM_DecodeAndUnwrapTpdo1(benchmark::State& state) {
    PositionUnwrapper u({4096, 4096, false, 20 * kNsPerMs});
    TimeNs t = 0;
    std::uint32_t raw = 0;
    for (auto _ : state) {
        const CanFrame f = encodeEncoderPositionTpdo(1, raw);
        auto p = decodeEncoderPositionTpdo(f);
        auto s = u.update(t, *p);
        benchmark::DoNotOptimize(s);
        t += kNsPerMs;
        raw = (raw + 20) % 4096;
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_DecodeAndUnwrapTpdo1);

}  // namespace
