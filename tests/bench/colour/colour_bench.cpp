// Cost of colourising laser points: a batch of points spread over the colour camera's view
// (a slanted wall at 4-6 m; a quarter of them on a near board that hides part of the wall), against
// 1 frame and against the 5 frames of a 1 s sweep at 5 Hz. Items/s = points/s; time per 1M points =
// 1e6 / items_per_second.
#include <benchmark/benchmark.h>

#include <random>

#include "handscan/camera/image_convert.hpp"
#include "handscan/colour/colouriser.hpp"

namespace handscan::colour {
namespace {

Calibration camchain() {
    Calibration c;
    loadCamchain(std::string(HANDSCAN_SOURCE_DIR_FOR_BENCH) + "/config/camchain.yaml", c);
    return c;
}

Image noiseFrame(TimeNs t, std::uint32_t seq, std::mt19937& rng) {
    Image img;
    img.t_host = t;
    img.sequence = seq;
    img.format = PixelFormat::kBgr8;
    img.width = 1600;
    img.height = 1200;
    img.stride_bytes = 4800;
    img.data.resize(4800u * 1200u);
    for (auto& b : img.data) b = static_cast<std::uint8_t>(rng() & 0xFF);
    return img;
}

void BM_Colourise(benchmark::State& state) {
    const auto n = static_cast<std::size_t>(state.range(0));
    const int frames = static_cast<int>(state.range(1));
    const Calibration cal = camchain();
    Colouriser col(cal);
    std::mt19937 rng(1);
    for (int k = 0; k < frames; ++k) {
        if (!col.addImage(noiseFrame(k * 200 * kNsPerMs, static_cast<std::uint32_t>(k), rng))
                 .isOk())
            state.SkipWithError("addImage");
    }
    std::uniform_real_distribution<float> xy(-0.55f, 0.55f);
    std::uniform_int_distribution<TimeNs> when(0, (frames - 1) * 200 * kNsPerMs + 1);
    std::vector<Eigen::Vector3f> pts(n);
    std::vector<TimeNs> times(n);
    for (std::size_t i = 0; i < n; ++i) {
        // Every 4th point lies on a board at 1.5 m covering the left quarter of the view.
        const bool board = i % 4 == 0;
        const float x = board ? -0.55f + 0.25f * (xy(rng) + 0.55f) : xy(rng);
        const float d = board ? 1.5f : 5.0f + 2.0f * x;  // else a slanted wall, 3.9 .. 6.1 m
        pts[i] = {x * d, xy(rng) * d, d};
        times[i] = when(rng);
    }
    const PoseAtFn pose_at = [](TimeNs t) {
        Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
        T.translation().x() = 0.1 * toSeconds(t);
        return T;
    };
    std::size_t coloured = 0;
    for (auto _ : state) {
        const ColourResult r = col.colourise(pts, times, pose_at);
        coloured = r.coloured;
        benchmark::DoNotOptimize(r.rgb.data());
    }
    state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * n));
    state.counters["coloured_frac"] = static_cast<double>(coloured) / static_cast<double>(n);
}
BENCHMARK(BM_Colourise)
    ->Args({1'000'000, 1})
    ->Args({1'000'000, 5})
    ->Args({43'000, 5})
    ->Unit(benchmark::kMillisecond);

void BM_AddImageYuyv(benchmark::State& state) {
    const Calibration cal = camchain();
    Colouriser col(cal);
    Image yuyv;
    yuyv.format = PixelFormat::kYuyv;
    yuyv.width = 1600;
    yuyv.height = 1200;
    yuyv.stride_bytes = 3200;
    yuyv.data.assign(3200u * 1200u, 100);
    TimeNs t = 0;
    for (auto _ : state) {
        yuyv.t_host = (t += 200 * kNsPerMs);
        Result<Image> bgr = camera::toBgr(yuyv);  // the driver's decode, then the colouriser
        if (!bgr || !col.addImage(std::move(*bgr)).isOk()) state.SkipWithError("addImage");
    }
}
BENCHMARK(BM_AddImageYuyv)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace handscan::colour
