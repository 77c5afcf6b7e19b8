// Export throughput for 10 million points against the raw write speed of the same disk, measured
// in the same run and interleaved iteration by iteration (the machine is shared and noisy, so the
// ratios are what to read):
//   dd_MBps         dd-style buffered baseline: 4 MiB write() calls + fsync   (dd bs=4M conv=fsync)
//   dd_direct_MBps  the same with O_DIRECT                                     (dd bs=4M
//   oflag=direct conv=fsync) dd_verify_MBps  O_DIRECT write + fsync + O_DIRECT read back of the
//   file: the work a verified
//                   export does on the medium, without any encoding or checksums
//   export_MBps     handscan::exporter::exportScan of the journal (encode, write, fsync, read back,
//                   CRC compare, rename), bytes of the point file / export seconds (= the
//                   benchmark's time)
//   vs_dd, vs_direct, vs_verify  export_MBps divided by each baseline
//   cpu_ns_per_point  CPU time of all the exporter's threads per point
// The journal (on the same disk) is in the page cache, as it is right after a scan.
// Run: build/ci/tests/bench/export/export_bench [--benchmark_filter=...]
// HANDSCAN_BENCH_DIR picks the disk (default: the temp directory).
#include <benchmark/benchmark.h>
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <memory>
#include <random>

#include "handscan/export/exporter.hpp"
#include "handscan/export/voxel_filter.hpp"
#include "handscan/journal/journal_reader.hpp"
#include "handscan/journal/journal_writer.hpp"

namespace {

namespace fs = std::filesystem;
using namespace handscan;
using Clock = std::chrono::steady_clock;

constexpr std::size_t kPoints = 10'000'000;
constexpr std::size_t kBlock = 4u << 20;

fs::path benchDir() {
    const char* env = std::getenv("HANDSCAN_BENCH_DIR");
    return fs::path(env ? env : fs::temp_directory_path().string()) /
           ("handscan_export_bench_" + std::to_string(::getpid()));
}

// One journal of 10 M points shared by the benchmarks, removed at exit.
const std::string& journalPath() {
    struct Dir {
        ~Dir() { fs::remove_all(benchDir()); }
    };
    static Dir cleanup;
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
                batch[i] = {static_cast<double>(done + i) * 1e-5,
                            u(rng),
                            u(rng),
                            u(rng) * 0.1f,
                            10,
                            20,
                            30,
                            100};
            }
            (void)(*w)->appendPoints(batch);
        }
        (void)(*w)->finish();
        return p;
    }();
    return path;
}

double processCpuSeconds() {
    timespec ts{};
    ::clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec) * 1e-9;
}

struct AlignedFree {
    void operator()(void* p) const { std::free(p); }
};

// dd-style raw write of `bytes` in 4 MiB blocks + fsync; with `direct`, O_DIRECT (page cache
// bypassed); with `read_back`, then read the file back with O_DIRECT. Returns seconds, < 0 on
// error.
double rawWrite(const std::string& path, std::uint64_t bytes, bool direct, bool read_back) {
    void* mem = nullptr;
    if (::posix_memalign(&mem, 4096, kBlock) != 0) return -1.0;
    std::unique_ptr<std::uint8_t, AlignedFree> block(static_cast<std::uint8_t*>(mem));
    std::fill(block.get(), block.get() + kBlock, std::uint8_t{'x'});
    const auto t0 = Clock::now();
    const int fd = ::open(path.c_str(),
                          O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC | (direct ? O_DIRECT : 0), 0644);
    if (fd < 0) return -1.0;
    bool ok = true;
    for (std::uint64_t done = 0; done < bytes && ok;) {
        // The last block is cut to the byte count, rounded up to 4 KiB for O_DIRECT.
        const std::size_t n = static_cast<std::size_t>(
            std::min<std::uint64_t>(kBlock, (bytes - done + 4095) & ~std::uint64_t{4095}));
        ok = ::write(fd, block.get(), n) == static_cast<ssize_t>(n);
        done += n;
    }
    ok = ok && ::fsync(fd) == 0;
    ::close(fd);
    if (ok && read_back) {
        const int rfd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_DIRECT);
        ok = rfd >= 0;
        while (ok && ::read(rfd, block.get(), kBlock) > 0) {
        }
        if (rfd >= 0) ::close(rfd);
    }
    const double s = std::chrono::duration<double>(Clock::now() - t0).count();
    ::unlink(path.c_str());
    return ok ? s : -1.0;
}

void BM_ExportVsDd(benchmark::State& state, const std::string& format, std::uint64_t bytes,
                   double e57_scale_m = 0.0) {
    const std::string& journal = journalPath();
    const fs::path target = benchDir() / "target";
    fs::create_directories(target);
    const std::string dd_path = (benchDir() / "dd.bin").string();
    double t_dd = 0, t_direct = 0, t_verify = 0, t_export = 0, cpu = 0;
    for (auto _ : state) {
        const double dd = rawWrite(dd_path, bytes, false, false);
        const double direct = rawWrite(dd_path, bytes, true, false);
        const double verify = rawWrite(dd_path, bytes, true, true);
        if (dd < 0 || direct < 0 || verify < 0) {
            state.SkipWithError("dd baseline failed (O_DIRECT unsupported on this filesystem?)");
            break;
        }
        const double cpu0 = processCpuSeconds();
        const auto t0 = Clock::now();
        // report.html as every export writes it; report.pdf (weasyprint, seconds of its own,
        // independent of the point count) is left out of the point formats' figures.
        exporter::ExportOptions options{{format}, 0.0, "scan", {}, {}, true, ""};
        options.e57_scale_m = e57_scale_m;
        auto r = exporter::exportScan(journal, target.string(), options);
        const double ex = std::chrono::duration<double>(Clock::now() - t0).count();
        cpu += processCpuSeconds() - cpu0;
        if (!r.isOk()) {
            state.SkipWithError(r.status().message().c_str());
            break;
        }
        state.SetIterationTime(ex);
        t_dd += dd;
        t_direct += direct;
        t_verify += verify;
        t_export += ex;
    }
    const double mb = static_cast<double>(bytes) * static_cast<double>(state.iterations()) / 1e6;
    if (t_export > 0 && t_dd > 0) {
        state.counters["export_MBps"] = mb / t_export;
        state.counters["dd_MBps"] = mb / t_dd;
        state.counters["dd_direct_MBps"] = mb / t_direct;
        state.counters["dd_verify_MBps"] = mb / t_verify;
        state.counters["vs_dd"] = t_dd / t_export;
        state.counters["vs_direct"] = t_direct / t_export;
        state.counters["vs_verify"] = t_verify / t_export;
        state.counters["ns_per_point"] =
            t_export * 1e9 /
            (static_cast<double>(kPoints) * static_cast<double>(state.iterations()));
        // CPU of all threads per point: on this shared 2-core machine the wall time follows it.
        state.counters["cpu_ns_per_point"] =
            cpu * 1e9 / (static_cast<double>(kPoints) * static_cast<double>(state.iterations()));
    }
}

void BM_ExportPly(benchmark::State& state) {
    BM_ExportVsDd(state, "ply", exporter::plyBytes(kPoints));
}
void BM_ExportLas(benchmark::State& state) {
    BM_ExportVsDd(state, "las", exporter::lasBytes(kPoints));
}
void BM_ExportE57(benchmark::State& state) {
    BM_ExportVsDd(state, "e57", exporter::e57Bytes(kPoints, 0));
}
// E57 with 0.1 mm ScaledInteger coordinates (--e57-coordinates scaled:0.0001): 12 bytes less
// per point than doubles.
void BM_ExportE57Scaled(benchmark::State& state) {
    BM_ExportVsDd(state, "e57", exporter::e57Bytes(kPoints, 0, true), 1e-4);
}
BENCHMARK(BM_ExportPly)->Unit(benchmark::kMillisecond)->Iterations(3)->UseManualTime();
BENCHMARK(BM_ExportE57)->Unit(benchmark::kMillisecond)->Iterations(3)->UseManualTime();
BENCHMARK(BM_ExportE57Scaled)->Unit(benchmark::kMillisecond)->Iterations(3)->UseManualTime();
BENCHMARK(BM_ExportLas)->Unit(benchmark::kMillisecond)->Iterations(3)->UseManualTime();

// The journal side of an export alone: open (every chunk's CRC checked) and stream the points
// decoded (what the encoders are fed), from the page cache.
void BM_JournalOpen(benchmark::State& state) {
    const std::string& journal = journalPath();
    for (auto _ : state) {
        auto r = journal::JournalReader::open(journal);
        if (!r.isOk()) state.SkipWithError(r.status().message().c_str());
    }
    state.SetBytesProcessed(static_cast<std::int64_t>(fs::file_size(journal)) * state.iterations());
}
BENCHMARK(BM_JournalOpen)->Unit(benchmark::kMillisecond)->Iterations(3)->UseRealTime();

void BM_JournalStream(benchmark::State& state) {
    auto reader = journal::JournalReader::open(journalPath());
    double sum = 0;
    for (auto _ : state) {
        (void)reader->forEachPoints(
            [&](std::span<const journal::MapPoint> pts) { sum += pts.back().x; });
    }
    benchmark::DoNotOptimize(sum);
    state.SetBytesProcessed(static_cast<std::int64_t>(fs::file_size(journalPath())) *
                            state.iterations());
}
BENCHMARK(BM_JournalStream)->Unit(benchmark::kMillisecond)->Iterations(3)->UseRealTime();

// Voxel thinning (--voxel) alone, in memory: 4 M points in a 2 m cube at 2 cm voxels (~1 M
// occupied voxels, ~4 points each, like a dense indoor scan).
void BM_VoxelFilter(benchmark::State& state) {
    std::vector<journal::MapPoint> pts(4'000'000);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(0.f, 2.f);
    for (std::size_t i = 0; i < pts.size(); ++i)
        pts[i] = {static_cast<double>(i) * 1e-6, u(rng), u(rng), u(rng), 1, 2, 3, 4};
    std::size_t kept = 0;
    for (auto _ : state) {
        exporter::VoxelFilter f(0.02);
        f.add(pts);
        kept = f.take().size();
        benchmark::DoNotOptimize(kept);
    }
    state.counters["kept"] = static_cast<double>(kept);
    state.counters["points_per_s"] = benchmark::Counter(
        static_cast<double>(pts.size()) * static_cast<double>(state.iterations()),
        benchmark::Counter::kIsRate);
}
BENCHMARK(BM_VoxelFilter)->Unit(benchmark::kMillisecond)->Iterations(3)->UseRealTime();

}  // namespace
