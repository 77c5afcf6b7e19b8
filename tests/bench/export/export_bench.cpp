// Export throughput for 10 million points against the raw write speed of the same disk, measured
// in the same run: a dd-style baseline writes the same number of bytes in 4 MiB blocks + fsync.
// Run: build/default/tests/bench/export/export_bench [--benchmark_filter=...]
// HANDSCAN_BENCH_DIR picks the disk (default: the temp directory).
#include <benchmark/benchmark.h>
#include <fcntl.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <random>

#include "handscan/export/exporter.hpp"
#include "handscan/journal/journal_writer.hpp"

namespace {

namespace fs = std::filesystem;
using namespace handscan;

constexpr std::size_t kPoints = 10'000'000;

fs::path benchDir() {
    const char* env = std::getenv("HANDSCAN_BENCH_DIR");
    return fs::path(env ? env : fs::temp_directory_path().string()) / ("handscan_export_bench_" + std::to_string(::getpid()));
}

// One journal of 10 M points shared by the benchmarks.
const std::string& journalPath() {
    static const std::string path = [] {
        const fs::path dir = benchDir();
        fs::remove_all(dir);
        fs::create_directories(dir);
        const std::string p = (dir / "journal.hsj").string();
        auto w = journal::JournalWriter::create(p, "{}");
        std::mt19937 rng(1);
        std::uniform_real_distribution<float> u(-50.f, 50.f);
        std::vector<journal::MapPoint> batch(100'000);
        for (std::size_t done = 0; done < kPoints; done += batch.size()) {
            for (std::size_t i = 0; i < batch.size(); ++i) {
                batch[i] = {static_cast<double>(done + i) * 1e-5, u(rng), u(rng), u(rng) * 0.1f, 10, 20, 30, 100};
            }
            (void)(*w)->appendPoints(batch);
        }
        (void)(*w)->finish();
        return p;
    }();
    return path;
}

// dd-style: 4 MiB blocks + fsync. With range(1) = 1 it also reads the file back from the medium
// (page cache dropped), which is what the exporter's verification costs on top of the write.
void BM_RawWriteBaseline(benchmark::State& state) {
    const std::uint64_t bytes = static_cast<std::uint64_t>(state.range(0));
    const bool read_back = state.range(1) != 0;
    std::vector<char> block(4 << 20, 'x');
    fs::create_directories(benchDir());
    const std::string path = (benchDir() / "dd.bin").string();
    for (auto _ : state) {
        const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        for (std::uint64_t done = 0; done < bytes; done += block.size()) {
            if (::write(fd, block.data(), block.size()) < 0) state.SkipWithError("write failed");
        }
        ::fsync(fd);
        ::posix_fadvise(fd, 0, 0, POSIX_FADV_DONTNEED);
        ::close(fd);
        if (read_back) {
            const int rfd = ::open(path.c_str(), O_RDONLY);
            while (::read(rfd, block.data(), block.size()) > 0) {}
            ::close(rfd);
        }
    }
    ::unlink(path.c_str());
    state.SetBytesProcessed(static_cast<std::int64_t>(bytes) * state.iterations());
}

void BM_Export(benchmark::State& state, const std::string& format, std::uint64_t bytes) {
    const std::string& journal = journalPath();
    const fs::path target = benchDir() / "target";
    fs::create_directories(target);
    for (auto _ : state) {
        auto r = exporter::exportScan(journal, target.string(), {{format}, 0.0, "scan", {}, {}});
        if (!r.isOk()) state.SkipWithError(r.status().message().c_str());
    }
    state.SetBytesProcessed(static_cast<std::int64_t>(bytes) * state.iterations());
    state.counters["points_per_s"] = benchmark::Counter(static_cast<double>(kPoints) * state.iterations(), benchmark::Counter::kIsRate);
}

void BM_ExportPly(benchmark::State& state) { BM_Export(state, "ply", exporter::plyBytes(kPoints)); }
void BM_ExportLas(benchmark::State& state) { BM_Export(state, "las", exporter::lasBytes(kPoints)); }

const std::int64_t kPlyBytes = static_cast<std::int64_t>(exporter::plyBytes(kPoints));
const std::int64_t kLasBytes = static_cast<std::int64_t>(exporter::lasBytes(kPoints));
BENCHMARK(BM_RawWriteBaseline)->Args({kPlyBytes, 0})->Args({kPlyBytes, 1})->Unit(benchmark::kMillisecond)->Iterations(3)->UseRealTime();
BENCHMARK(BM_ExportPly)->Unit(benchmark::kMillisecond)->Iterations(3)->UseRealTime();
BENCHMARK(BM_RawWriteBaseline)->Args({kLasBytes, 0})->Args({kLasBytes, 1})->Unit(benchmark::kMillisecond)->Iterations(3)->UseRealTime();
BENCHMARK(BM_ExportLas)->Unit(benchmark::kMillisecond)->Iterations(3)->UseRealTime();

}  // namespace
