// The colour camera's path through the daemon: CameraDevice over a V4L2 device layer without a
// kernel (no video nodes here: camera::ReplayV4l2Device, the camera replay transport, released
// at wall-clock pace with CLOCK_MONOTONIC buffer stamps as a UVC camera gives them), MJPEG frames
// of a red scene, into the colouriser on the pipeline thread: the journal's points that the
// camera saw carry its colour, the others keep the laser's grey.
#include <gtest/gtest.h>
#include <turbojpeg.h>

#include <chrono>
#include <cstdio>
#include <thread>

#include "daemon_rig.hpp"
#include "handscan/camera/replay_v4l2_device.hpp"
#include "handscan/journal/journal_reader.hpp"
#include "handscan/pipeline_daemon/pipeline_daemon.hpp"
#include "handscan/shm/text_field.hpp"

namespace handscan::pipeline_daemon::test {
namespace {

constexpr int kWidth = 1600, kHeight = 1200;  // cam1 of config/camchain.yaml

std::vector<std::uint8_t> redJpeg() {
    std::vector<std::uint8_t> rgb(static_cast<std::size_t>(kWidth) * kHeight * 3);
    for (std::size_t i = 0; i < rgb.size(); i += 3) {
        rgb[i] = 220;
        rgb[i + 1] = 30;
        rgb[i + 2] = 30;
    }
    tjhandle h = tjInitCompress();
    unsigned char* jpeg = nullptr;
    unsigned long size = 0;
    const int rc = tjCompress2(h, rgb.data(), kWidth, kWidth * 3, kHeight, TJPF_RGB, &jpeg, &size,
                               TJSAMP_422, 90, 0);
    std::vector<std::uint8_t> out;
    if (rc == 0) out.assign(jpeg, jpeg + size);
    tjFree(jpeg);
    tjDestroy(h);
    return out;
}

// Frames released when their (monotonic) timestamp comes, 4 per second from its creation on.
class PacedCamera final : public transport::V4l2Device {
public:
    explicit PacedCamera(const std::vector<std::uint8_t>& jpeg) : inner_(config()) {
        const TimeNs t0 = monotonicNow() + 300 * kNsPerMs;
        for (std::uint32_t k = 0; k < 60; ++k) {
            camera::FrameRecordHeader h;
            h.sequence = k;
            h.flags =
                transport::kV4l2BufFlagTimestampMonotonic | transport::kV4l2BufFlagTstampSrcSoe;
            h.timestamp_ns = t0 + k * 250 * kNsPerMs;
            h.bytesused = static_cast<std::uint32_t>(jpeg.size());
            h.fourcc = transport::kFourccMjpeg;
            h.width = kWidth;
            h.height = kHeight;
            due_.push_back(h.timestamp_ns + 5 * kNsPerMs);  // delivered at the end of the exposure
            inner_.addFrame(h, jpeg);
        }
    }
    Status open() override { return inner_.open(); }
    void close() override { inner_.close(); }
    Result<transport::V4l2Capability> queryCapability() override {
        return inner_.queryCapability();
    }
    Result<transport::V4l2PixFormat> setFormat(const transport::V4l2PixFormat& f) override {
        return inner_.setFormat(f);
    }
    Result<transport::V4l2Fraction> setFrameInterval(transport::V4l2Fraction t) override {
        return inner_.setFrameInterval(t);
    }
    Result<std::uint32_t> requestBuffers(std::uint32_t n) override {
        return inner_.requestBuffers(n);
    }
    Result<transport::V4l2Buffer> queryBuffer(std::uint32_t i) override {
        return inner_.queryBuffer(i);
    }
    Result<std::span<std::uint8_t>> map(std::uint32_t o, std::uint32_t l) override {
        return inner_.map(o, l);
    }
    void unmap(std::span<std::uint8_t> m) override { inner_.unmap(m); }
    Status queueBuffer(std::uint32_t i) override { return inner_.queueBuffer(i); }
    Result<transport::V4l2Buffer> dequeueBuffer() override {
        if (next_ >= due_.size() || monotonicNow() < due_[next_])
            return Status(StatusCode::kTimeout, "no buffer ready");
        ++next_;
        return inner_.dequeueBuffer();
    }
    Status streamOn() override { return inner_.streamOn(); }
    Status streamOff() override { return inner_.streamOff(); }
    Result<bool> waitReadable(TimeNs timeout) override {
        const TimeNs until = next_ < due_.size() ? std::min(due_[next_], monotonicNow() + timeout)
                                                 : monotonicNow() + timeout;
        std::this_thread::sleep_for(
            std::chrono::nanoseconds(std::max<TimeNs>(0, until - monotonicNow())));
        if (next_ >= due_.size() || monotonicNow() < due_[next_]) return false;
        return inner_.waitReadable(timeout);
    }
    Status setControl(std::uint32_t id, std::int32_t v) override {
        return inner_.setControl(id, v);
    }
    Result<std::int32_t> getControl(std::uint32_t id) override { return inner_.getControl(id); }
    std::string describe() const override { return inner_.describe(); }

private:
    static camera::ReplayDeviceConfig config() {
        camera::ReplayDeviceConfig c;
        c.path = "/dev/video-colour-test";
        c.formats = {{kWidth, kHeight, transport::kFourccMjpeg, transport::kV4l2FieldNone, 0,
                      kWidth * kHeight}};
        c.frame_intervals = {{1, 4}};
        return c;
    }
    camera::ReplayV4l2Device inner_;
    std::vector<TimeNs> due_;
    std::size_t next_ = 0;
};

class LinksWithColourCamera final : public DeviceLinks {
public:
    std::unique_ptr<transport::ByteStream> hokuyo(const HokuyoConfig& c) override {
        return linux_->hokuyo(c);
    }
    Result<xsens::XsensLink> xsens(const XsensConfig& c) override { return linux_->xsens(c); }
    Result<CanLink> can(const MotorConfig& c) override { return linux_->can(c); }
    std::unique_ptr<transport::V4l2Device> camera(const CameraConfig& c) override {
        if (c.device == "/dev/video-colour-test") return std::make_unique<PacedCamera>(jpeg_);
        return linux_->camera(c);
    }
    Result<std::unique_ptr<gpio::GpioChip>> gpioChip(const GpioConfig& c) override {
        return linux_->gpioChip(c);
    }

private:
    std::unique_ptr<DeviceLinks> linux_ = makeLinuxDeviceLinks();
    std::vector<std::uint8_t> jpeg_ = redJpeg();
};

TEST(PipelineDaemonColour, PointsTheColourCameraSawCarryItsColour) {
    RigDevices devices;
    devices.colour_camera = "/dev/video-colour-test";
    DaemonRig rig("colour", devices);
    DaemonOptions o;
    o.device_config = rig.deviceYaml();
    o.calibration = DaemonRig::calibrationYaml();
    o.shm_name = rig.shmName();
    o.map_capacity_points = 1 << 18;
    PipelineDaemon daemon(o, std::make_unique<LinksWithColourCamera>());
    ASSERT_TRUE(daemon.open().isOk());
    DaemonThread running(daemon);

    auto up = rig.waitStatus(
        [](const shm::StatusBlock& s) {
            return sensorConnected(s, "colour-cam") && sensorConnected(s, "hokuyo") &&
                   sensorConnected(s, "encoder") && sensorConnected(s, "xsens");
        },
        10.0);
    ASSERT_TRUE(up) << "devices did not come up";
    EXPECT_EQ(rig.command(shm::CommandType::kStartScan).state,
              static_cast<std::uint32_t>(shm::CommandState::kDone));
    auto scanned =
        rig.waitStatus([](const shm::StatusBlock& s) { return s.point_count > 60000; }, 15.0);
    EXPECT_EQ(rig.command(shm::CommandType::kStopScan).state,
              static_cast<std::uint32_t>(shm::CommandState::kDone));
    const Status result = running.stop();
    ASSERT_TRUE(scanned) << "no points";
    EXPECT_TRUE(result.isOk()) << result.message();

    ASSERT_EQ(rig.scanDirs().size(), 1u);
    auto j = journal::JournalReader::open((rig.scanDirs()[0] / "journal.hsj").string());
    ASSERT_TRUE(j.isOk()) << j.status().message();
    std::uint64_t red = 0, grey = 0, total = 0;
    ASSERT_TRUE(j->forEachPoints([&](std::span<const journal::MapPoint> pts) {
                     for (const journal::MapPoint& p : pts) {
                         ++total;
                         if (p.r > 180 && p.g < 80 && p.b < 80) ++red;
                         if (p.r == p.g && p.g == p.b) ++grey;
                     }
                 }).isOk());
    std::printf(
        "journal: %llu points, %llu red (seen by the colour camera), %llu grey (laser intensity)\n",
        static_cast<unsigned long long>(total), static_cast<unsigned long long>(red),
        static_cast<unsigned long long>(grey));
    // The camera looks one way, the laser all around: some points red, many grey, no others.
    EXPECT_GT(red, total / 50) << red << " red of " << total;
    EXPECT_GT(grey, total / 4) << grey << " grey of " << total;
    EXPECT_GE(red + grey, total * 99 / 100);
}

}  // namespace
}  // namespace handscan::pipeline_daemon::test
