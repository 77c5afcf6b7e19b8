#include "handscan/calibrate/camchain_check.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <variant>

#include "handscan/calibrate/gyro_alignment.hpp"
#include "handscan/calibrate/recorded_observations.hpp"
#include "handscan/camera/image_convert.hpp"
#include "handscan/colour/camera_projection.hpp"
#include "handscan/core/se3.hpp"
#include "handscan/sources/recorded_source.hpp"
#include "handscan/tum/trajectory_pose.hpp"

namespace handscan::calibrate {
namespace {

constexpr double kDeg = M_PI / 180.0;
// Neighbouring Hokuyo steps are 25 us apart (1440 steps per 37.5 ms turn of the mirror): two
// observations further apart in time are not neighbours on the scan line (a dropped return).
constexpr TimeNs kMaxStepGap = TimeNs{40} * 1000;

struct Camera {
    std::string name;
    const CameraIntrinsics* intrinsics;
    Eigen::Isometry3d T_cam_body;
};

struct Frame {
    TimeNs t = 0;
    cv::Mat edges;  // CV_32F, edge strength 0..1
};

// A depth edge in the camera frame at its frame's time, with its weight.
struct EdgePoint {
    Eigen::Vector3d p_cam;
    double weight;
    int frame;
};

bool untrusted(double t, const std::vector<std::pair<double, double>>& spans, double margin) {
    return std::any_of(spans.begin(), spans.end(), [&](const auto& s) {
        return t >= s.first - margin && t <= s.second + margin;
    });
}

// Intensity edges, smoothed so that a projection a few pixels off still scores part of the edge,
// and normalised per image (its 99th percentile is 1) so that bright and dark frames count alike.
cv::Mat edgeStrength(const Image& grey) {
    const cv::Mat view(grey.height, grey.width, CV_8UC1,
                       const_cast<std::uint8_t*>(grey.data.data()),
                       static_cast<std::size_t>(grey.stride_bytes));
    cv::Mat f, gx, gy, mag;
    view.convertTo(f, CV_32F, 1.0 / 255.0);
    cv::GaussianBlur(f, f, cv::Size(0, 0), 1.0);
    cv::Sobel(f, gx, CV_32F, 1, 0);
    cv::Sobel(f, gy, CV_32F, 0, 1);
    cv::magnitude(gx, gy, mag);
    const double sigma = std::max(1.0, 0.0025 * grey.width);  // 1.6 px at 640, 4 px at 1600
    cv::GaussianBlur(mag, mag, cv::Size(0, 0), sigma);
    std::vector<float> values(mag.begin<float>(), mag.end<float>());
    const auto k = static_cast<std::ptrdiff_t>(0.99 * static_cast<double>(values.size()));
    std::nth_element(values.begin(), values.begin() + k, values.end());
    const float top = std::max(1e-6F, values[static_cast<std::size_t>(k)]);
    cv::min(mag / top, 1.0, mag);
    return mag;
}

float sample(const cv::Mat& m, const Eigen::Vector2d& px) {
    const double x = std::floor(px.x()), y = std::floor(px.y());
    if (x < 0 || y < 0 || x + 1 >= m.cols || y + 1 >= m.rows) return 0.0F;
    const auto c = static_cast<int>(x), r = static_cast<int>(y);
    const auto u = static_cast<float>(px.x() - x), v = static_cast<float>(px.y() - y);
    return (1 - v) * ((1 - u) * m.at<float>(r, c) + u * m.at<float>(r, c + 1)) +
           v * ((1 - u) * m.at<float>(r + 1, c) + u * m.at<float>(r + 1, c + 1));
}

// Mean edge strength under the depth edges of `frames` (a subset; all when empty) turned by `turn`.
double score(const std::vector<EdgePoint>& points, const std::vector<Frame>& images,
             const colour::CameraProjection& projection, const Eigen::Vector3d& turn_rad,
             const std::vector<bool>* use_frame) {
    const Eigen::Matrix3d R = expSO3(turn_rad);
    double sum = 0.0, weights = 0.0;
    for (const EdgePoint& e : points) {
        if (use_frame != nullptr && !(*use_frame)[static_cast<std::size_t>(e.frame)]) continue;
        weights += e.weight;
        if (auto px = projection.project(R * e.p_cam))
            sum += e.weight * sample(images[static_cast<std::size_t>(e.frame)].edges, *px);
    }
    return weights > 0.0 ? sum / weights : 0.0;
}

// The best turn on a grid of `step` within `half_width` of `centre` (each axis).
Eigen::Vector3d bestTurn(const std::vector<EdgePoint>& points, const std::vector<Frame>& images,
                         const colour::CameraProjection& projection, const Eigen::Vector3d& centre,
                         double half_width, double step, const std::vector<bool>* use_frame,
                         double* best_score) {
    const int n = static_cast<int>(std::lround(half_width / step));
    Eigen::Vector3d best = centre;
    double top = -1.0;
    for (int i = -n; i <= n; ++i)
        for (int j = -n; j <= n; ++j)
            for (int k = -n; k <= n; ++k) {
                const Eigen::Vector3d t = centre + step * Eigen::Vector3d(i, j, k);
                const double s = score(points, images, projection, t, use_frame);
                if (s > top) {
                    top = s;
                    best = t;
                }
            }
    if (best_score != nullptr) *best_score = top;
    return best;
}

// The fine steps around a coarse best turn: the score's peak is a few tenths of a degree wide.
Eigen::Vector3d refine(const std::vector<EdgePoint>& points, const std::vector<Frame>& images,
                       const colour::CameraProjection& projection, const Eigen::Vector3d& centre,
                       const std::vector<bool>* use_frame, double* best_score) {
    const Eigen::Vector3d t =
        bestTurn(points, images, projection, centre, 0.5 * kDeg, 0.125 * kDeg, use_frame, nullptr);
    return bestTurn(points, images, projection, t, 0.1 * kDeg, 0.05 * kDeg, use_frame, best_score);
}

// Coarse to fine over the whole search range.
Eigen::Vector3d search(const std::vector<EdgePoint>& points, const std::vector<Frame>& images,
                       const colour::CameraProjection& projection, double search_rad,
                       const std::vector<bool>* use_frame, double* best_score) {
    const Eigen::Vector3d t = bestTurn(points, images, projection, Eigen::Vector3d::Zero(),
                                       search_rad, 0.5 * kDeg, use_frame, nullptr);
    return refine(points, images, projection, t, use_frame, best_score);
}

}  // namespace

Result<CamchainCheck> checkCamchain(const std::string& recording, const DeviceConfig& device,
                                    const Calibration& calibration,
                                    const tum::Trajectory& trajectory,
                                    const std::vector<std::pair<double, double>>& untrusted_s,
                                    const CamchainCheckOptions& o) {
    if (trajectory.size() < 2)
        return Status{StatusCode::kInvalidArgument, "camchain check: no replayed trajectory"};
    const std::vector<Camera> cameras = {
        {"tracking", &calibration.tracking, Eigen::Isometry3d::Identity()},
        {"colour", &calibration.colour, calibration.T_colour_tracking}};
    // Frame times: evenly over the walk (a second in from each end), none where tracking was not
    // trusted; per camera the first frame at or after each.
    const double t0 = trajectory.front().t_s + 1.0, t1 = trajectory.back().t_s - 1.0;
    std::vector<double> wanted;
    for (int i = 0; i < 4 * o.frames && t1 > t0; ++i) {
        const double t = t0 + (t1 - t0) * (i + 0.5) / (4 * o.frames);
        if (!untrusted(t, untrusted_s, o.window_s)) wanted.push_back(t);
    }
    while (wanted.size() > static_cast<std::size_t>(o.frames)) {
        std::vector<double> thinned;
        for (std::size_t i = 0; i < wanted.size(); i += 2) thinned.push_back(wanted[i]);
        wanted = std::move(thinned);
    }
    std::vector<std::vector<Frame>> frames(cameras.size());
    std::vector<std::size_t> next(cameras.size(), 0);
    {
        sources::RecordedSourceOptions so;
        so.laser = false;
        so.colour = true;
        so.tracking = true;
        so.fast = true;
        auto source = sources::RecordedSource::open(recording, device, so);
        if (!source.isOk()) return source.status();
        std::vector<sources::Sample> samples;
        for (;;) {
            samples.clear();
            auto clock = (*source)->next(samples);
            if (!clock.isOk()) return clock.status();
            for (const sources::Sample& s : samples) {
                const Image* image = nullptr;
                std::size_t c = 0;
                if (const auto* f = std::get_if<sources::TrackingFrame>(&s)) {
                    image = &f->image;
                    c = 0;
                } else if (const auto* i = std::get_if<Image>(&s)) {
                    image = i;
                    c = 1;
                }
                if (image == nullptr || next[c] >= wanted.size() ||
                    toSeconds(image->t_host) < wanted[next[c]])
                    continue;
                while (next[c] < wanted.size() && toSeconds(image->t_host) >= wanted[next[c]])
                    ++next[c];
                auto grey = camera::toGrey(*image);
                if (!grey.isOk()) return grey.status();
                frames[c].push_back({image->t_host, edgeStrength(*grey)});
            }
            if (!clock->has_value()) break;
        }
    }

    // The laser around those frames: every step, placed with the trajectory.
    std::vector<std::pair<double, double>> outside;  // everything but the frames' windows
    {
        std::vector<double> times;
        for (const auto& fs : frames)
            for (const Frame& f : fs) times.push_back(toSeconds(f.t));
        std::sort(times.begin(), times.end());
        double from = -1e18;
        for (double t : times) {
            if (t - o.window_s > from) outside.emplace_back(from, t - o.window_s);
            from = std::max(from, t + o.window_s);
        }
        outside.emplace_back(from, 1e18);
    }
    auto imu = loadImu(recording, device);
    if (!imu.isOk()) return imu.status();
    ObservationOptions oo;
    oo.step_stride = 1;
    oo.max_range_m = o.max_range_m + o.min_depth_jump_m;
    auto obs = loadObservations(recording, device, calibration, trajectory, outside, *imu, oo);
    if (!obs.isOk()) return obs.status();
    const PreparedSpin spin = SpinModel{calibration}.prepare(SpinCorrection::Vector::Zero());

    CamchainCheck out;
    for (std::size_t c = 0; c < cameras.size(); ++c) {
        if (frames[c].empty()) continue;
        const Camera& cam = cameras[c];
        const colour::CameraProjection projection(*cam.intrinsics);
        CamchainCameraCheck check;
        check.camera = cam.name;
        check.frames = frames[c].size();
        std::vector<Eigen::Isometry3d> T_cam_world;
        for (const Frame& f : frames[c])
            T_cam_world.push_back(cam.T_cam_body *
                                  tum::poseAt(trajectory, toSeconds(f.t)).inverse());
        // Depth edges: the nearer side of a jump between neighbouring steps of one scan line,
        // weighted by the square root of the jump (Levinson & Thrun), capped at 1 m.
        std::vector<EdgePoint> points;
        const std::vector<SpinObservation>& v = *obs;
        auto range = [](const SpinObservation& s) { return std::hypot(s.x_laser, s.y_laser); };
        for (std::size_t i = 0; i < v.size(); ++i) {
            double jump = 0.0;
            for (std::size_t j : {i - 1, i + 1})
                if (j < v.size() && v[j].scan == v[i].scan &&
                    std::abs(v[j].t - v[i].t) <= kMaxStepGap)
                    jump = std::max(jump, static_cast<double>(range(v[j]) - range(v[i])));
            if (jump < o.min_depth_jump_m || range(v[i]) > o.max_range_m) continue;
            // The frame whose window holds the step.
            for (std::size_t f = 0; f < frames[c].size(); ++f) {
                if (std::abs(toSeconds(v[i].t - frames[c][f].t)) > o.window_s) continue;
                const Eigen::Vector3d p = T_cam_world[f] * spin.world(v[i]);
                if (p.z() < 0.3) continue;
                if (!projection.project(p)) continue;
                points.push_back({p, std::sqrt(std::min(jump, 1.0)), static_cast<int>(f)});
            }
        }
        check.edge_points = points.size();
        if (points.size() < 200 || check.frames < static_cast<std::size_t>(o.groups)) {
            check.summary = fmt::format(
                "{} camera: not checked ({} frames, {} laser depth edges in view; a walk past "
                "doors, pillars or furniture gives more)",
                cam.name, check.frames, points.size());
            out.cameras.push_back(check);
            continue;
        }
        check.checked = true;
        check.score_given = score(points, frames[c], projection, Eigen::Vector3d::Zero(), nullptr);
        const Eigen::Vector3d best =
            search(points, frames[c], projection, o.search_deg * kDeg, nullptr, &check.score_best);
        // Scatter: the best turn of each group of frames (every groups-th frame), near the best.
        std::vector<Eigen::Vector3d> per_group;
        for (int g = 0; g < o.groups; ++g) {
            std::vector<bool> use(frames[c].size(), false);
            for (std::size_t f = static_cast<std::size_t>(g); f < use.size();
                 f += static_cast<std::size_t>(o.groups))
                use[f] = true;
            per_group.push_back(refine(points, frames[c], projection, best, &use, nullptr));
        }
        Eigen::Vector3d mean = Eigen::Vector3d::Zero();
        for (const auto& t : per_group) mean += t / static_cast<double>(per_group.size());
        Eigen::Vector3d var = Eigen::Vector3d::Zero();
        for (const auto& t : per_group)
            var += (t - mean).cwiseAbs2() / static_cast<double>(per_group.size() - 1);
        // The std of a group's turn over sqrt(groups): the all-frames turn's.
        check.turn_std_deg = (var / static_cast<double>(per_group.size())).cwiseSqrt() / kDeg;
        check.best_turn_deg = best / kDeg;
        const double turn = check.best_turn_deg.norm();
        const double std = std::max(0.05, check.turn_std_deg.norm());
        check.looks_wrong = turn >= o.min_turn_deg && turn > 3.0 * std;
        check.summary = fmt::format(
            "{} camera: laser depth edges fit the image edges best with the camera turned "
            "({:+.2f}, {:+.2f}, {:+.2f}) deg (x right, y down, z forward; std {:.2f}), edge "
            "score {:.3f} as is, {:.3f} turned ({} frames, {} edges): {}",
            cam.name, check.best_turn_deg.x(), check.best_turn_deg.y(), check.best_turn_deg.z(),
            check.turn_std_deg.norm(), check.score_given, check.score_best, check.frames,
            check.edge_points,
            check.looks_wrong
                ? fmt::format("LOOKS WRONG - the camchain's {} ({}) is off by about {:.1f} deg; "
                              "calibrate the cameras again with Kalibr",
                              c == 0 ? "cam0 intrinsics" : "cam1 T_cn_cnm1 or intrinsics", cam.name,
                              turn)
                : "consistent");
        out.cameras.push_back(check);
    }
    return out;
}

}  // namespace handscan::calibrate
