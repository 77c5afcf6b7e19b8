// The `v4l2-replay-host-clock:FILE` camera of `handscan hil`: recorded frame records in a timed
// frame file, moved onto the host clock by the file's offset, delivered through the real
// CameraDevice start-up and buffer handling each at its due time, none before.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "handscan/camera/camera_device.hpp"
#include "handscan/camera/frame_record.hpp"
#include "handscan/camera/replay_v4l2_device.hpp"
#include "handscan/camera/timed_frame_file.hpp"

namespace handscan::camera {
namespace {

namespace fs = std::filesystem;
using namespace transport;

constexpr std::uint32_t kW = 16, kH = 8;

fs::path tempPath(const std::string& name) {
    return fs::temp_directory_path() /
           ("handscan-host-clock-replay-" + std::to_string(::getpid()) + "-" + name);
}

FrameRecordHeader greyHeader(std::uint32_t seq, TimeNs t, TimeNs t_host) {
    FrameRecordHeader h;
    h.sequence = seq;
    h.flags = kV4l2BufFlagTimestampMonotonic | kV4l2BufFlagTstampSrcSoe;
    h.timestamp_ns = t;
    h.fourcc = kFourccGrey;
    h.width = kW;
    h.height = kH;
    h.stride = kW;
    h.exposure_us = 2000;
    h.t_host_ns = t_host;
    return h;
}

std::vector<std::uint8_t> pixels(std::uint8_t seed) {
    std::vector<std::uint8_t> p(kW * kH);
    for (std::size_t i = 0; i < p.size(); ++i) p[i] = static_cast<std::uint8_t>(seed + i * 7);
    return p;
}

TEST(TimedFrameFile, ReadsBackEachRecordShiftedByTheFilesClockOffset) {
    const fs::path path = tempPath("roundtrip.frames");
    auto w = TimedFrameFileWriter::create(path.string());
    ASSERT_TRUE(w.isOk()) << w.status().message();
    // One PNG-coded record (as the simulator stores GREY) and one raw record on a host clock.
    const auto png = encodeFrameRecord(greyHeader(7, 1000, 1500), pixels(1), FrameCoding::kPng);
    const std::uint32_t host_clock = 0;  // no CLOCK_MONOTONIC flag: its timestamp is not moved
    FrameRecordHeader raw_header = greyHeader(8, 2000, 2500);
    raw_header.flags = host_clock;
    const auto raw = encodeFrameRecord(raw_header, pixels(2));
    ASSERT_TRUE(w->append(1200, png).isOk());
    ASSERT_TRUE(w->append(2200, raw).isOk());
    EXPECT_EQ(w->append(3000, std::vector<std::uint8_t>{1, 2, 3}).code(),
              StatusCode::kTruncated);  // not a record: refused
    ASSERT_TRUE(w->close().isOk());
    ASSERT_TRUE(TimedFrameFileWriter::setClockOffset(path.string(), 5 * kNsPerSec).isOk());

    auto r = TimedFrameFileReader::open(path.string());
    ASSERT_TRUE(r.isOk()) << r.status().message();
    auto first = r->next();
    ASSERT_TRUE(first.isOk() && *first);
    EXPECT_EQ((*first)->due, 1200 + 5 * kNsPerSec);
    auto v = decodeFrameRecord((*first)->record);
    ASSERT_TRUE(v.isOk());
    EXPECT_EQ(v->coding, FrameCoding::kPng);  // stored as recorded
    EXPECT_EQ(v->header.timestamp_ns, 1000 + 5 * kNsPerSec);
    EXPECT_EQ(v->header.t_host_ns, 1500 + 5 * kNsPerSec);
    EXPECT_EQ(v->header.sequence, 7u);
    EXPECT_EQ(std::vector<std::uint8_t>(v->payload.begin(), v->payload.end()), pixels(1));
    auto second = r->next();
    ASSERT_TRUE(second.isOk() && *second);
    auto v2 = decodeFrameRecord((*second)->record);
    ASSERT_TRUE(v2.isOk());
    EXPECT_EQ(v2->header.timestamp_ns, 2000);  // not on CLOCK_MONOTONIC: left alone
    EXPECT_EQ(v2->header.t_host_ns, 2500 + 5 * kNsPerSec);
    auto end = r->next();
    ASSERT_TRUE(end.isOk());
    EXPECT_FALSE(*end);

    // Cut inside the second entry: an error naming the file and where.
    fs::resize_file(path, fs::file_size(path) - 10);
    auto cut = TimedFrameFileReader::open(path.string());
    ASSERT_TRUE(cut.isOk());
    ASSERT_TRUE(cut->next().isOk());
    auto bad = cut->next();
    ASSERT_FALSE(bad.isOk());
    EXPECT_NE(bad.status().message().find(path.string()), std::string::npos);
    EXPECT_NE(bad.status().message().find("truncated"), std::string::npos);
    fs::remove(path);

    std::ofstream(tempPath("not.frames")) << "HSVF but not timed";
    auto wrong = TimedFrameFileReader::open(tempPath("not.frames").string());
    ASSERT_FALSE(wrong.isOk());
    EXPECT_NE(wrong.status().message().find("not a timed camera frame file"), std::string::npos);
    fs::remove(tempPath("not.frames"));
}

TEST(HostClockReplay, TheCameraDriverGetsEachFrameAtItsDueTimeNoneBefore) {
    const fs::path path = tempPath("paced.frames");
    // Recorded on another clock (frames 40 ms apart from t = 10 s); played from 300 ms from now.
    const TimeNs rec0 = 10 * kNsPerSec;
    const TimeNs period = 40 * kNsPerMs;
    {
        auto w = TimedFrameFileWriter::create(path.string());
        ASSERT_TRUE(w.isOk());
        for (std::uint32_t k = 0; k < 6; ++k) {
            const TimeNs t = rec0 + k * period;
            ASSERT_TRUE(
                w->append(t + 5 * kNsPerMs, encodeFrameRecord(greyHeader(100 + k, t, t + kNsPerMs),
                                                              pixels(static_cast<std::uint8_t>(k)),
                                                              FrameCoding::kPng))
                    .isOk());
        }
        ASSERT_TRUE(w->close().isOk());
    }
    const TimeNs offset = monotonicNow() + 300 * kNsPerMs - rec0;
    ASSERT_TRUE(TimedFrameFileWriter::setClockOffset(path.string(), offset).isOk());

    auto device = openHostClockReplay(path.string(), {1, 25});
    CameraConfig cfg;
    cfg.width = kW;
    cfg.height = kH;
    cfg.frame_interval = {1, 25};
    CameraDevice cam(*device, cfg);
    ASSERT_TRUE(cam.start().isOk());
    EXPECT_EQ(cam.format().pixelformat, kFourccGrey);
    EXPECT_EQ(cam.format().width, kW);
    EXPECT_GE(cam.bufferCount(), 2u);

    std::vector<TimeNs> got_at, stamps;
    const TimeNs give_up = monotonicNow() + 2 * kNsPerSec;
    while (got_at.size() < 6 && monotonicNow() < give_up) {
        auto f = cam.grab(100 * kNsPerMs);
        ASSERT_TRUE(f.isOk()) << f.status().message();
        if (!*f) continue;
        got_at.push_back(monotonicNow());
        stamps.push_back((*f)->t_host);
        EXPECT_EQ((*f)->data, pixels(static_cast<std::uint8_t>(got_at.size() - 1)));
    }
    ASSERT_EQ(got_at.size(), 6u);
    for (std::size_t k = 0; k < 6; ++k) {
        const TimeNs due = rec0 + static_cast<TimeNs>(k) * period + 5 * kNsPerMs + offset;
        EXPECT_GE(got_at[k], due) << "frame " << k << " delivered early";
        EXPECT_LT(got_at[k], due + 30 * kNsPerMs) << "frame " << k << " delivered late";
        // Mid-exposure on the host clock: start of exposure + half the 2 ms exposure.
        EXPECT_EQ(stamps[k], rec0 + static_cast<TimeNs>(k) * period + offset + kNsPerMs);
    }
    EXPECT_EQ(cam.stats().dropped, 0u);
    ASSERT_TRUE(cam.stop().isOk());

    // Opened again after every frame was due (a restarted daemon): those are gone.
    auto again = openHostClockReplay(path.string(), {1, 25});
    CameraDevice cam2(*again, cfg);
    ASSERT_TRUE(cam2.start().isOk());
    auto none = cam2.grab(50 * kNsPerMs);
    ASSERT_TRUE(none.isOk());
    EXPECT_FALSE(*none) << "a frame due before STREAMON was delivered";
    ASSERT_TRUE(cam2.stop().isOk());
    fs::remove(path);
}

TEST(HostClockReplay, AFileThatCannotBeReadFailsTheCameraStartNamingIt) {
    auto device = openHostClockReplay("/nonexistent/colour.frames", {1, 5});
    CameraDevice cam(*device, CameraConfig{});
    const Status s = cam.start();
    ASSERT_FALSE(s.isOk());
    EXPECT_NE(s.message().find("/nonexistent/colour.frames"), std::string::npos) << s.message();
}

}  // namespace
}  // namespace handscan::camera
