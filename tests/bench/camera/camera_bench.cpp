// Per-frame cost of the camera path at the tracking camera's size (640x512): frame record
// encode + decode (recording and replay) and YUYV -> grey / BGR conversion.
#include <benchmark/benchmark.h>

#include "handscan/camera/frame_record.hpp"
#include "handscan/camera/image_convert.hpp"
#include "handscan/transport/v4l2_device.hpp"

namespace {

using namespace handscan;
using namespace handscan::camera;

constexpr std::uint32_t kW = 640, kH = 512;

void BM_FrameRecordRoundTripGrey(benchmark::State& state) {
    FrameRecordHeader h;
    h.fourcc = transport::kFourccGrey;
    h.width = kW;
    h.height = kH;
    h.stride = kW;
    const std::vector<std::uint8_t> payload(kW * kH, 128);
    for (auto _ : state) {
        auto rec = encodeFrameRecord(h, payload);
        auto v = decodeFrameRecord(rec);
        benchmark::DoNotOptimize(v);
    }
    state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) * kW * kH);
}
BENCHMARK(BM_FrameRecordRoundTripGrey);

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
