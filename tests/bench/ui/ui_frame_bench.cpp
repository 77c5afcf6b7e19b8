// Frame time of the live-map view with 1, 5 and 10 million points (the renderer handscan-ui
// uses, 1020 x 690 view in a 1280 x 800 window), and the cost of appending a chunk of new points.
// Needs an X display: run under xvfb-run for Mesa's software renderer (llvmpipe), e.g.
//   xvfb-run -a -s "-screen 0 1280x800x24" build/release/tests/bench/ui/ui_frame_bench
#include <GLFW/glfw3.h>
#include <benchmark/benchmark.h>

#include <random>
#include <string>
#include <vector>

#include "handscan/ui/map_renderer.hpp"
#include "handscan/ui/view_camera.hpp"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>

namespace {

using handscan::shm::DisplayPoint;
using handscan::ui::ColourMode;
using handscan::ui::MapRenderer;

// A 60 m x 40 m two-floor building shell with clutter: the kind of map a long scan leaves.
std::vector<DisplayPoint> syntheticMap(std::size_t n, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<DisplayPoint> pts(n);
    for (DisplayPoint& p : pts) {
        const float a = u(rng);
        if (a < 0.4f) {  // floors
            p.x_m = u(rng) * 60 - 30, p.y_m = u(rng) * 40 - 20, p.z_m = u(rng) < 0.5f ? 0.0f : 3.0f;
        } else if (a < 0.8f) {  // walls
            const bool ew = u(rng) < 0.5f;
            p.x_m = ew ? (u(rng) < 0.5f ? -30.0f : 30.0f) : u(rng) * 60 - 30;
            p.y_m = ew ? u(rng) * 40 - 20 : (u(rng) < 0.5f ? -20.0f : 20.0f);
            p.z_m = u(rng) * 6;
        } else {  // clutter
            p.x_m = u(rng) * 60 - 30, p.y_m = u(rng) * 40 - 20, p.z_m = u(rng) * 2;
        }
        p.r = static_cast<std::uint8_t>(100 + 155 * u(rng));
        p.g = static_cast<std::uint8_t>(100 + 155 * u(rng));
        p.b = static_cast<std::uint8_t>(100 + 155 * u(rng));
        p.intensity = static_cast<std::uint8_t>(255 * u(rng));
    }
    return pts;
}

struct GlWindow {
    GLFWwindow* window = nullptr;
    std::string renderer;
    GlWindow() {
        if (!glfwInit()) return;
        glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
        glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
        glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
        glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
        window = glfwCreateWindow(1280, 800, "ui_frame_bench", nullptr, nullptr);
        if (!window) return;
        glfwMakeContextCurrent(window);
        glfwSwapInterval(0);
        renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    }
    ~GlWindow() {
        if (window) glfwDestroyWindow(window);
        glfwTerminate();
    }
};

GlWindow& window() {
    static GlWindow w;
    return w;
}

void BM_FrameTime(benchmark::State& state) {
    if (!window().window) {
        state.SkipWithError("no OpenGL 3.3 window: run under xvfb-run (DISPLAY unset?)");
        return;
    }
    const auto n = static_cast<std::size_t>(state.range(0));
    const auto mode = static_cast<ColourMode>(state.range(1));
    const auto point_size = static_cast<float>(state.range(2));
    const auto budget = static_cast<std::size_t>(state.range(3));
    MapRenderer renderer;
    if (!renderer.init().isOk()) {
        state.SkipWithError("shader build failed");
        return;
    }
    const std::vector<DisplayPoint> pts = syntheticMap(n, 1);
    renderer.appendPoints(pts);
    handscan::ui::ViewCamera cam;
    cam.mode = handscan::ui::CameraMode::kFree;
    cam.target = {0, 0, 1};
    cam.distance_m = 45;
    glViewport(0, 110, 1020, 690);
    renderer.draw(cam.projection(1020.0f / 690.0f) * cam.view(), mode, point_size,
                  budget);  // warm-up: shader JIT
    glFinish();
    for (auto _ : state) {
        glClearColor(0.08f, 0.08f, 0.1f, 1.0f);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        cam.drag(3.0f, 0.0f);  // the operator orbits: every frame is a new view
        renderer.draw(cam.projection(1020.0f / 690.0f) * cam.view(), mode, point_size, budget);
        glfwSwapBuffers(window().window);
        glFinish();
    }
    state.counters["points"] = static_cast<double>(n);
    state.counters["drawn"] = static_cast<double>(renderer.lastDrawnPoints());
    state.counters["fps"] =
        benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
    state.SetLabel(window().renderer);
}
// Args: points, colour mode, point size (px), per-frame point budget (0 = draw all).
BENCHMARK(BM_FrameTime)
    ->ArgNames({"points", "colour", "size", "budget"})
    ->ArgsProduct(
        {{1'000'000, 5'000'000, 10'000'000}, {static_cast<int>(ColourMode::kRgb)}, {1, 2}, {0}})
    ->Args({10'000'000, static_cast<int>(ColourMode::kHeight), 1, 0})
    ->ArgsProduct({{1'000'000, 5'000'000, 10'000'000},
                   {static_cast<int>(ColourMode::kRgb)},
                   {1},
                   {1'000'000}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(1.0);

// Appending one chunk of new points to a map that already holds `base` points (what a frame
// pays when the pipeline publishes an update), including the occasional buffer doubling.
void BM_AppendChunk(benchmark::State& state) {
    if (!window().window) {
        state.SkipWithError("no OpenGL 3.3 window: run under xvfb-run (DISPLAY unset?)");
        return;
    }
    const std::vector<DisplayPoint> chunk =
        syntheticMap(static_cast<std::size_t>(state.range(0)), 2);
    MapRenderer renderer;
    if (!renderer.init().isOk()) {
        state.SkipWithError("shader build failed");
        return;
    }
    for (auto _ : state) {
        renderer.appendPoints(chunk);
        glFinish();
        if (renderer.pointCount() > 8'000'000) {
            state.PauseTiming();
            renderer.reset();
            state.ResumeTiming();
        }
    }
    state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * state.range(0));
}
BENCHMARK(BM_AppendChunk)->Arg(20'000)->Arg(200'000)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
