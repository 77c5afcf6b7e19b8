// Camera rendering by ray casting. A camera is a Kalibr camchain entry (pinhole projection with
// equidistant or radtan distortion); each pixel's viewing ray is precomputed once. Rendering is
// fast because most pixels never trace a ray: a coarse grid of rays (every `coarse` pixels) is
// cast with Embree; inside a grid cell whose four corner rays hit the same plane (same material),
// every pixel is the exact ray-plane intersection; only cells on an edge cast their pixels' rays.
// Shading: material colour x procedural texture (mip-mapped by the pixel footprint) x a fixed
// diffuse light; exposure, vignetting, shot + read noise, 8-bit quantisation, optional motion
// blur (sub-frames over the exposure) and a --dark mode (little light: camera degeneracy).
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "handscan/core/config.hpp"
#include "handscan/sim/random.hpp"
#include "handscan/sim/raycaster.hpp"

namespace handscan::sim {

struct CameraRenderConfig {
    int coarse = 4;                       // grid spacing of the coarse rays, pixels
    double exposure_s = 0.005;            // exposure time
    double reference_exposure_s = 0.005;  // exposure at which a white wall reaches ~full scale
    double illumination = 1.0;            // scene light (--dark: 0.02)
    double gain = 1.7;  // analogue gain: indoor auto-exposure puts the mean near mid-grey
    // Temporal noise of a low-noise global-shutter pixel (Sony Pregius class, EMVA 1288 figures:
    // a few e- of dark noise, a ~20 ke- well): 8 bits hold ~85 e- per DN at unity gain, ~50 e-
    // behind the gain of 1.7, so the read noise is ~0.05-0.1 DN and shot noise dominates with a
    // variance of ~1/50 DN per DN of signal. (1 DN of read noise, the earlier value, is an old
    // CMOS sensor's; it added ~0.3 bit per pixel that the lossless recording had to store.)
    double read_noise_dn = 0.1;     // sigma, digital numbers
    double shot_noise_gain = 0.02;  // variance per DN of signal
    bool motion_blur = false;
    int blur_samples = 3;
    bool colour = false;  // RGB output (colour camera) instead of grey
    // Shading resolution relative to the output (1: every pixel; 0.5: a quarter of the pixels,
    // bilinearly upsampled before noise - enough for colourising points, 4x cheaper).
    double render_scale = 1.0;
};

// Unprojects pixel centres of a camchain camera to unit rays in the camera frame.
std::vector<Eigen::Vector3f> cameraRays(const CameraIntrinsics& cam);

class CameraRenderer {
public:
    CameraRenderer(const CameraIntrinsics& intrinsics, const CameraRenderConfig& config,
                   const Raycaster& raycaster, Rng rng);

    int width() const { return w_; }
    int height() const { return h_; }
    // Renders one frame exposed from t_start for exposure_s; `pose(t)` gives T_world_camera.
    // Grey: width*height bytes. Colour: width*height*3 bytes RGB.
    void render(double t_start, const std::function<Eigen::Isometry3d(double)>& pose,
                std::vector<std::uint8_t>& out);

    std::uint64_t raysCast() const { return rays_cast_; }
    std::uint64_t pixelsRendered() const { return pixels_; }

private:
    // Linear radiance (per channel) of every pixel for a camera at pose T.
    void radiance(const Eigen::Isometry3d& T, std::vector<float>& rad);
    void shade(std::size_t pixel, const Eigen::Vector3f& origin, const Eigen::Vector3f& dir,
               float t, std::uint32_t triangle, float* out) const;

    CameraIntrinsics intr_;
    CameraRenderConfig cfg_;
    const Raycaster& rc_;
    Rng rng_;
    int w_, h_;    // output size
    int rw_, rh_;  // shading size (render_scale)
    int channels_;
    std::vector<Eigen::Vector3f> dirs_;  // unit rays in the camera frame
    std::vector<float> vignette_;
    float pixel_angle_;                    // radians per pixel near the centre
    std::vector<std::uint32_t> plane_id_;  // per triangle: same id = same plane and material
    std::vector<Eigen::Vector4f> planes_;  // per triangle: n, d with n.x = d
    std::vector<float> gauss_table_;       // standard normal quantiles
    std::vector<std::size_t> up_x0_;       // upsampling: left source column per output column
    std::vector<float> up_tx_;             // ... and the weight of the right one
    std::vector<Ray> rays_;
    std::vector<RayHit> hits_;
    std::vector<float> rad_, acc_, full_;
    std::uint64_t rays_cast_ = 0;
    std::uint64_t pixels_ = 0;
};

}  // namespace handscan::sim
