// Per-frame cost of the camera path at the tracking camera's size (640x512): frame record
// encode + decode (recording and replay), raw and PNG-coded, PNG decode alone (libpng's and
// ours), and YUYV -> grey / BGR conversion.
#include <benchmark/benchmark.h>
#include <png.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "handscan/camera/frame_record.hpp"
#include "handscan/camera/image_convert.hpp"
#include "handscan/camera/png_payload.hpp"
#include "handscan/transport/v4l2_device.hpp"

namespace {

using namespace handscan;
using namespace handscan::camera;

constexpr std::uint32_t kW = 640, kH = 512;

FrameRecordHeader greyHeader() {
    FrameRecordHeader h;
    h.fourcc = transport::kFourccGrey;
    h.width = kW;
    h.height = kH;
    h.stride = kW;
    return h;
}

void BM_FrameRecordRoundTripGrey(benchmark::State& state) {
    const FrameRecordHeader h = greyHeader();
    const std::vector<std::uint8_t> payload(kW * kH, 128);
    for (auto _ : state) {
        auto rec = encodeFrameRecord(h, payload);
        auto v = decodeFrameRecord(rec);
        benchmark::DoNotOptimize(v);
    }
    state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) * kW * kH);
}
BENCHMARK(BM_FrameRecordRoundTripGrey);

// A camera-like frame: a smooth shading ramp with a texture edge pattern and shot noise of
// variance 0.02 DN per DN (the simulator's sensor model), so the PNG figures mean something.
std::vector<std::uint8_t> cameraLikeFrame() {
    std::mt19937 rng(7);
    std::normal_distribution<float> unit(0.0f, 1.0f);
    std::vector<std::uint8_t> px(kW * kH);
    for (std::uint32_t y = 0; y < kH; ++y) {
        for (std::uint32_t x = 0; x < kW; ++x) {
            const float signal =
                40.0f + 0.15f * static_cast<float>(x) + (((x / 24) + (y / 24)) % 2 ? 50.0f : 0.0f);
            const float v = signal + unit(rng) * std::sqrt(0.02f * signal) + 0.5f;
            px[y * kW + x] = static_cast<std::uint8_t>(std::clamp(v, 0.0f, 255.0f));
        }
    }
    return px;
}

void BM_FrameRecordPngGrey(benchmark::State& state) {
    const FrameRecordHeader h = greyHeader();
    const std::vector<std::uint8_t> payload = cameraLikeFrame();
    std::size_t stored = 0;
    for (auto _ : state) {
        auto rec = encodeFrameRecord(h, payload, FrameCoding::kPng);
        stored = rec.size();
        if (state.range(0) == 1) {
            auto v = decodeFrameRecord(rec);
            benchmark::DoNotOptimize(v);
        }
        benchmark::DoNotOptimize(rec);
    }
    state.SetLabel(state.range(0) == 1 ? "encode+decode" : "encode");
    state.counters["bits_per_pixel"] = 8.0 * static_cast<double>(stored) / (kW * kH);
}
BENCHMARK(BM_FrameRecordPngGrey)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// Replay's share: one PNG-coded tracking frame back to its bytes. Arg 0: libpng's simplified
// reader (what decodePngPayload used before png_fast_decode), 1: decodePngPayload (libdeflate).
void BM_PngDecodeGrey(benchmark::State& state) {
    FrameRecordHeader h = greyHeader();
    h.bytesused = kW * kH;
    const std::vector<std::uint8_t> payload = cameraLikeFrame();
    const auto png = encodePngPayload(h, payload);
    if (!png) {
        state.SkipWithError("PNG encode failed");
        return;
    }
    std::vector<std::uint8_t> out(payload.size());
    for (auto _ : state) {
        if (state.range(0) == 0) {
            png_image image{};
            image.version = PNG_IMAGE_VERSION;
            png_image_begin_read_from_memory(&image, png->data(), png->size());
            png_image_finish_read(&image, nullptr, out.data(), 0, nullptr);
        } else {
            benchmark::DoNotOptimize(decodePngPayload(h, *png, out));
        }
        benchmark::DoNotOptimize(out.data());
    }
    state.SetLabel(state.range(0) == 0 ? "libpng" : "decodePngPayload");
    if (out != payload) state.SkipWithError("decoded bytes differ from the frame");
}
BENCHMARK(BM_PngDecodeGrey)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

Image yuyv() {
    Image im;
    im.format = PixelFormat::kYuyv;
    im.width = kW;
    im.height = kH;
    im.stride_bytes = 2 * kW;
    im.data.resize(2u * kW * kH);
    for (std::size_t i = 0; i < im.data.size(); ++i) im.data[i] = static_cast<std::uint8_t>(i * 7);
    return im;
}

void BM_YuyvToGrey(benchmark::State& state) {
    const Image im = yuyv();
    for (auto _ : state) {
        auto g = toGrey(im);
        benchmark::DoNotOptimize(g);
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_YuyvToGrey);

void BM_YuyvToBgr(benchmark::State& state) {
    const Image im = yuyv();
    for (auto _ : state) {
        auto g = toBgr(im);
        benchmark::DoNotOptimize(g);
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_YuyvToBgr);

}  // namespace
