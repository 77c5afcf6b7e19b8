// The colouriser on the digital twin: an office walk is simulated with the colour camera on
// (1600x1200 MJPEG at 5 Hz, UVC end-of-frame stamps turned into mid-exposure times by the camera
// codec); its frames go through the recorded V4L2 record format into the Colouriser; laser-like
// points are ray cast from the true laser pose at their own times; each point's assigned colour
// is compared with the simulator's own surface colour there (material colour x texture). Light
// and vignetting scale all three channels alike, so the comparison is of chromaticity: the angle
// between the two RGB vectors.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <random>

#include "handscan/camera/frame_record.hpp"
#include "handscan/camera/image_convert.hpp"
#include "handscan/colour/colouriser.hpp"
#include "handscan/sim/raycaster.hpp"
#include "handscan/sim/simulator.hpp"
#include "handscan/sim/textures.hpp"

namespace handscan::colour {
namespace {

// Keeps the colour camera's frames as decoded Images (the same bytes an MCAP would hold).
class ColourFrameSink : public sim::RecordingSink {
public:
    Status write(const sim::StreamMessage& m) override {
        if (m.channel != sim::SimChannel::kColourCamera) return Status::ok();
        Result<camera::FrameRecordView> rec = camera::decodeFrameRecord(m.bytes);
        if (!rec) return rec.status();
        const auto format = camera::pixelFormatFromFourcc(rec->header.fourcc);
        if (!format) return {StatusCode::kProtocolError, "colour frame with an unknown fourcc"};
        Image img;
        img.t_host = rec->header.t_host_ns;
        img.sequence = rec->header.sequence;
        img.format = *format;
        img.width = static_cast<int>(rec->header.width);
        img.height = static_cast<int>(rec->header.height);
        img.stride_bytes = static_cast<int>(rec->header.stride);
        img.exposure_ns = static_cast<TimeNs>(rec->header.exposure_us) * kNsPerUs;
        img.data.assign(rec->payload.begin(), rec->payload.end());
        Result<Image> bgr = camera::toBgr(img);  // decoded by the camera driver, as replay does
        if (!bgr) return bgr.status();
        frames.push_back(std::move(bgr).value());
        return Status::ok();
    }
    std::vector<Image> frames;
};

double chromaAngleDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    const double c = a.normalized().dot(b.normalized());
    return std::acos(std::clamp(c, -1.0, 1.0)) * 180.0 / M_PI;
}

TEST(ColourSim, OfficeWalkPointsTakeTheSurfaceColours) {
    const DeviceConfig device =
        loadDeviceConfig(std::string(HANDSCAN_SOURCE_DIR) + "/config/device.yaml");
    const Calibration cal =
        loadCalibration(std::string(HANDSCAN_SOURCE_DIR) + "/config/calibration.yaml");
    sim::SimOptions opt;
    opt.scene = "office";
    opt.duration_s = 8.0;
    sim::Simulator simulator(opt, device, cal);
    simulator.devices().tracking.fps =
        1.0;  // the tracking camera is not under test: render little of it
    ColourFrameSink sink;
    ASSERT_TRUE(simulator.run(sink).isOk());
    ASSERT_GE(sink.frames.size(), 35u);

    const auto simSeconds = [&](TimeNs t) { return toSeconds(t - opt.host_start_ns); };
    const PoseAtFn pose_at = [&](TimeNs t) {
        return simulator.trajectory().at(simSeconds(t)).T_world_body;
    };
    const sim::World& world = simulator.scene().world;
    const sim::Raycaster raycaster(world);
    const sim::TextureAtlas& atlas = sim::TextureAtlas::instance();

    // Laser-like points: random beams of the spinning Hokuyo (270 degree fan in {L}) at random
    // times, cast from the true laser pose, in 1 s sweeps.
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> beam(-0.75 * M_PI, 0.75 * M_PI), unit(0.0, 1.0);
    Colouriser colouriser(simulator.calibration());
    std::size_t next_frame = 0, total = 0, coloured = 0, agree = 0, agree_shuffled = 0,
                coloured_late = 0, agree_late = 0;
    // Control: poses taken 100 ms late, as if the frames' times (or the points') were wrong.
    const PoseAtFn late_pose_at = [&](TimeNs t) { return pose_at(t + 100 * kNsPerMs); };
    std::vector<double> angles;
    std::array<std::size_t, 6> reasons{};
    for (double sweep = 1.0; sweep + 1.0 <= opt.duration_s - 0.3; sweep += 1.0) {
        std::vector<Eigen::Vector3f> pts;
        std::vector<TimeNs> times;
        std::vector<Eigen::Vector3d> truth;
        for (int i = 0; i < 20000; ++i) {
            const double t = sweep + unit(rng);
            const Eigen::Isometry3d T_wl = simulator.laserPose(t);
            const double a = beam(rng);
            sim::Ray ray;
            ray.origin = T_wl.translation().cast<float>();
            ray.dir = (T_wl.linear() * Eigen::Vector3d(std::cos(a), std::sin(a), 0.0))
                          .cast<float>()
                          .normalized();
            const sim::RayHit hit = raycaster.cast(ray);
            if (!hit.hit() || hit.t > 30.0f) continue;
            const Eigen::Vector3f p = ray.origin + hit.t * ray.dir;
            const sim::Material& m = world.materials[world.triangle_material[hit.triangle]];
            Eigen::Vector3f n = world.triangleNormal(hit.triangle);
            float cos_inc = -n.dot(ray.dir);
            if (cos_inc < 0) {
                n = -n;
                cos_inc = -cos_inc;
            }
            // The renderer's footprint: colour pixels shaded at half resolution (render_scale 0.5).
            const float footprint =
                hit.t * (2.0f / 1350.0f) / (m.texture_scale_m * std::max(cos_inc, 0.25f));
            const Eigen::Vector2f uv = sim::TextureAtlas::planarUv(p, n, m.texture_scale_m);
            const Eigen::Vector3f tex = atlas.rgb(m.texture, uv.x(), uv.y(), footprint);
            truth.emplace_back(tex.x() * m.colour[0], tex.y() * m.colour[1], tex.z() * m.colour[2]);
            pts.push_back(p);
            times.push_back(opt.host_start_ns + fromSeconds(t));
        }
        // The frames that have arrived by the end of the sweep plus a frame period (the pipeline
        // colours a sweep once the next frame is in).
        const TimeNs arrived = opt.host_start_ns + fromSeconds(sweep + 1.0 + 0.25);
        for (; next_frame < sink.frames.size() && sink.frames[next_frame].t_host < arrived;
             ++next_frame) {
            ASSERT_TRUE(colouriser.addImage(sink.frames[next_frame]).isOk());
        }
        const ColourResult r = colouriser.colourise(pts, times, pose_at);
        const ColourResult late = colouriser.colourise(pts, times, late_pose_at);
        for (std::size_t i = 0; i < pts.size(); ++i) {
            if (!late.valid(i)) continue;
            ++coloured_late;
            agree_late += chromaAngleDeg(Eigen::Vector3d(late.rgb[i][0] + 0.5, late.rgb[i][1] + 0.5,
                                                         late.rgb[i][2] + 0.5),
                                         truth[i]) < 5.0;
        }
        total += pts.size();
        for (std::size_t i = 0; i < pts.size(); ++i) {
            ++reasons[static_cast<std::size_t>(r.status[i])];
            if (!r.valid(i)) continue;
            ++coloured;
            const Eigen::Vector3d got(r.rgb[i][0] + 0.5, r.rgb[i][1] + 0.5, r.rgb[i][2] + 0.5);
            const double ang = chromaAngleDeg(got, truth[i]);
            angles.push_back(ang);
            agree += ang < 5.0;
            // Control: the same comparison against another point's true colour.
            agree_shuffled += chromaAngleDeg(got, truth[(i * 7919 + 13) % pts.size()]) < 5.0;
        }
    }
    ASSERT_GT(coloured, 0u);
    std::sort(angles.begin(), angles.end());
    const double frac = static_cast<double>(agree) / static_cast<double>(coloured);
    const double frac_shuffled =
        static_cast<double>(agree_shuffled) / static_cast<double>(coloured);
    std::printf(
        "[ measured ] office sim: %zu frames, %zu points, %zu coloured (%.1f %%); chromaticity "
        "angle median %.2f deg, "
        "p90 %.2f deg; agree (< 5 deg) %.1f %% (control with shuffled truth: %.1f %%)\n",
        sink.frames.size(), total, coloured,
        100.0 * static_cast<double>(coloured) / static_cast<double>(total),
        angles[angles.size() / 2], angles[angles.size() * 9 / 10], 100.0 * frac,
        100.0 * frac_shuffled);
    const double frac_late = static_cast<double>(agree_late) /
                             static_cast<double>(std::max<std::size_t>(1, coloured_late));
    std::printf("[ measured ] control with poses 100 ms late: agree %.1f %%\n", 100.0 * frac_late);
    EXPECT_LT(frac_late, frac - 0.05);
    std::printf("[ measured ] not coloured: ");
    for (std::size_t k = 1; k < reasons.size(); ++k)
        std::printf("%s %zu  ", toString(static_cast<ColourStatus>(k)), reasons[k]);
    std::printf("\n");
    // The laser sees 270 x 360 degrees, the colour camera about 61 x 48: most points are behind it
    // or outside its image, not occluded and never without a frame.
    EXPECT_GT(static_cast<double>(coloured), 0.15 * static_cast<double>(total));
    EXPECT_GT(reasons[static_cast<std::size_t>(ColourStatus::kOutside)] +
                  reasons[static_cast<std::size_t>(ColourStatus::kBehind)],
              total / 2);
    EXPECT_EQ(reasons[static_cast<std::size_t>(ColourStatus::kNoImage)], 0u);
    EXPECT_LT(reasons[static_cast<std::size_t>(ColourStatus::kOccluded)], total / 20);
    EXPECT_GT(frac, 0.8);
    EXPECT_LT(frac_shuffled, frac - 0.3);
}

}  // namespace
}  // namespace handscan::colour
