#include "handscan/report/map_images.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace handscan::report {
namespace {

constexpr int kMargin = 48;  // room for the title, the scale bar and the legend
const cv::Scalar kWhite(255, 255, 255), kBlack(0, 0, 0);

struct Crop {
    int i0 = MapRaster::kCells, i1 = -1, j0 = MapRaster::kCells, j1 = -1;
    bool empty() const { return i1 < i0; }
};

Crop occupied(const MapRaster& r) {
    Crop c;
    if (r.empty()) return c;
    for (int j = 0; j < MapRaster::kCells; ++j) {
        for (int i = 0; i < MapRaster::kCells; ++i) {
            if (!r.at(i, j).set) continue;
            c.i0 = std::min(c.i0, i);
            c.i1 = std::max(c.i1, i);
            c.j0 = std::min(c.j0, j);
            c.j1 = std::max(c.j1, j);
        }
    }
    return c;
}

// The cropped raster with f x f cells merged (the nearest point wins), rows top-down.
struct Grid {
    int w = 0, h = 0, f = 1;
    std::vector<RasterCell> cells;
    const RasterCell& at(int col, int row) const {
        return cells[static_cast<std::size_t>(row) * w + col];
    }
};

Grid merged(const MapRaster& r, const Crop& c, int f) {
    Grid g;
    g.f = f;
    g.w = (c.i1 - c.i0) / f + 1;
    g.h = (c.j1 - c.j0) / f + 1;
    g.cells.assign(static_cast<std::size_t>(g.w) * g.h, RasterCell{});
    for (int j = c.j0; j <= c.j1; ++j) {
        for (int i = c.i0; i <= c.i1; ++i) {
            const RasterCell& cell = r.at(i, j);
            if (!cell.set) continue;
            RasterCell& m =
                g.cells[static_cast<std::size_t>((c.j1 - j) / f) * g.w + (i - c.i0) / f];
            if (!m.set || cell.depth > m.depth) m = cell;
        }
    }
    return g;
}

double occupancy(const Grid& g) {
    std::size_t set = 0;
    for (const RasterCell& c : g.cells) set += c.set;
    return static_cast<double>(set) / static_cast<double>(g.cells.size());
}

// Coarser cells until the points are dense at that resolution: doubling the cell size again
// would fill less than 30 % more of the picture (a sparse cloud otherwise shows as speckles).
Grid denseGrid(const MapRaster& r, const Crop& c) {
    Grid g = merged(r, c, 1);
    while (g.f < 16) {
        Grid next = merged(r, c, g.f * 2);
        if (occupancy(next) < 1.3 * occupancy(g)) break;
        g = std::move(next);
    }
    return g;
}

std::pair<float, float> heightRange(const Grid& g) {
    std::vector<float> h;
    for (const RasterCell& c : g.cells)
        if (c.set) h.push_back(c.height);
    auto pct = [&](double q) {
        auto it = h.begin() + static_cast<std::ptrdiff_t>(q * static_cast<double>(h.size() - 1));
        std::nth_element(h.begin(), it, h.end());
        return *it;
    };
    // Wide enough for walls and furniture to stand out above a floor that fills most cells.
    const float lo = pct(0.01), hi = pct(0.999);
    return {lo, std::max(hi, lo + 0.01f)};
}

// One pixel per cell, rows top-down (v grows upwards in the world).
cv::Mat cellsImage(const Grid& g, Colouring colouring, float lo, float hi) {
    const int w = g.w, h = g.h;
    cv::Mat img(h, w, CV_8UC3, kWhite);
    cv::Mat level(h, w, CV_8UC1, cv::Scalar(0)), mask(h, w, CV_8UC1, cv::Scalar(0));
    for (int row = 0; row < h; ++row) {
        for (int col = 0; col < w; ++col) {
            const RasterCell& cell = g.at(col, row);
            if (!cell.set) continue;
            if (colouring == Colouring::kRgb) {
                const bool coloured = (cell.r | cell.g | cell.b) != 0;
                img.at<cv::Vec3b>(row, col) =
                    coloured ? cv::Vec3b(cell.b, cell.g, cell.r) : cv::Vec3b(170, 170, 170);
            } else {
                const float t = std::clamp((cell.height - lo) / (hi - lo), 0.0f, 1.0f);
                level.at<std::uint8_t>(row, col) = static_cast<std::uint8_t>(t * 255.0f);
                mask.at<std::uint8_t>(row, col) = 255;
            }
        }
    }
    if (colouring == Colouring::kHeight) {
        cv::Mat turbo;
        cv::applyColorMap(level, turbo, cv::COLORMAP_TURBO);
        turbo.copyTo(img, mask);
    }
    return img;
}

void scaleBar(cv::Mat& img, double metres_per_px) {
    const double target = metres_per_px * img.cols / 5.0;
    const double bar = std::pow(10.0, std::floor(std::log10(std::max(target, 1e-3))));
    const int len = static_cast<int>(bar / metres_per_px);
    const cv::Point b0(kMargin, img.rows - 16);
    cv::line(img, b0, b0 + cv::Point(len, 0), kBlack, 3);
    char text[32];
    std::snprintf(text, sizeof text, "%g m", bar);
    cv::putText(img, text, b0 + cv::Point(len + 8, 5), cv::FONT_HERSHEY_SIMPLEX, 0.5, kBlack, 1,
                cv::LINE_AA);
}

void heightLegend(cv::Mat& img, float lo, float hi) {
    const int x0 = img.cols - kMargin - 200, y0 = img.rows - 26;
    if (x0 < kMargin + 180) return;  // too narrow an image for a legend beside the scale bar
    cv::Mat ramp(1, 200, CV_8UC1);
    for (int k = 0; k < 200; ++k)
        ramp.at<std::uint8_t>(0, k) = static_cast<std::uint8_t>(k * 255 / 199);
    cv::Mat colours;
    cv::applyColorMap(ramp, colours, cv::COLORMAP_TURBO);
    cv::resize(colours, colours, {200, 12}, 0, 0, cv::INTER_NEAREST);
    colours.copyTo(img(cv::Rect(x0, y0, 200, 12)));
    char text[48];
    std::snprintf(text, sizeof text, "%.1f m", lo);
    cv::putText(img, text, {x0 - 60, y0 + 11}, cv::FONT_HERSHEY_SIMPLEX, 0.45, kBlack, 1,
                cv::LINE_AA);
    std::snprintf(text, sizeof text, "%.1f m", hi);
    cv::putText(img, text, {x0 + 206, y0 + 11}, cv::FONT_HERSHEY_SIMPLEX, 0.45, kBlack, 1,
                cv::LINE_AA);
}

Result<MapImage> renderMapOrThrow(const MapRaster& r, Colouring colouring,
                                  std::span<const journal::TrajectoryPose> trajectory,
                                  const std::string& title, int max_px);

}  // namespace

Result<MapImage> renderMap(const MapRaster& r, Colouring colouring,
                           std::span<const journal::TrajectoryPose> trajectory,
                           const std::string& title, int max_px) {
    try {
        return renderMapOrThrow(r, colouring, trajectory, title, max_px);
    } catch (const cv::Exception& e) {  // OpenCV reports misuse by exception: never crash an export
        return Status(StatusCode::kInvalidArgument,
                      "report: cannot draw '" + title + "': " + e.what());
    }
}

namespace {

Result<MapImage> renderMapOrThrow(const MapRaster& r, Colouring colouring,
                                  std::span<const journal::TrajectoryPose> trajectory,
                                  const std::string& title, int max_px) {
    const Crop c = occupied(r);
    cv::Mat img;
    double scale = 1.0;  // pixels per (merged) cell
    float lo = 0, hi = 1;
    Grid g;
    if (c.empty()) {
        img = cv::Mat(200, 400, CV_8UC3, kWhite);
        cv::putText(img, "no points", {140, 100}, cv::FONT_HERSHEY_SIMPLEX, 0.8, kBlack, 2);
    } else {
        g = denseGrid(r, c);
        if (colouring == Colouring::kHeight) std::tie(lo, hi) = heightRange(g);
        const cv::Mat cells = cellsImage(g, colouring, lo, hi);
        scale = std::min(double(max_px) / cells.cols, double(max_px) / cells.rows);
        if (scale >= 1.0) scale = std::min(std::floor(scale), 16.0);
        cv::resize(cells, img, {}, scale, scale, scale >= 1.0 ? cv::INTER_NEAREST : cv::INTER_AREA);
    }
    cv::copyMakeBorder(img, img, kMargin, kMargin, kMargin, kMargin, cv::BORDER_CONSTANT, kWhite);
    if (!c.empty()) {
        // World (u, v) to pixels of the cropped, scaled, bordered image.
        const double u_left = r.u0() + c.i0 * r.cell(), v_top = r.v0() + (c.j1 + 1) * r.cell();
        const double cell = r.cell() * g.f;
        auto px = [&](const journal::TrajectoryPose& p) {
            const double u = p.x, v = r.view() == View::kTop ? p.y : p.z;
            return cv::Point(static_cast<int>(kMargin + (u - u_left) / cell * scale),
                             static_cast<int>(kMargin + (v_top - v) / cell * scale));
        };
        if (!trajectory.empty()) {
            std::vector<cv::Point> path;
            const std::size_t step = std::max<std::size_t>(1, trajectory.size() / 5000);
            for (std::size_t k = 0; k < trajectory.size(); k += step)
                path.push_back(px(trajectory[k]));
            path.push_back(px(trajectory.back()));
            cv::polylines(img, path, false, cv::Scalar(40, 40, 40), 4, cv::LINE_AA);
            cv::polylines(img, path, false, cv::Scalar(255, 0, 255), 2, cv::LINE_AA);
            cv::circle(img, path.front(), 8, kBlack, 2, cv::LINE_AA);
            cv::rectangle(img, path.back() - cv::Point(7, 7), path.back() + cv::Point(7, 7), kBlack,
                          2);
        }
        scaleBar(img, cell / scale);
        if (colouring == Colouring::kHeight) heightLegend(img, lo, hi);
    }
    cv::putText(img, title, {kMargin, 30}, cv::FONT_HERSHEY_SIMPLEX, 0.7, kBlack, 2, cv::LINE_AA);
    MapImage out;
    out.width = img.cols;
    out.height = img.rows;
    if (!cv::imencode(".png", img, out.png))
        return Status(StatusCode::kIoError, "report: PNG encoding of '" + title + "' failed");
    return out;
}

}  // namespace

Status writePng(const std::string& path, const MapImage& image) {
    std::ofstream f(path, std::ios::binary);
    f.write(reinterpret_cast<const char*>(image.png.data()),
            static_cast<std::streamsize>(image.png.size()));
    if (!f) return Status(StatusCode::kIoError, "cannot write " + path + " (directory exists?)");
    return Status::ok();
}

}  // namespace handscan::report
