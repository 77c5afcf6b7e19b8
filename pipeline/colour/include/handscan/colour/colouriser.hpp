// Colourisation of registered laser points with the HD colour camera (paper section 10.2: the
// laser map is coloured by a 1600x1200 camera at 5 Hz). The Colouriser keeps the last few colour
// frames, already decoded to BGR by the camera driver (camera::toBgr: YUYV, MJPEG), with their
// mid-exposure host times; it never sees a wire format. For a batch of world-frame
// points with their capture times it picks, per point, the frame closest in time (falling back to
// the other bracketing frame when the closest cannot see the point), moves the point into the
// colour camera with the body pose AT THAT FRAME'S TIME (the device moves between the laser
// return and the exposure), projects it through cam1 and samples the image bilinearly.
//
//   p_colour = T_colour_tracking * T_world_body(t_image)^-1 * p_world
//
// A point is rejected when it is behind the camera, outside the image, beyond max_range_m, or
// occluded: a coarse z-buffer of the whole batch, per frame, keeps only the nearest surface of
// each cell. Rejected points keep status != kColoured so the caller can keep intensity grey.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <deque>
#include <functional>
#include <span>
#include <vector>

#include "handscan/colour/camera_projection.hpp"
#include "handscan/core/config.hpp"
#include "handscan/core/samples.hpp"
#include "handscan/core/status.hpp"
#include "handscan/core/time.hpp"

namespace handscan::colour {

// T_world_body (body = tracking camera {C}) at any host time.
using PoseAtFn = std::function<Eigen::Isometry3d(TimeNs)>;

struct ColouriserConfig {
    std::size_t max_images = 8;  // frames kept (8 at 5 Hz: 1.6 s, more than a sweep)
    TimeNs max_time_offset_ns =
        250 * kNsPerMs;                   // a frame further than this from the point is not used
    double min_depth_m = 0.05;            // closer than this to the colour camera: not coloured
    double max_range_m = 12.0;            // farther: too few pixels per point and too much parallax
    int zbuffer_cell_px = 8;              // z-buffer cell edge in image pixels
    int zbuffer_splat_cells = 1;          // each point also occludes this many neighbouring cells
    double occlusion_tolerance_m = 0.05;  // a point within this of the cell's nearest depth ...
    double occlusion_tolerance_rel = 0.03;  // ... plus this fraction of its depth is on the surface
    int border_px = 1;                      // samples need this many pixels to the image edge
};

enum class ColourStatus : std::uint8_t {
    kColoured = 0,
    kNoImage,   // no frame within max_time_offset_ns of the point's time
    kBehind,    // behind (or too close to) the colour camera
    kOutside,   // projects outside the image
    kTooFar,    // beyond max_range_m
    kOccluded,  // a nearer surface covers it in the z-buffer
};
const char* toString(ColourStatus status);

struct ColourResult {
    std::vector<std::array<std::uint8_t, 3>> rgb;  // R, G, B; {0, 0, 0} where not coloured
    std::vector<ColourStatus> status;  // per point; for rejects: the closest frame's reason
    std::vector<std::uint32_t> image_sequence;  // sequence of the frame that coloured each point
    std::size_t coloured = 0;

    bool valid(std::size_t i) const { return status[i] == ColourStatus::kColoured; }
    std::size_t size() const { return status.size(); }
    std::size_t count(ColourStatus s) const;
};

class Colouriser {
public:
    // `calibration.colour` is cam1 of the camchain and `T_colour_tracking` its T_cn_cnm1.
    // Throws std::invalid_argument for a camera model we cannot project (start-up only).
    Colouriser(const Calibration& calibration, ColouriserConfig config = {});

    // Keeps a decoded colour frame (PixelFormat::kBgr8, rows of stride_bytes); the oldest frame
    // goes when the buffer is full. Errors name the frame: not BGR8, a size that is not cam1's
    // resolution, or a frame older than the buffer. The buffer is unchanged on error. Taken by
    // value: a caller done with its frame moves it in (1600x1200 BGR is 5.8 MB to copy).
    [[nodiscard]] Status addImage(Image image);

    // Colours each point (world frame, captured at times[i]); points.size() must equal
    // times.size(). `pose_at` is called once per buffered frame that some point can use, with that
    // frame's mid-exposure t_host (so the pose history must cover the frames, not only the points).
    // Cost: about 0.1 s of one core per million points per frame used (tests/bench/colour).
    // Never throws unless pose_at does: a size mismatch gives every point kNoImage.
    ColourResult colourise(std::span<const Eigen::Vector3f> points_world,
                           std::span<const TimeNs> times, const PoseAtFn& pose_at) const;

    std::size_t imageCount() const { return images_.size(); }
    // Host times of the buffered frames, oldest first (empty when none).
    TimeNs oldestImageTime() const { return images_.empty() ? 0 : images_.front().t_host; }
    TimeNs newestImageTime() const { return images_.empty() ? 0 : images_.back().t_host; }
    void clear() { images_.clear(); }

    const CameraProjection& projection() const { return projection_; }
    const ColouriserConfig& config() const { return config_; }

private:
    CameraProjection projection_;
    Eigen::Isometry3d T_colour_tracking_;
    ColouriserConfig config_;
    std::deque<Image> images_;  // BGR8, packed, sorted by t_host
};

}  // namespace handscan::colour
