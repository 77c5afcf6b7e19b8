// VizWriter: what the pipeline measured, written as an MCAP file with standard, self-describing
// channels (message encoding "protobuf", each schema a FileDescriptorSet), for Foxglove or any
// MCAP + protobuf reader. Channels (frame ids: world, body = the tracking camera {C}, laser,
// imu, camera_track, camera_colour, groundtruth_world):
//   /pose               foxglove.PoseInFrame       every 200 Hz integrated pose, in world
//   /path               foxglove.PosesInFrame      the trajectory so far once per sweep (poses
//                                                  10 cm or 10 deg apart, at most 2000)
//   /tf                 foxglove.FrameTransforms   world->body and body->laser (encoder angle
//                                                  interpolated at the pose's time) with every
//                                                  pose; body->imu/cameras (camchain) per sweep
//   /sweep              foxglove.PointCloud        each registered sweep's points, in world
//   /map                foxglove.PointCloud        the display map (5 cm voxels) once per sweep
//   /imu                handscan.msgs.Imu          every IMU sample (gyro, accelerometer)
//   /status             handscan.msgs.PipelineStatus    once per sweep: solved directions,
//                                                  degeneracy, match, tracking, sensor rates
//   /camera/track, /camera/colour                  foxglove.CompressedImage (JPEG)
//   /camera/track/calibration, /camera/colour/calibration  foxglove.CameraCalibration
//   /groundtruth/pose   foxglove.PoseInFrame       the recording's ground truth, when it has one,
//                                                  in groundtruth_world; /tf aligns that with
//                                                  world at the first estimated pose
// Log times are the host monotonic times of what each message shows. Not thread-safe.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include "handscan/core/config.hpp"
#include "handscan/core/samples.hpp"
#include "handscan/core/status.hpp"
#include "handscan/journal/map_point.hpp"
#include "handscan/journal/sweep_record.hpp"
#include "handscan/lio/laser_inertial_odometry.hpp"
#include "handscan/recording/channels.hpp"

namespace handscan::viz {

struct VizConfig {
    float map_voxel_m = 0.05f;            // the display map's voxel, as the touch screen's
    std::size_t map_max_points = 100000;  // a /map snapshot beyond this is thinned (DisplayMap)
    std::size_t path_max_poses = 2000;    // a longer /path is thinned evenly
    // /map at most this often (0: with every sweep). Beyond map_max_points each snapshot is the
    // largest message; a journal's viz (one per 0.5 s window) sets 2 s to stay small.
    double map_every_s = 0.0;
    int jpeg_quality = 80;
    // Frames that must be encoded (not already JPEG or PNG) and are wider than this are halved
    // until they fit (encoding a 1600 px frame whole costs replay time a viewer does not need).
    // The calibration published with them is scaled to match.
    int max_image_width = 800;
    // The tracking camera's 50 Hz frames are shown at most this often (0: all): a viewer's image
    // panel needs no more, and they are most of the file and of its cost (each ~150 kB of PNG).
    double track_camera_max_hz = 10.0;
    std::string library = "handscan-viz";
    // Chunks stored as they are: most of the bytes are PNG and JPEG frames already compressed,
    // and zstd (level 1) on the rest saved 10 % of the file for 5-10 % more replay time (12 s
    // office walk: 56.7 MB with zstd, 62.6 MB without; the recording is 109 MB).
    std::string compression;
};

enum class Camera : std::uint8_t { kTrack = 0, kColour = 1 };

class VizWriter {
public:
    [[nodiscard]] static Result<std::unique_ptr<VizWriter>> create(const std::string& path,
                                                                   const Calibration& calibration,
                                                                   VizConfig config = {});
    ~VizWriter();
    VizWriter(const VizWriter&) = delete;
    VizWriter& operator=(const VizWriter&) = delete;

    [[nodiscard]] Status pose(const PoseEstimate& pose);
    // The shaft angle for body->laser; samples in time order, ahead of the poses they serve.
    [[nodiscard]] Status encoder(const EncoderSample& sample);
    [[nodiscard]] Status imu(const ImuSample& sample);
    // A frame to show: a JPEG a browser decodes is kept as it is, anything else is JPEG-encoded.
    [[nodiscard]] Status image(Camera camera, const Image& image);
    // A frame already compressed as `format` ("png", "jpeg"): written as it is, no decoding.
    [[nodiscard]] Status compressedImage(Camera camera, TimeNs t,
                                         std::span<const std::uint8_t> data, const char* format,
                                         int width, int height);
    [[nodiscard]] Status groundTruth(const recording::GroundTruthPose& pose);
    // `points`: the sweep's map points as journaled (empty when the tracking monitor kept the
    // sweep out of the map: then only its status is written); `devices`: its sweep record's
    // sample counts, the status' device rates.
    [[nodiscard]] Status sweep(const lio::RegisteredSweep& sweep,
                               std::span<const journal::MapPoint> points,
                               const journal::DeviceCounts& devices);
    // Map points without the matcher's sweep (a journal's): /sweep, /map and /path at `t`, no
    // /status.
    [[nodiscard]] Status mapPoints(TimeNs t, std::span<const journal::MapPoint> points);
    [[nodiscard]] Status close();

    std::uint64_t bytesWritten() const;
    std::uint64_t messageCount() const;

private:
    struct Impl;
    explicit VizWriter(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

}  // namespace handscan::viz
