// Test scenes for the VIO: a box room of textured walls (random grey blocks, blurred, 8 cm) seen
// by a camchain camera, rendered by casting each pixel's ray (pixels unprojected once with
// OpenCV's undistortPoints / fisheye::undistortPoints), laser-like points sampled on the same
// walls, and a smooth hand-held-like trajectory that returns to its start (so a benchmark can
// loop over it).
#pragma once

#include <Eigen/Geometry>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <random>
#include <vector>

#include "handscan/core/config.hpp"
#include "handscan/core/se3.hpp"

namespace handscan::vio::test {

// A textured rectangle o + u a + v b, u in [0, size_u], v in [0, size_v] (metres).
struct Wall {
    Eigen::Vector3d o, a, b;
    double size_u, size_v;
    cv::Mat texture;  // CV_32F, texels_per_m
};

class SyntheticRoom {
public:
    static constexpr double kTexelsPerM = 100.0;

    explicit SyntheticRoom(unsigned seed = 1, bool textured = true) {
        std::mt19937 rng(seed);
        // Camera frame convention (OpenCV): x right, y down, z forward; the room is 6 x 3 x 7 m.
        add({-3, -1.5, 4}, {1, 0, 0}, {0, 1, 0}, 6, 3, rng, textured);   // front wall
        add({-3, -1.5, -3}, {0, 0, 1}, {0, 1, 0}, 7, 3, rng, textured);  // left wall
        add({3, -1.5, -3}, {0, 0, 1}, {0, 1, 0}, 7, 3, rng, textured);   // right wall
        add({-3, 1.5, -3}, {1, 0, 0}, {0, 0, 1}, 6, 7, rng, textured);   // floor
        add({-3, -1.5, -3}, {1, 0, 0}, {0, 0, 1}, 6, 7, rng, textured);  // ceiling
        add({-3, -1.5, -3}, {1, 0, 0}, {0, 1, 0}, 6, 3, rng, textured);  // back wall
    }

    // Nearest wall hit along o + s d: distance and grey value.
    bool cast(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double& s_hit,
              float& grey) const {
        s_hit = 1e30;
        bool hit = false;
        for (const Wall& w : walls_) {
            const Eigen::Vector3d n = w.a.cross(w.b);
            const double den = n.dot(d);
            if (std::abs(den) < 1e-12) continue;
            const double s = n.dot(w.o - o) / den;
            if (s <= 1e-6 || s >= s_hit) continue;
            const Eigen::Vector3d p = o + s * d - w.o;
            const double u = p.dot(w.a), v = p.dot(w.b);
            if (u < 0 || v < 0 || u > w.size_u || v > w.size_v) continue;
            s_hit = s;
            grey = sample(w.texture, u * kTexelsPerM, v * kTexelsPerM);
            hit = true;
        }
        return hit;
    }

private:
    static float sample(const cv::Mat& tex, double x, double y) {
        const int x0 = std::clamp(static_cast<int>(x), 0, tex.cols - 2);
        const int y0 = std::clamp(static_cast<int>(y), 0, tex.rows - 2);
        const float fx = static_cast<float>(std::clamp(x - x0, 0.0, 1.0));
        const float fy = static_cast<float>(std::clamp(y - y0, 0.0, 1.0));
        const float* r0 = tex.ptr<float>(y0);
        const float* r1 = tex.ptr<float>(y0 + 1);
        return (1 - fy) * ((1 - fx) * r0[x0] + fx * r0[x0 + 1]) +
               fy * ((1 - fx) * r1[x0] + fx * r1[x0 + 1]);
    }

    void add(Eigen::Vector3d o, Eigen::Vector3d a, Eigen::Vector3d b, double su, double sv,
             std::mt19937& rng, bool textured) {
        const int w = static_cast<int>(su * kTexelsPerM) + 2;
        const int h = static_cast<int>(sv * kTexelsPerM) + 2;
        cv::Mat tex(h, w, CV_32F, cv::Scalar(128));
        if (textured) {
            std::uniform_real_distribution<float> grey(30.f, 220.f);
            for (int y = 0; y < h; y += 8)
                for (int x = 0; x < w; x += 8)
                    tex(cv::Rect(x, y, std::min(8, w - x), std::min(8, h - y))).setTo(grey(rng));
            cv::GaussianBlur(tex, tex, cv::Size(0, 0), 1.0);
        }
        walls_.push_back({o, a, b, su, sv, tex});
    }

    std::vector<Wall> walls_;
};

// Unit viewing rays of every pixel of a camchain camera (row-major).
inline std::vector<Eigen::Vector3d> pixelRays(const CameraIntrinsics& cam) {
    const int w = cam.resolution[0], h = cam.resolution[1];
    std::vector<cv::Point2d> px;
    px.reserve(static_cast<std::size_t>(w) * h);
    for (int v = 0; v < h; ++v)
        for (int u = 0; u < w; ++u) px.emplace_back(u, v);
    const cv::Matx33d K(cam.intrinsics[0], 0, cam.intrinsics[2], 0, cam.intrinsics[1],
                        cam.intrinsics[3], 0, 0, 1);
    std::vector<cv::Point2d> norm;
    if (cam.distortion_model == "equidistant") {
        cv::fisheye::undistortPoints(px, norm, K, cam.distortion_coeffs);
    } else if (cam.distortion_model == "radtan") {
        cv::undistortPoints(px, norm, K, cam.distortion_coeffs);
    } else {
        cv::undistortPoints(px, norm, K, cv::noArray());
    }
    std::vector<Eigen::Vector3d> rays(norm.size());
    for (std::size_t i = 0; i < norm.size(); ++i)
        rays[i] = Eigen::Vector3d(norm[i].x, norm[i].y, 1.0).normalized();
    return rays;
}

// A grey frame of the room from T_world_cam, with Gaussian noise of `noise_dn`.
inline cv::Mat render(const SyntheticRoom& room, const std::vector<Eigen::Vector3d>& rays, int w,
                      int h, const Eigen::Isometry3d& T_world_cam, double noise_dn,
                      std::mt19937& rng, double brightness = 1.0) {
    cv::Mat img(h, w, CV_8UC1);
    std::normal_distribution<float> noise(0.f, static_cast<float>(noise_dn));
    const Eigen::Vector3d o = T_world_cam.translation();
    const Eigen::Matrix3d R = T_world_cam.linear();
    for (int v = 0; v < h; ++v) {
        auto* row = img.ptr<unsigned char>(v);
        for (int u = 0; u < w; ++u) {
            double s;
            float g = 0.f;
            room.cast(o, R * rays[static_cast<std::size_t>(v) * w + u], s, g);
            const float val =
                static_cast<float>(brightness) * g + (noise_dn > 0 ? noise(rng) : 0.f);
            row[u] = static_cast<unsigned char>(std::clamp(val + 0.5f, 0.f, 255.f));
        }
    }
    return img;
}

// Laser-like points: `count` random rays of the camera's half space from T_world_cam, hit on the
// walls, with range noise.
inline std::vector<Eigen::Vector3d> laserPoints(const SyntheticRoom& room,
                                                const Eigen::Isometry3d& T_world_cam, int count,
                                                double range_sigma_m, std::mt19937& rng) {
    std::normal_distribution<double> n01(0.0, 1.0);
    std::vector<Eigen::Vector3d> pts;
    for (int i = 0; i < count; ++i) {
        Eigen::Vector3d d(n01(rng), n01(rng), std::abs(n01(rng)) + 0.3);
        d = T_world_cam.linear() * d.normalized();
        double s;
        float g;
        if (!room.cast(T_world_cam.translation(), d, s, g)) continue;
        pts.push_back(T_world_cam.translation() + (s + range_sigma_m * n01(rng)) * d);
    }
    return pts;
}

// A hand-held-like motion with period `period_s` (returns to its start): sways of +-0.3 m and
// +-12 deg of yaw, smaller pitch and roll.
inline Eigen::Isometry3d trajectory(double t, double period_s) {
    const double w = 2.0 * M_PI / period_s;
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = Eigen::Vector3d(0.3 * std::sin(w * t), 0.1 * std::sin(2 * w * t),
                                      0.4 * (1 - std::cos(w * t)));
    T.linear() = expSO3(Eigen::Vector3d(0.05 * std::sin(2 * w * t), 0.2 * std::sin(w * t),
                                        0.03 * std::sin(3 * w * t)));
    return T;
}

}  // namespace handscan::vio::test
