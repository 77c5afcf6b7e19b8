#include "handscan/colour/colouriser.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace handscan::colour {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr std::int16_t kNone = -1;

// A point projected into one frame: pixel and depth, or the reason it is not visible.
struct Projected {
    float u = 0, v = 0, z = 0;
    ColourStatus status = ColourStatus::kNoImage;
};

// Min-depth grid over the image at zbuffer_cell_px resolution, dilated by zbuffer_splat_cells so
// that sparse laser points of a near surface still cover the gaps between them.
class DepthGrid {
public:
    DepthGrid(int width, int height, int cell_px) : cell_(std::max(1, cell_px)) {
        gw_ = (width + cell_ - 1) / cell_;
        gh_ = (height + cell_ - 1) / cell_;
        z_.assign(static_cast<std::size_t>(gw_) * static_cast<std::size_t>(gh_), kInf);
    }
    float& at(float u, float v) { return z_[index(u, v)]; }
    float at(float u, float v) const { return z_[index(u, v)]; }
    void insert(float u, float v, float z) {
        float& c = at(u, v);
        c = std::min(c, z);
    }
    // Separable min filter of radius r cells.
    void dilate(int r) {
        if (r <= 0) return;
        std::vector<float> tmp(z_.size(), kInf);
        for (int y = 0; y < gh_; ++y) {
            for (int x = 0; x < gw_; ++x) {
                float m = kInf;
                for (int dx = std::max(0, x - r); dx <= std::min(gw_ - 1, x + r); ++dx)
                    m = std::min(m, z_[idx(dx, y)]);
                tmp[idx(x, y)] = m;
            }
        }
        for (int y = 0; y < gh_; ++y) {
            for (int x = 0; x < gw_; ++x) {
                float m = kInf;
                for (int dy = std::max(0, y - r); dy <= std::min(gh_ - 1, y + r); ++dy)
                    m = std::min(m, tmp[idx(x, dy)]);
                z_[idx(x, y)] = m;
            }
        }
    }

private:
    std::size_t idx(int x, int y) const {
        return static_cast<std::size_t>(y) * static_cast<std::size_t>(gw_) +
               static_cast<std::size_t>(x);
    }
    std::size_t index(float u, float v) const {
        // Pixel (0,0) is the centre of the top-left pixel: its area starts at -0.5.
        const int x =
            std::clamp(static_cast<int>((u + 0.5f) / static_cast<float>(cell_)), 0, gw_ - 1);
        const int y =
            std::clamp(static_cast<int>((v + 0.5f) / static_cast<float>(cell_)), 0, gh_ - 1);
        return idx(x, y);
    }
    int cell_, gw_ = 0, gh_ = 0;
    std::vector<float> z_;
};

// Bilinear sample of a packed BGR8 image at (u, v), returned as RGB.
std::array<std::uint8_t, 3> sampleRgb(const Image& bgr, float u, float v) {
    const int x0 = static_cast<int>(u), y0 = static_cast<int>(v);
    const float fx = u - static_cast<float>(x0), fy = v - static_cast<float>(y0);
    const std::size_t stride = static_cast<std::size_t>(bgr.stride_bytes);
    const std::uint8_t* p00 =
        bgr.data.data() + static_cast<std::size_t>(y0) * stride + static_cast<std::size_t>(x0) * 3;
    const std::uint8_t* p10 = p00 + 3;
    const std::uint8_t* p01 = p00 + stride;
    const std::uint8_t* p11 = p01 + 3;
    const float w00 = (1 - fx) * (1 - fy), w10 = fx * (1 - fy), w01 = (1 - fx) * fy, w11 = fx * fy;
    std::array<std::uint8_t, 3> rgb{};
    for (int c = 0; c < 3; ++c) {
        const float s = w00 * static_cast<float>(p00[c]) + w10 * static_cast<float>(p10[c]) +
                        w01 * static_cast<float>(p01[c]) + w11 * static_cast<float>(p11[c]);
        rgb[static_cast<std::size_t>(2 - c)] =
            static_cast<std::uint8_t>(std::clamp(s + 0.5f, 0.0f, 255.0f));
    }
    return rgb;
}

}  // namespace

const char* toString(ColourStatus s) {
    switch (s) {
        case ColourStatus::kColoured:
            return "coloured";
        case ColourStatus::kNoImage:
            return "no-image";
        case ColourStatus::kBehind:
            return "behind";
        case ColourStatus::kOutside:
            return "outside";
        case ColourStatus::kTooFar:
            return "too-far";
        case ColourStatus::kOccluded:
            return "occluded";
    }
    return "unknown";
}

std::size_t ColourResult::count(ColourStatus s) const {
    return static_cast<std::size_t>(std::count(status.begin(), status.end(), s));
}

Colouriser::Colouriser(const Calibration& calibration, ColouriserConfig config)
    : projection_(calibration.colour),
      T_colour_tracking_(calibration.T_colour_tracking),
      config_(config) {
    config_.max_images = std::max<std::size_t>(1, config_.max_images);
}

Status Colouriser::addImage(Image image) {
    const auto where = [&] {
        return "colour frame " + std::to_string(image.sequence) +
               " at t=" + std::to_string(image.t_host) + " ns";
    };
    if (image.width != projection_.width() || image.height != projection_.height()) {
        return {StatusCode::kInvalidArgument,
                where() + ": " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                    " but cam1 is calibrated at " + std::to_string(projection_.width()) + "x" +
                    std::to_string(projection_.height()) +
                    "; set the camera to the calibrated mode"};
    }
    if (images_.size() >= config_.max_images && image.t_host <= images_.front().t_host) {
        return {StatusCode::kInvalidArgument, where() +
                                                  ": older than every buffered frame (oldest t=" +
                                                  std::to_string(images_.front().t_host) +
                                                  " ns); frames must arrive roughly in order"};
    }
    if (image.format != PixelFormat::kBgr8 || image.stride_bytes < image.width * 3 ||
        image.data.size() <
            static_cast<std::size_t>(image.stride_bytes) * static_cast<std::size_t>(image.height)) {
        return {StatusCode::kInvalidArgument,
                where() + ": not a decoded BGR8 image of its size (format " +
                    std::to_string(static_cast<int>(image.format)) + ", stride " +
                    std::to_string(image.stride_bytes) + ", " + std::to_string(image.data.size()) +
                    " bytes); decode camera frames with camera::toBgr before colouring"};
    }
    const auto pos = std::upper_bound(images_.begin(), images_.end(), image.t_host,
                                      [](TimeNs t, const Image& im) { return t < im.t_host; });
    images_.insert(pos, std::move(image));
    while (images_.size() > config_.max_images) images_.pop_front();
    return Status::ok();
}

ColourResult Colouriser::colourise(std::span<const Eigen::Vector3f> points,
                                   std::span<const TimeNs> times, const PoseAtFn& pose_at) const {
    const std::size_t n = points.size();
    ColourResult out;
    out.rgb.assign(n, {0, 0, 0});
    out.status.assign(n, ColourStatus::kNoImage);
    out.image_sequence.assign(n, 0);
    if (times.size() != n || images_.empty() || n == 0) return out;

    // 1. Per point, the two frames bracketing its time, closest first, within the time limit.
    const std::size_t m = images_.size();
    std::vector<std::array<std::int16_t, 2>> cand(n, {kNone, kNone});
    std::vector<bool> used(m, false);
    for (std::size_t i = 0; i < n; ++i) {
        const auto it = std::lower_bound(images_.begin(), images_.end(), times[i],
                                         [](const Image& im, TimeNs t) { return im.t_host < t; });
        const auto after = static_cast<std::int64_t>(it - images_.begin());
        const std::int64_t before = after - 1;
        std::array<std::pair<TimeNs, std::int64_t>, 2> c{
            {{std::numeric_limits<TimeNs>::max(), kNone},
             {std::numeric_limits<TimeNs>::max(), kNone}}};
        if (before >= 0)
            c[0] = {times[i] - images_[static_cast<std::size_t>(before)].t_host, before};
        if (after < static_cast<std::int64_t>(m))
            c[1] = {images_[static_cast<std::size_t>(after)].t_host - times[i], after};
        if (c[1].first < c[0].first) std::swap(c[0], c[1]);
        int r = 0;
        for (const auto& [dt, k] : c) {
            if (k == kNone || dt > config_.max_time_offset_ns) continue;
            cand[i][static_cast<std::size_t>(r++)] = static_cast<std::int16_t>(k);
            used[static_cast<std::size_t>(k)] = true;
        }
    }

    // 2. Per frame: project the whole batch with the pose at the frame's time, build the z-buffer,
    //    then colour the points that chose this frame. A closest-frame colour replaces a
    //    second-choice one; a reject reason is only recorded from the closest frame.
    const float w = static_cast<float>(projection_.width()),
                h = static_cast<float>(projection_.height());
    const float border = static_cast<float>(std::max(0, config_.border_px));
    const float u_max = w - 1.0f - border, v_max = h - 1.0f - border;
    const float min_z = static_cast<float>(config_.min_depth_m);
    const float max_r2 = static_cast<float>(config_.max_range_m * config_.max_range_m);
    std::vector<Projected> proj(n);
    std::vector<std::int8_t> coloured_rank(n, -1);
    for (std::size_t k = 0; k < m; ++k) {
        if (!used[k]) continue;
        const Image& img = images_[k];
        const Eigen::Isometry3d T_colour_world = T_colour_tracking_ * pose_at(img.t_host).inverse();
        const Eigen::Matrix3f R = T_colour_world.linear().cast<float>();
        const Eigen::Vector3f t = T_colour_world.translation().cast<float>();
        DepthGrid grid(projection_.width(), projection_.height(), config_.zbuffer_cell_px);
        for (std::size_t i = 0; i < n; ++i) {
            Projected& p = proj[i];
            const Eigen::Vector3f pc = R * points[i] + t;
            if (!(pc.z() >= min_z)) {  // NaN points land here too
                p.status = ColourStatus::kBehind;
                continue;
            }
            if (pc.squaredNorm() > max_r2) {
                p.status = ColourStatus::kTooFar;
                continue;
            }
            const auto px = projection_.project(pc.cast<double>());
            if (!px ||
                !(px->x() >= border && px->x() <= u_max && px->y() >= border && px->y() <= v_max)) {
                p.status = ColourStatus::kOutside;
                continue;
            }
            p = {static_cast<float>(px->x()), static_cast<float>(px->y()), pc.z(),
                 ColourStatus::kColoured};
            grid.insert(p.u, p.v, p.z);
        }
        grid.dilate(config_.zbuffer_splat_cells);
        for (std::size_t i = 0; i < n; ++i) {
            const int rank = cand[i][0] == static_cast<std::int16_t>(k)   ? 0
                             : cand[i][1] == static_cast<std::int16_t>(k) ? 1
                                                                          : -1;
            if (rank < 0 || (coloured_rank[i] >= 0 && coloured_rank[i] <= rank)) continue;
            const Projected& p = proj[i];
            ColourStatus s = p.status;
            if (s == ColourStatus::kColoured) {
                const float tol = static_cast<float>(config_.occlusion_tolerance_m +
                                                     config_.occlusion_tolerance_rel * p.z);
                if (p.z > grid.at(p.u, p.v) + tol) s = ColourStatus::kOccluded;
            }
            if (s == ColourStatus::kColoured) {
                out.rgb[i] = sampleRgb(img, p.u, p.v);
                out.status[i] = s;
                out.image_sequence[i] = img.sequence;
                coloured_rank[i] = static_cast<std::int8_t>(rank);
            } else if (rank == 0 && coloured_rank[i] < 0) {
                out.status[i] = s;
            }
        }
    }
    out.coloured = static_cast<std::size_t>(
                       std::count(coloured_rank.begin(), coloured_rank.end(), std::int8_t{0})) +
                   static_cast<std::size_t>(
                       std::count(coloured_rank.begin(), coloured_rank.end(), std::int8_t{1}));
    return out;
}

}  // namespace handscan::colour
