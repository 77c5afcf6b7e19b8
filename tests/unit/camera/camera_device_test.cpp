// The V4L2 ioctl sequence and buffer handling against the fake device layer.
#include "handscan/camera/camera_device.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <mutex>

#include "handscan/camera/frame_record.hpp"
#include "handscan/camera/replay_v4l2_device.hpp"

namespace handscan::camera {
namespace {

using namespace transport;

V4l2PixFormat fmt(std::uint32_t fourcc, std::uint32_t w, std::uint32_t h, std::uint32_t bpl) {
    return {w, h, fourcc, kV4l2FieldNone, bpl, bpl ? bpl * h : w * h};
}

ReplayDeviceConfig greyCamera() {
    ReplayDeviceConfig c;
    c.formats = {fmt(kFourccGrey, 8, 4, 16)};  // padded lines: stride 16 for 8 pixels
    c.frame_intervals = {{1, 30}, {1, 60}};
    c.max_buffers = 3;
    return c;
}

std::vector<std::uint8_t> greyFrame(std::uint8_t seed) {
    std::vector<std::uint8_t> p(16 * 4);
    for (std::size_t i = 0; i < p.size(); ++i) p[i] = static_cast<std::uint8_t>(seed + i);
    return p;
}

FrameRecordHeader header(std::uint32_t seq, TimeNs t,
                         std::uint32_t flags = kV4l2BufFlagTimestampMonotonic |
                                               kV4l2BufFlagTstampSrcSoe) {
    FrameRecordHeader h;
    h.sequence = seq;
    h.flags = flags;
    h.timestamp_ns = t;
    h.fourcc = kFourccGrey;
    h.width = 8;
    h.height = 4;
    h.stride = 16;
    h.exposure_us = 2000;
    return h;
}

TEST(CameraDevice, RunsTheV4l2StreamingSequence) {
    ReplayV4l2Device dev(greyCamera());
    dev.addFrame(header(0, kNsPerSec), greyFrame(0));
    CameraConfig cfg;
    cfg.width = 8;
    cfg.height = 4;
    cfg.frame_interval = {1, 60};
    cfg.buffer_count = 4;  // the driver grants 3
    cfg.exposure = 5 * kNsPerMs;
    CameraDevice cam(dev, cfg, nullptr, [] { return 2 * kNsPerSec; });
    Status s = cam.start();
    ASSERT_TRUE(s) << s.message();
    EXPECT_EQ(cam.bufferCount(), 3u);
    EXPECT_EQ(cam.frameInterval().denominator, 60u);
    EXPECT_EQ(cam.format().bytesperline, 16u);
    auto img = cam.grab(100 * kNsPerMs);
    ASSERT_TRUE(img) << img.status().message();
    ASSERT_TRUE(img->has_value());
    ASSERT_TRUE(cam.stop());
    const std::vector<std::string> expected = {
        "open",
        "QUERYCAP",
        "S_FMT 8x4 GREY",
        "S_PARM 1/60",
        "S_CTRL 0x009A0901 1",
        "S_CTRL 0x009A0902 50",  // manual exposure, 50 x 100 us
        "REQBUFS 4",
        "QUERYBUF 0",
        "mmap 0 64",
        "QUERYBUF 1",
        "mmap 4096 64",
        "QUERYBUF 2",
        "mmap 8192 64",
        "QBUF 0",
        "QBUF 1",
        "QBUF 2",
        "STREAMON",
        "poll",
        "DQBUF",
        "QBUF 0",
        "STREAMOFF",
        "munmap",
        "munmap",
        "munmap",
        "REQBUFS 0",
        "close"};
    EXPECT_EQ(dev.calls(), expected);
    EXPECT_TRUE(dev.violations().empty()) << dev.violations().front();
}

TEST(CameraDevice, FallsBackThroughTheFormatPreferences) {
    ReplayDeviceConfig c;
    c.formats = {fmt(kFourccMjpeg, 8, 4, 0), fmt(kFourccYuyv, 8, 4, 16)};
    ReplayV4l2Device dev(c);
    CameraConfig cfg;
    cfg.width = 8;
    cfg.height = 4;
    CameraDevice cam(dev, cfg);
    ASSERT_TRUE(cam.start());
    EXPECT_EQ(cam.format().pixelformat, kFourccYuyv);
    EXPECT_EQ(dev.calls()[2], "S_FMT 8x4 GREY");
    EXPECT_EQ(dev.calls()[3], "S_FMT 8x4 YUYV");

    ReplayDeviceConfig only_rgb;
    only_rgb.formats = {fmt(fourcc('R', 'G', 'B', '3'), 8, 4, 24)};
    ReplayV4l2Device dev2(only_rgb);
    CameraDevice cam2(dev2, cfg);
    Status s = cam2.start();
    ASSERT_FALSE(s);
    EXPECT_EQ(s.code(), StatusCode::kUnsupported);
    EXPECT_NE(s.message().find("offers none of GREY, YUYV, MJPG at 8x4 (driver answered RGB3)"),
              std::string::npos)
        << s.message();
    EXPECT_EQ(dev2.calls().back(), "close");
    EXPECT_TRUE(dev2.violations().empty());
}

TEST(CameraDevice, RefusesANodeWithoutStreaming) {
    ReplayDeviceConfig c = greyCamera();
    c.capabilities = kV4l2CapVideoCapture;  // read() only
    ReplayV4l2Device dev(c);
    CameraDevice cam(dev, {});
    Status s = cam.start();
    ASSERT_FALSE(s);
    EXPECT_NE(s.message().find("not a video capture device with streaming I/O"), std::string::npos);
}

TEST(CameraDevice, CountsDroppedFramesAndSkipsErrorBuffers) {
    ReplayV4l2Device dev(greyCamera());
    dev.addFrame(header(5, 1 * kNsPerSec), greyFrame(1));
    dev.addFrame(header(6, 2 * kNsPerSec), greyFrame(2));
    dev.addFrame(header(9, 3 * kNsPerSec), greyFrame(3));  // 7, 8 dropped
    dev.addFrame(header(10, 4 * kNsPerSec, kV4l2BufFlagTimestampMonotonic | kV4l2BufFlagError),
                 greyFrame(4));
    dev.addFrame(header(11, 5 * kNsPerSec), std::vector<std::uint8_t>(20));  // short payload
    dev.addFrame(header(12, 6 * kNsPerSec), greyFrame(6));
    CameraConfig cfg;
    cfg.width = 8;
    cfg.height = 4;
    CameraDevice cam(dev, cfg);
    ASSERT_TRUE(cam.start());
    std::vector<std::uint32_t> seqs;
    for (int i = 0; i < 10; ++i) {
        auto r = cam.grab(kNsPerMs);
        ASSERT_TRUE(r) << r.status().message();
        if (*r) seqs.push_back((*r)->sequence);
    }
    EXPECT_EQ(seqs, (std::vector<std::uint32_t>{5, 6, 9, 12}));
    EXPECT_EQ(cam.stats().frames, 4u);
    EXPECT_EQ(cam.stats().dropped, 2u);
    EXPECT_EQ(cam.stats().error_buffers, 2u);
    EXPECT_TRUE(dev.violations().empty()) << dev.violations().front();
}

TEST(CameraDevice, ShiftsTimestampsToMidExposure) {
    ReplayV4l2Device dev(greyCamera());
    dev.addFrame(header(0, 10 * kNsPerSec), greyFrame(0));  // SOE, auto exposure reports 2000 us
    dev.addFrame(
        header(1, 11 * kNsPerSec, kV4l2BufFlagTimestampMonotonic | kV4l2BufFlagTstampSrcEof),
        greyFrame(1));
    dev.addFrame(header(2, 12 * kNsPerSec, kV4l2BufFlagTimestampCopy), greyFrame(2));
    CameraConfig cfg;
    cfg.width = 8;
    cfg.height = 4;
    cfg.readout = 10 * kNsPerMs;
    CameraDevice cam(dev, cfg, nullptr, [] { return 20 * kNsPerSec; });
    ASSERT_TRUE(cam.start());
    std::vector<Image> imgs;
    for (int i = 0; i < 3; ++i) {
        auto r = cam.grab(kNsPerMs);
        ASSERT_TRUE(r && *r);
        imgs.push_back(**r);
    }
    EXPECT_EQ(imgs[0].exposure_ns, 2 * kNsPerMs);
    EXPECT_EQ(imgs[0].t_host, 10 * kNsPerSec + kNsPerMs);
    EXPECT_EQ(imgs[1].t_host, 11 * kNsPerSec - 10 * kNsPerMs - kNsPerMs);
    EXPECT_EQ(imgs[2].t_host, 20 * kNsPerSec - 10 * kNsPerMs - kNsPerMs);
    EXPECT_EQ(cam.stats().host_timestamps, 1u);
    // The buffer bytes come out as delivered, padding included.
    EXPECT_EQ(imgs[1].data, greyFrame(1));
    EXPECT_EQ(imgs[1].stride_bytes, 16);
}

TEST(CameraDevice, ReportsAnUnpluggedCamera) {
    ReplayDeviceConfig c = greyCamera();
    c.disconnect_at_end = true;
    ReplayV4l2Device dev(c);
    dev.addFrame(header(0, kNsPerSec), greyFrame(0));
    CameraConfig cfg;
    cfg.width = 8;
    cfg.height = 4;
    CameraDevice cam(dev, cfg);
    ASSERT_TRUE(cam.start());
    ASSERT_TRUE(cam.grab(kNsPerMs));
    auto r = cam.grab(kNsPerMs);
    ASSERT_FALSE(r);
    EXPECT_EQ(r.status().code(), StatusCode::kDisconnected);
    EXPECT_NE(r.status().message().find("/dev/video-replay"), std::string::npos);
}

TEST(CameraDevice, TapsEachBufferAsAFrameRecordThatReplaysIdentically) {
    struct Tap : RawTap {
        void onRaw(TimeNs, std::span<const std::uint8_t> b) override {
            bytes.insert(bytes.end(), b.begin(), b.end());
        }
        std::vector<std::uint8_t> bytes;
    } tap;
    ReplayV4l2Device live(greyCamera());
    for (std::uint32_t i = 0; i < 5; ++i)
        live.addFrame(header(i * 2, (i + 1) * kNsPerSec), greyFrame(static_cast<std::uint8_t>(i)));
    CameraConfig cfg;
    cfg.width = 8;
    cfg.height = 4;
    std::vector<Image> first, second;
    {
        CameraDevice cam(live, cfg, &tap);
        ASSERT_TRUE(cam.start());
        for (int i = 0; i < 5; ++i) {
            auto r = cam.grab(kNsPerMs);
            ASSERT_TRUE(r && *r);
            first.push_back(**r);
        }
    }
    // Coded as the simulator codes uncompressed frames: version-2 PNG records.
    for (std::span<const std::uint8_t> rest(tap.bytes); !rest.empty();) {
        auto rec = decodeFrameRecord(rest);
        ASSERT_TRUE(rec) << rec.status().message();
        EXPECT_EQ(rest[4], kFrameRecordCodedVersion);
        EXPECT_EQ(rec->coding, FrameCoding::kPng);
        rest = rest.subspan(rec->record_size);
    }
    ReplayV4l2Device replay(greyCamera());
    auto added = replay.addRecords(tap.bytes);
    ASSERT_TRUE(added) << added.status().message();
    EXPECT_EQ(*added, 5u);
    CameraDevice cam(replay, cfg);
    ASSERT_TRUE(cam.start());
    for (int i = 0; i < 5; ++i) {
        auto r = cam.grab(kNsPerMs);
        ASSERT_TRUE(r && *r);
        second.push_back(**r);
    }
    for (int i = 0; i < 5; ++i) {
        EXPECT_EQ(second[i].t_host, first[i].t_host);
        EXPECT_EQ(second[i].sequence, first[i].sequence);
        EXPECT_EQ(second[i].data, first[i].data);
        EXPECT_EQ(second[i].exposure_ns, first[i].exposure_ns);
    }
    EXPECT_EQ(cam.stats().dropped, 4u);
}

TEST(CameraDevice, ASlowRecordingTapDoesNotHoldUpCapture) {
    // The recorder's side is stuck (a slow disk, the coding): capture goes on at full pace, and
    // every frame reaches the tap, in order, once it moves again.
    struct StuckTap : RawTap {
        void onRaw(TimeNs t, std::span<const std::uint8_t> b) override {
            std::unique_lock lock(m);
            moving.wait(lock, [this] { return released; });
            times.push_back(t);
            records.emplace_back(b.begin(), b.end());
        }
        void release() {
            {
                std::lock_guard lock(m);
                released = true;
            }
            moving.notify_all();
        }
        std::mutex m;
        std::condition_variable moving;
        bool released = false;
        std::vector<TimeNs> times;
        std::vector<std::vector<std::uint8_t>> records;
    } tap;
    ReplayV4l2Device live(greyCamera());
    for (std::uint32_t i = 0; i < 8; ++i)
        live.addFrame(header(i, (i + 1) * kNsPerSec), greyFrame(static_cast<std::uint8_t>(i)));
    CameraConfig cfg;
    cfg.width = 8;
    cfg.height = 4;
    TimeNs now = 100 * kNsPerSec;
    std::vector<Image> grabbed;
    {
        CameraDevice cam(live, cfg, &tap, [&now] { return now += kNsPerMs; });
        ASSERT_TRUE(cam.start());
        for (int i = 0; i < 8; ++i) {
            auto r = cam.grab(kNsPerMs);  // would wait forever if the tap ran on this thread
            ASSERT_TRUE(r && *r) << (r ? "no frame" : r.status().message());
            grabbed.push_back(**r);
        }
        EXPECT_EQ(cam.stats().frames, 8u);
        EXPECT_EQ(cam.stats().unrecorded, 0u);
        tap.release();
    }  // the camera's tap hands on what is queued before it goes
    ASSERT_EQ(tap.records.size(), 8u);
    for (std::size_t i = 0; i < 8; ++i) {
        auto rec = decodeFrameRecord(tap.records[i]);
        ASSERT_TRUE(rec) << rec.status().message();
        EXPECT_EQ(rec->header.sequence, i);
        EXPECT_EQ(rec->header.t_host_ns, grabbed[i].t_host);
        EXPECT_TRUE(std::equal(rec->payload.begin(), rec->payload.end(), grabbed[i].data.begin(),
                               grabbed[i].data.end()));
        if (i > 0) {
            EXPECT_GT(tap.times[i], tap.times[i - 1]);
        }
    }
}

TEST(FrameRecordTap, DropsAndCountsBeyondItsBoundRatherThanWait) {
    struct CountingTap : RawTap {
        void onRaw(TimeNs, std::span<const std::uint8_t>) override { ++n; }
        std::atomic<int> n{0};
    } counting;
    struct BlockedTap : RawTap {
        void onRaw(TimeNs, std::span<const std::uint8_t>) override {
            std::unique_lock lock(m);
            cv.wait(lock, [this] { return go; });
        }
        std::mutex m;
        std::condition_variable cv;
        bool go = false;
    } blocked;
    FrameRecordHeader h = header(0, kNsPerSec);
    {
        FrameRecordTap t(blocked, 3 * 64);  // three 64-byte frames
        for (int i = 0; i < 10; ++i) t.submit(i, h, greyFrame(static_cast<std::uint8_t>(i)));
        // One may be with the worker already; the rest wait up to the bound.
        EXPECT_GE(t.dropped(), 6u);
        EXPECT_LE(t.dropped(), 7u);
        {
            std::lock_guard lock(blocked.m);
            blocked.go = true;
        }
        blocked.cv.notify_all();
        t.flush();
        EXPECT_EQ(t.recorded() + t.dropped(), 10u);
    }
    FrameRecordTap t(counting);
    for (int i = 0; i < 5; ++i) t.submit(i, h, greyFrame(1));
    t.flush();
    EXPECT_EQ(counting.n.load(), 5);
    EXPECT_EQ(t.dropped(), 0u);
}

}  // namespace
}  // namespace handscan::camera
