// Throughput of the MCAP writer and reader (bytes of message payload per second) for the
// project's message sizes: IMU-sized (70 B), laser-sized (3.3 KB) and camera-sized (327 KB,
// a 640x512 grey frame) messages, chunks uncompressed or zstd level 1. The recorder must write
// faster than the devices produce (~17 MB/s for the tracking camera at 50 Hz plus a few MB/s of
// the rest).
#include <benchmark/benchmark.h>

#include <cstdio>
#include <random>

#include "handscan/recording/crc32.hpp"
#include "handscan/recording/mcap_reader.hpp"
#include "handscan/recording/mcap_writer.hpp"

namespace handscan::recording {
namespace {

// Camera-like content: a smooth gradient with sensor noise (compresses like a real image, not
// like zeros or pure noise).
std::vector<std::uint8_t> payload(std::size_t size) {
    std::mt19937 rng(1);
    std::vector<std::uint8_t> v(size);
    for (std::size_t i = 0; i < size; ++i)
        v[i] = static_cast<std::uint8_t>((i % 640) / 3 + rng() % 8);
    return v;
}

std::string compressionName(std::int64_t arg) { return arg == 0 ? "" : "zstd"; }

void writeMessages(McapWriter& w, const std::vector<std::uint8_t>& data, std::size_t total_bytes) {
    const auto ch = *w.addChannel("/bench", "x-bench");
    TimeNs t = kNsPerSec;
    for (std::size_t done = 0; done < total_bytes; done += data.size(), t += kNsPerMs) {
        if (!w.write(ch, t, data)) std::abort();
    }
    if (!w.close()) std::abort();
}

// args: message size, compression (0 none, 1 zstd)
void BM_WriteMemory(benchmark::State& state) {
    const auto data = payload(static_cast<std::size_t>(state.range(0)));
    const std::size_t total = 32u << 20;
    McapWriterOptions o;
    o.compression = compressionName(state.range(1));
    for (auto _ : state) {
        auto w = McapWriter::inMemory(o);
        writeMessages(**w, data, total);
        benchmark::DoNotOptimize((*w)->takeBuffer());
    }
    state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * total));
}
BENCHMARK(BM_WriteMemory)
    ->ArgsProduct({{70, 3300, 327680}, {0, 1}})
    ->ArgNames({"msg_bytes", "zstd"})
    ->Unit(benchmark::kMillisecond);

// To a file in /tmp (page cache; no fdatasync): what the recorder thread sees.
void BM_WriteFile(benchmark::State& state) {
    const auto data = payload(static_cast<std::size_t>(state.range(0)));
    const std::size_t total = 64u << 20;
    McapWriterOptions o;
    o.compression = compressionName(state.range(1));
    const std::string path = "/tmp/handscan_recording_bench.mcap";
    for (auto _ : state) {
        auto w = McapWriter::create(path, o);
        writeMessages(**w, data, total);
    }
    std::remove(path.c_str());
    state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * total));
}
BENCHMARK(BM_WriteFile)
    ->ArgsProduct({{3300, 327680}, {0, 1}})
    ->ArgNames({"msg_bytes", "zstd"})
    ->Unit(benchmark::kMillisecond);

// Reading every message back in log-time order, indexed.
void BM_Read(benchmark::State& state) {
    const auto data = payload(static_cast<std::size_t>(state.range(0)));
    const std::size_t total = 32u << 20;
    McapWriterOptions o;
    o.compression = compressionName(state.range(1));
    auto w = McapWriter::inMemory(o);
    writeMessages(**w, data, total);
    const auto bytes = (*w)->takeBuffer();
    std::uint64_t read = 0;
    for (auto _ : state) {
        auto r = McapReader::fromBuffer(bytes);
        std::uint64_t n = 0;
        if (!(*r)->forEachMessage({}, [&](const RecordedMessage& m) { n += m.data.size(); }))
            std::abort();
        read += n;
    }
    state.SetBytesProcessed(static_cast<std::int64_t>(read));
}
BENCHMARK(BM_Read)
    ->ArgsProduct({{70, 3300, 327680}, {0, 1}})
    ->ArgNames({"msg_bytes", "zstd"})
    ->Unit(benchmark::kMillisecond);

// Recovery of a file without footer: the linear scan (decompress + CRC every chunk), then reading.
void BM_ReadTruncated(benchmark::State& state) {
    const auto data = payload(3300);
    const std::size_t total = 32u << 20;
    auto w = McapWriter::inMemory();
    writeMessages(**w, data, total);
    auto bytes = (*w)->takeBuffer();
    bytes.resize(bytes.size() * 9 / 10);
    std::uint64_t read = 0;
    for (auto _ : state) {
        auto r = McapReader::fromBuffer(bytes);
        if (!(*r)->truncated()) std::abort();
        if (!(*r)->forEachMessage({}, [&](const RecordedMessage& m) { read += m.data.size(); }))
            std::abort();
    }
    state.SetBytesProcessed(static_cast<std::int64_t>(read));
}
BENCHMARK(BM_ReadTruncated)->Unit(benchmark::kMillisecond);

void BM_Crc32(benchmark::State& state) {
    const auto data = payload(1u << 20);
    for (auto _ : state) benchmark::DoNotOptimize(crc32(data));
    state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * data.size()));
}
BENCHMARK(BM_Crc32);

}  // namespace
}  // namespace handscan::recording
