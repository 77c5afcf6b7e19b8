#include "handscan/viz/viz_writer.hpp"

#include <algorithm>
#include <deque>
#include <map>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>

#include "foxglove/CameraCalibration.pb.h"
#include "foxglove/CompressedImage.pb.h"
#include "foxglove/FrameTransforms.pb.h"
#include "foxglove/PointCloud.pb.h"
#include "foxglove/PoseInFrame.pb.h"
#include "foxglove/PosesInFrame.pb.h"
#include "handscan/camera/image_convert.hpp"
#include "handscan/core/log.hpp"
#include "handscan/msgs/Imu.pb.h"
#include "handscan/msgs/PipelineStatus.pb.h"
#include "handscan/recording/mcap_writer.hpp"
#include "handscan/scan/sweep_assembler.hpp"
#include "handscan/viz/point_cloud.hpp"
#include "proto_schema.hpp"

namespace handscan::viz {
namespace {

constexpr const char* kWorld = "world";
constexpr const char* kBody = "body";
constexpr const char* kLaser = "laser";
constexpr const char* kImuFrame = "imu";
// The ground truth's own world (the simulator's scene frame), not the estimate's: /tf places it
// in world by the first estimated pose (see alignGroundTruth).
constexpr const char* kGroundTruthWorld = "groundtruth_world";
constexpr TimeNs kGroundTruthMatch = 10 * kNsPerMs;  // a ground-truth pose this close to a pose
constexpr const char* kCameraFrames[2] = {"camera_track", "camera_colour"};
constexpr const char* kImageTopics[2] = {"/camera/track", "/camera/colour"};
constexpr const char* kCalibrationTopics[2] = {"/camera/track/calibration",
                                               "/camera/colour/calibration"};
// Encoder samples further apart (or further from a pose) than this place no laser frame: the
// same bound the sweep assembler puts on a step's angle.
constexpr TimeNs kMaxEncoderGap = 50 * kNsPerMs;

void setTime(google::protobuf::Timestamp* ts, TimeNs t) {
    t = std::max<TimeNs>(t, 0);  // host monotonic time: never negative on a real clock
    ts->set_seconds(t / kNsPerSec);
    ts->set_nanos(static_cast<std::int32_t>(t % kNsPerSec));
}

void setIsometry(foxglove::Vector3* p, foxglove::Quaternion* q, const Eigen::Isometry3d& T) {
    p->set_x(T.translation().x());
    p->set_y(T.translation().y());
    p->set_z(T.translation().z());
    const Eigen::Quaterniond r(T.linear());
    q->set_x(r.x());
    q->set_y(r.y());
    q->set_z(r.z());
    q->set_w(r.w());
}

// The pose of `child` in `parent` (T_parent_child), as FrameTransform defines it.
void addTransform(foxglove::FrameTransforms& tf, TimeNs t, const char* parent, const char* child,
                  const Eigen::Isometry3d& T_parent_child) {
    foxglove::FrameTransform* f = tf.add_transforms();
    setTime(f->mutable_timestamp(), t);
    f->set_parent_frame_id(parent);
    f->set_child_frame_id(child);
    setIsometry(f->mutable_translation(), f->mutable_rotation(), T_parent_child);
}

// UVC cameras' MJPEG frames often lack the Huffman tables (DHT, 0xFFC4), which browsers' JPEG
// decoders (Foxglove's) need; libjpeg-turbo supplies the standard ones when decoding.
bool hasHuffmanTables(std::span<const std::uint8_t> jpeg) {
    for (std::size_t i = 0; i + 1 < jpeg.size(); ++i) {
        if (jpeg[i] != 0xFF) continue;
        if (jpeg[i + 1] == 0xC4) return true;
        if (jpeg[i + 1] == 0xDA) return false;  // start of scan: the tables come before it
    }
    return false;
}

// The frame as a cv::Mat (grey or BGR); a view of `image` where no conversion is needed.
Result<cv::Mat> toMat(const Image& image, Image& converted) {
    if (image.format == PixelFormat::kGrey8)
        return cv::Mat(image.height, image.width, CV_8UC1,
                       const_cast<std::uint8_t*>(image.data.data()),
                       static_cast<std::size_t>(image.stride_bytes));
    if (image.format != PixelFormat::kBgr8) {
        Result<Image> bgr = camera::toBgr(image);
        if (!bgr.isOk()) return bgr.status();
        converted = std::move(*bgr);
        return toMat(converted, converted);
    }
    return cv::Mat(image.height, image.width, CV_8UC3, const_cast<std::uint8_t*>(image.data.data()),
                   static_cast<std::size_t>(image.stride_bytes));
}

// K and P of a Kalibr camchain camera, scaled to an image `scale` times its calibrated size.
void fillCalibration(foxglove::CameraCalibration& c, const CameraIntrinsics& in, double scale) {
    const double fx = in.intrinsics[0] * scale, fy = in.intrinsics[1] * scale;
    // Pixel centres: (u + 0.5) scales, so cx' = (cx + 0.5) s - 0.5.
    const double cx = (in.intrinsics[2] + 0.5) * scale - 0.5;
    const double cy = (in.intrinsics[3] + 0.5) * scale - 0.5;
    c.clear_d();
    c.clear_k();
    c.clear_r();
    c.clear_p();
    for (double v : {fx, 0.0, cx, 0.0, fy, cy, 0.0, 0.0, 1.0}) c.add_k(v);
    for (double v : {1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0}) c.add_r(v);
    for (double v : {fx, 0.0, cx, 0.0, 0.0, fy, cy, 0.0, 0.0, 0.0, 1.0, 0.0}) c.add_p(v);
    // Kalibr's radtan is OpenCV's plumb_bob (k1 k2 p1 p2, k3 = 0). Its equidistant (fisheye
    // k1..k4) has no Foxglove model; it keeps ROS's name "equidistant" and its coefficients, so
    // nothing is lost, and a viewer that cannot rectify it shows the raw image.
    if (in.distortion_model == "radtan") {
        c.set_distortion_model("plumb_bob");
        for (double v : in.distortion_coeffs) c.add_d(v);
        while (c.d_size() < 5) c.add_d(0.0);
    } else if (in.distortion_model == "equidistant") {
        c.set_distortion_model("equidistant");
        for (double v : in.distortion_coeffs) c.add_d(v);
    } else {
        c.set_distortion_model("plumb_bob");
        for (int i = 0; i < 5; ++i) c.add_d(0.0);
    }
}

}  // namespace

struct VizWriter::Impl {
    Calibration calibration;
    VizConfig config;
    scan::SpinGeometry spin;
    std::unique_ptr<recording::McapWriter> mcap;
    std::map<std::string, std::uint16_t> schemas;
    std::uint16_t pose_ch = 0, path_ch = 0, tf_ch = 0, sweep_ch = 0, map_ch = 0, imu_ch = 0,
                  status_ch = 0, gt_ch = 0;
    std::uint16_t image_ch[2] = {0, 0}, calibration_ch[2] = {0, 0};
    std::string buffer;  // serialised message, reused
    DisplayMap map;
    std::deque<EncoderSample> encoder;  // the samples around the poses still to come
    TimeNs last_pose_t = 0;
    TimeNs last_track_t = 0;              // the last tracking-camera frame written
    TimeNs last_map_t = 0;                // the last /map snapshot written
    bool map_pending = false;             // points added since (map_every_s)
    std::vector<Eigen::Isometry3d> path;  // the trajectory's poses 10 cm or 10 deg apart
    std::deque<std::pair<TimeNs, Eigen::Isometry3d>> ground_truth;  // until the first pose
    std::optional<Eigen::Isometry3d> T_world_gtworld;
    bool static_tf_written = false;
    // Decoded samples since the last status, for its rates.
    std::uint64_t image_errors = 0;
    // Reused messages (their buffers keep their capacity).
    foxglove::PointCloud cloud;
    foxglove::FrameTransforms tf;
    foxglove::PoseInFrame pose_msg;
    foxglove::CompressedImage image_msg;
    foxglove::CameraCalibration calibration_msg;
    msgs::Imu imu_msg;
    std::vector<std::uint8_t> jpeg;

    Impl(const Calibration& c, VizConfig cfg)
        : calibration(c),
          config(std::move(cfg)),
          spin(scan::SpinGeometry::fromCalibration(c)),
          map(config.map_voxel_m, config.map_max_points) {}

    Result<std::uint16_t> channel(const std::string& topic,
                                  const google::protobuf::Descriptor* type) {
        auto it = schemas.find(type->full_name());
        if (it == schemas.end()) {
            auto id = mcap->addSchema(type->full_name(), "protobuf", fileDescriptorSet(type));
            if (!id.isOk()) return id.status();
            it = schemas.emplace(type->full_name(), *id).first;
        }
        return mcap->addChannel(topic, "protobuf", it->second);
    }

    Status addChannels() {
        struct Wanted {
            std::uint16_t* id;
            std::string topic;
            const google::protobuf::Descriptor* type;
        };
        std::vector<Wanted> wanted = {
            {&pose_ch, "/pose", foxglove::PoseInFrame::descriptor()},
            {&path_ch, "/path", foxglove::PosesInFrame::descriptor()},
            {&tf_ch, "/tf", foxglove::FrameTransforms::descriptor()},
            {&sweep_ch, "/sweep", foxglove::PointCloud::descriptor()},
            {&map_ch, "/map", foxglove::PointCloud::descriptor()},
            {&imu_ch, "/imu", msgs::Imu::descriptor()},
            {&status_ch, "/status", msgs::PipelineStatus::descriptor()},
        };
        for (int c = 0; c < 2; ++c) {
            wanted.push_back(
                {&image_ch[c], kImageTopics[c], foxglove::CompressedImage::descriptor()});
            wanted.push_back({&calibration_ch[c], kCalibrationTopics[c],
                              foxglove::CameraCalibration::descriptor()});
        }
        for (const Wanted& w : wanted) {
            auto id = channel(w.topic, w.type);
            if (!id.isOk()) return id.status();
            *w.id = *id;
        }
        return Status::ok();
    }

    Status write(std::uint16_t channel_id, TimeNs t, const google::protobuf::Message& m) {
        buffer.clear();
        if (!m.SerializeToString(&buffer))
            return {StatusCode::kUnsupported, "viz: cannot serialise " + m.GetTypeName()};
        return mcap->write(channel_id, std::max<TimeNs>(t, 0),
                           {reinterpret_cast<const std::uint8_t*>(buffer.data()), buffer.size()});
    }

    // The shaft angle at t, interpolated between the encoder samples around it (a little
    // extrapolated at the newest one); nullopt when none is close enough.
    std::optional<double> shaftAngleAt(TimeNs t) {
        while (encoder.size() > 2 && encoder[1].t_host <= t) encoder.pop_front();
        if (encoder.empty()) return std::nullopt;
        const EncoderSample& a = encoder.front();
        if (t <= a.t_host) {
            if (a.t_host - t > kMaxEncoderGap) return std::nullopt;
            return a.angle_rad - a.speed_radps * toSeconds(a.t_host - t);
        }
        if (encoder.size() >= 2 && encoder[1].t_host >= t) {
            const EncoderSample& b = encoder[1];
            if (b.t_host - a.t_host > kMaxEncoderGap) return std::nullopt;
            const double f = static_cast<double>(t - a.t_host) /
                             static_cast<double>(std::max<TimeNs>(1, b.t_host - a.t_host));
            return a.angle_rad + f * (b.angle_rad - a.angle_rad);
        }
        const EncoderSample& last = encoder.back();
        if (t - last.t_host > kMaxEncoderGap) return std::nullopt;
        return last.angle_rad + last.speed_radps * toSeconds(t - last.t_host);
    }

    // The ground truth's world in the estimate's: the two agree at the first estimated pose the
    // ground truth covers (as a trajectory evaluation aligns them at the start), so the viewer
    // shows both paths from one point and their drift apart.
    void alignGroundTruth(const PoseEstimate& p) {
        if (T_world_gtworld || ground_truth.empty()) return;
        const auto nearest = std::min_element(
            ground_truth.begin(), ground_truth.end(), [&](const auto& a, const auto& b) {
                return std::abs(a.first - p.t_host) < std::abs(b.first - p.t_host);
            });
        if (std::abs(nearest->first - p.t_host) > kGroundTruthMatch) return;
        T_world_gtworld = p.T_world_body * nearest->second.inverse();
        ground_truth.clear();
    }

    // The path keeps a pose once the body moved 10 cm or turned 10 deg from the last one kept:
    // the trajectory's shape at a size independent of the pose rate and of standing still.
    void extendPath(const Eigen::Isometry3d& T) {
        if (!path.empty()) {
            const Eigen::Isometry3d d = path.back().inverse() * T;
            if (d.translation().norm() < 0.1 && Eigen::AngleAxisd(d.linear()).angle() < 0.1745)
                return;
        }
        path.push_back(T);
    }

    // /sweep (the points as they are) and /map (the display map with them added), in world.
    Status writeClouds(TimeNs t, std::span<const journal::MapPoint> points) {
        if (points.empty()) return Status::ok();
        cloud.Clear();
        setTime(cloud.mutable_timestamp(), t);
        cloud.set_frame_id(kWorld);
        // The identity, written out: the cloud's points are in world coordinates.
        cloud.mutable_pose()->mutable_position()->set_x(0.0);
        cloud.mutable_pose()->mutable_orientation()->set_w(1.0);
        cloud.set_point_stride(kPointStride);
        for (const PointField& f : kPointFields) {
            foxglove::PackedElementField* field = cloud.add_fields();
            field->set_name(f.name);
            field->set_offset(f.offset);
            field->set_type(static_cast<foxglove::PackedElementField::NumericType>(f.type));
        }
        std::string* data = cloud.mutable_data();
        data->reserve(points.size() * kPointStride);
        for (const journal::MapPoint& p : points) appendPointRecord(p, *data);
        if (Status st = write(sweep_ch, t, cloud); !st.isOk()) return st;

        // The same header; the display map's records as the data.
        map.add(points);
        map_pending = true;  // the last cloud's header: close() writes the final map with it
        if (last_map_t != 0 && toSeconds(t - last_map_t) < config.map_every_s) return Status::ok();
        last_map_t = t;
        map_pending = false;
        map.snapshot(*cloud.mutable_data());
        if (Status st = write(map_ch, t, cloud); !st.isOk()) return st;
        return Status::ok();
    }

    // /path and the camchain's frames again, so a viewer that seeks finds them near.
    Status writePathAndStatic(TimeNs t) {
        if (Status st = writePath(t); !st.isOk()) return st;
        tf.Clear();
        addStaticTransforms(t);
        return write(tf_ch, t, tf);
    }

    Status writePath(TimeNs t) {
        foxglove::PosesInFrame msg;
        setTime(msg.mutable_timestamp(), t);
        msg.set_frame_id(kWorld);
        const std::size_t n = path.size(), kept = std::min(n, config.path_max_poses);
        for (std::size_t j = 0; j < kept; ++j) {
            // Evenly thinned beyond the budget; the newest pose always last.
            const std::size_t i = kept < n ? (j + 1 == kept ? n - 1 : j * n / kept) : j;
            foxglove::Pose* pose = msg.add_poses();
            setIsometry(pose->mutable_position(), pose->mutable_orientation(), path[i]);
        }
        return write(path_ch, t, msg);
    }

    // body -> imu and body -> cameras from the camchain (body is the tracking camera {C}), and the
    // ground truth's world once aligned.
    void addStaticTransforms(TimeNs t) {
        if (T_world_gtworld) addTransform(tf, t, kWorld, kGroundTruthWorld, *T_world_gtworld);
        addTransform(tf, t, kBody, kImuFrame, calibration.T_camera_imu());
        addTransform(tf, t, kBody, kCameraFrames[0], Eigen::Isometry3d::Identity());
        // Kalibr's T_cn_cnm1 maps tracking-camera coordinates into the colour camera's.
        addTransform(tf, t, kBody, kCameraFrames[1], calibration.T_colour_tracking.inverse());
    }

    // Thins the tracking camera to config.track_camera_max_hz (on the frames' own times, so a
    // replay gives the same frames whatever the pace).
    bool imageDue(Camera camera, TimeNs t) {
        if (camera != Camera::kTrack || config.track_camera_max_hz <= 0) return true;
        const auto period = static_cast<TimeNs>(1e9 / config.track_camera_max_hz);
        // Half a frame's slack, so 50 Hz frames at 10 Hz are every fifth, not every sixth.
        if (last_track_t != 0 && t - last_track_t < period - 10 * kNsPerMs) return false;
        last_track_t = t;
        return true;
    }

    Status encodeImage(Camera camera, const Image& image, int& width, int& height) {
        Image converted;
        Result<cv::Mat> mat = toMat(image, converted);
        if (!mat.isOk()) return mat.status();
        cv::Mat shown = *mat;
        while (shown.cols > config.max_image_width) {
            cv::Mat half;
            cv::resize(shown, half, cv::Size(shown.cols / 2, shown.rows / 2), 0, 0, cv::INTER_AREA);
            shown = half;
        }
        if (!cv::imencode(".jpg", shown, jpeg, {cv::IMWRITE_JPEG_QUALITY, config.jpeg_quality}))
            return {StatusCode::kUnsupported, std::string("viz: JPEG encoding of a ") +
                                                  kImageTopics[static_cast<int>(camera)] +
                                                  " frame failed"};
        width = shown.cols;
        height = shown.rows;
        return Status::ok();
    }
};

VizWriter::VizWriter(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
VizWriter::~VizWriter() = default;

Result<std::unique_ptr<VizWriter>> VizWriter::create(const std::string& path,
                                                     const Calibration& calibration,
                                                     VizConfig config) {
    recording::McapWriterOptions options;
    options.library = config.library;
    options.compression = config.compression;
    auto impl = std::make_unique<Impl>(calibration, std::move(config));
    auto mcap = recording::McapWriter::create(path, options);
    if (!mcap.isOk())
        return Status(mcap.status().code(), "--viz " + path + ": " + mcap.status().message());
    impl->mcap = std::move(*mcap);
    if (Status s = impl->addChannels(); !s.isOk()) return s;
    return std::unique_ptr<VizWriter>(new VizWriter(std::move(impl)));
}

Status VizWriter::pose(const PoseEstimate& p) {
    Impl& m = *impl_;
    m.last_pose_t = p.t_host;
    m.pose_msg.Clear();
    setTime(m.pose_msg.mutable_timestamp(), p.t_host);
    m.pose_msg.set_frame_id(kWorld);
    auto* pose = m.pose_msg.mutable_pose();
    setIsometry(pose->mutable_position(), pose->mutable_orientation(), p.T_world_body);
    if (Status s = m.write(m.pose_ch, p.t_host, m.pose_msg); !s.isOk()) return s;
    if (!p.tracking_lost) m.extendPath(p.T_world_body);  // guesses are no part of the path

    m.tf.Clear();
    addTransform(m.tf, p.t_host, kWorld, kBody, p.T_world_body);
    if (const std::optional<double> angle = m.shaftAngleAt(p.t_host))
        addTransform(m.tf, p.t_host, kBody, kLaser, m.spin.bodyFromLaser(*angle));
    const bool aligned = m.T_world_gtworld.has_value();
    m.alignGroundTruth(p);
    if (!m.static_tf_written || aligned != m.T_world_gtworld.has_value()) {
        m.addStaticTransforms(p.t_host);
        m.static_tf_written = true;
    }
    return m.write(m.tf_ch, p.t_host, m.tf);
}

Status VizWriter::encoder(const EncoderSample& sample) {
    Impl& m = *impl_;
    if (!m.encoder.empty() && sample.t_host <= m.encoder.back().t_host) return Status::ok();
    m.encoder.push_back(sample);
    return Status::ok();
}

Status VizWriter::imu(const ImuSample& s) {
    Impl& m = *impl_;
    m.imu_msg.Clear();
    setTime(m.imu_msg.mutable_timestamp(), s.t_host);
    m.imu_msg.set_frame_id(kImuFrame);
    auto* w = m.imu_msg.mutable_angular_velocity_radps();
    w->set_x(s.gyro_radps_imu.x());
    w->set_y(s.gyro_radps_imu.y());
    w->set_z(s.gyro_radps_imu.z());
    auto* a = m.imu_msg.mutable_linear_acceleration_mps2();
    a->set_x(s.accel_mps2_imu.x());
    a->set_y(s.accel_mps2_imu.y());
    a->set_z(s.accel_mps2_imu.z());
    m.imu_msg.set_status_word(s.status_word);
    return m.write(m.imu_ch, s.t_host, m.imu_msg);
}

Status VizWriter::image(Camera camera, const Image& image) {
    Impl& m = *impl_;
    if (image.format == PixelFormat::kMjpeg && hasHuffmanTables(image.data)) {
        // Already a JPEG a browser decodes: kept as the camera sent it.
        return compressedImage(camera, image.t_host, image.data, "jpeg", image.width, image.height);
    }
    int width = 0, height = 0;
    if (Status s = m.encodeImage(camera, image, width, height); !s.isOk()) {
        // A frame that does not decode is the camera's problem, not the file's: skip it.
        if (m.image_errors++ == 0)
            log().warn("viz: {}: {} (frame skipped)", kImageTopics[static_cast<int>(camera)],
                       s.message());
        return Status::ok();
    }
    return compressedImage(camera, image.t_host, m.jpeg, "jpeg", width, height);
}

Status VizWriter::compressedImage(Camera camera, TimeNs t, std::span<const std::uint8_t> data,
                                  const char* format, int width, int height) {
    Impl& m = *impl_;
    const int c = static_cast<int>(camera);
    if (!m.imageDue(camera, t)) return Status::ok();
    m.image_msg.Clear();
    setTime(m.image_msg.mutable_timestamp(), t);
    m.image_msg.set_frame_id(kCameraFrames[c]);
    m.image_msg.set_data(data.data(), data.size());
    m.image_msg.set_format(format);
    if (Status s = m.write(m.image_ch[c], t, m.image_msg); !s.isOk()) return s;

    // With every frame, so a viewer that seeks finds the calibration next to the image.
    const CameraIntrinsics& in =
        camera == Camera::kTrack ? m.calibration.tracking : m.calibration.colour;
    const double scale = in.resolution[0] > 0 ? static_cast<double>(width) / in.resolution[0] : 1.0;
    m.calibration_msg.Clear();
    setTime(m.calibration_msg.mutable_timestamp(), t);
    m.calibration_msg.set_frame_id(kCameraFrames[c]);
    m.calibration_msg.set_width(static_cast<std::uint32_t>(width));
    m.calibration_msg.set_height(static_cast<std::uint32_t>(height));
    fillCalibration(m.calibration_msg, in, scale);
    return m.write(m.calibration_ch[c], t, m.calibration_msg);
}

Status VizWriter::groundTruth(const recording::GroundTruthPose& gt) {
    Impl& m = *impl_;
    if (m.gt_ch == 0) {
        auto id = m.channel("/groundtruth/pose", foxglove::PoseInFrame::descriptor());
        if (!id.isOk()) return id.status();
        m.gt_ch = *id;
    }
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = gt.q_world_body.normalized().toRotationMatrix();
    T.translation() = gt.p_world_body;
    if (!m.T_world_gtworld) {
        m.ground_truth.emplace_back(gt.t, T);
        // Poses lag the ground truth by the worker's hold-back and a sweep: a few seconds kept.
        while (m.ground_truth.size() > 2000) m.ground_truth.pop_front();
    }
    foxglove::PoseInFrame msg;
    setTime(msg.mutable_timestamp(), gt.t);
    msg.set_frame_id(kGroundTruthWorld);
    setIsometry(msg.mutable_pose()->mutable_position(), msg.mutable_pose()->mutable_orientation(),
                T);
    return m.write(m.gt_ch, gt.t, msg);
}

Status VizWriter::sweep(const lio::RegisteredSweep& s, std::span<const journal::MapPoint> points,
                        const journal::DeviceCounts& devices) {
    Impl& m = *impl_;
    const TimeNs t = s.times.empty() ? s.result.pose.t_host : s.times.back();  // sweep complete
    if (Status st = m.writeClouds(t, points); !st.isOk()) return st;

    msgs::PipelineStatus status;
    setTime(status.mutable_timestamp(), t);
    status.set_sweep_index(s.sweep.index);
    const std::uint8_t mask = s.result.pose.solved_dof_mask;
    status.set_solved_rx((mask & scan::kRx) ? 1 : 0);
    status.set_solved_ry((mask & scan::kRy) ? 1 : 0);
    status.set_solved_rz((mask & scan::kRz) ? 1 : 0);
    status.set_solved_tx((mask & scan::kTx) ? 1 : 0);
    status.set_solved_ty((mask & scan::kTy) ? 1 : 0);
    status.set_solved_tz((mask & scan::kTz) ? 1 : 0);
    status.set_solved_count(static_cast<std::uint32_t>(std::popcount(mask & 0x3Fu)));
    const auto& eig = s.result.match.degeneracy.eigenvalues;
    for (int i = 0; i < eig.size(); ++i) status.add_degeneracy_eigenvalues(eig[i]);
    status.set_min_eigenvalue(eig.minCoeff());
    status.set_associations(s.result.match.associations);
    status.set_match_rms_m(s.result.match.rms_m);
    status.set_match_ms(s.result.total_ms);
    status.set_sweep_points(static_cast<std::uint32_t>(points.size()));
    status.set_tracking_lost(s.tracking.lost);
    status.set_enters_map(s.tracking.enters_map);
    // The device rates the worker counted since the previous sweep's record: the sweep's own,
    // whenever the sweep reaches the file (a scan's first sweeps wait for its calibration check).
    const double dt = devices.window_s;
    const auto rate = [dt](std::uint32_t n) { return dt > 0 ? static_cast<double>(n) / dt : 0.0; };
    status.set_imu_hz(rate(devices.imu_samples));
    status.set_laser_scans_hz(rate(devices.laser_scans));
    status.set_encoder_hz(rate(devices.encoder_samples));
    status.set_track_camera_hz(rate(devices.tracking_frames));
    status.set_colour_camera_hz(rate(devices.colour_frames));
    status.set_map_points(m.map.size());
    if (Status st = m.write(m.status_ch, t, status); !st.isOk()) return st;
    return m.writePathAndStatic(std::max(t, m.last_pose_t));
}

Status VizWriter::mapPoints(TimeNs t, std::span<const journal::MapPoint> points) {
    Impl& m = *impl_;
    if (Status st = m.writeClouds(t, points); !st.isOk()) return st;
    return m.writePathAndStatic(std::max(t, m.last_pose_t));
}

Status VizWriter::close() {
    Impl& m = *impl_;
    if (m.map_pending) {  // the whole map at the end, whatever map_every_s
        m.map.snapshot(*m.cloud.mutable_data());
        const TimeNs t = m.cloud.timestamp().seconds() * kNsPerSec + m.cloud.timestamp().nanos();
        if (Status s = m.write(m.map_ch, t, m.cloud); !s.isOk()) return s;
        m.map_pending = false;
    }
    return m.mcap->close();
}

std::uint64_t VizWriter::bytesWritten() const { return impl_->mcap->bytesWritten(); }
std::uint64_t VizWriter::messageCount() const { return impl_->mcap->messageCount(); }

}  // namespace handscan::viz
