// RecordingFakes: the devices of a recording, played over their real transports at the
// recording's pace, all on one shifted clock (host time = recording time + offset):
//   Hokuyo   FakeHokuyoServer on loopback TCP: answers the driver's start-up (SCIP2.0, VV, PP,
//            II, BM, ME/MD) and sends each recorded scan frame at its recorded receive time;
//   Xsens    FakeXsens behind a pty: answers GoToConfig, ReqDID, ReqProductCode,
//            SetOutputConfiguration, GoToMeasurement as the recorded MTi (its id and product
//            code), then sends the recorded MTData2 bytes at their receive times;
//   CAN      a candump log on the host clock for the daemon's `candump-host-clock:FILE` bus:
//            the emulated encoder's and drive's answers to the daemon's own NMT/SDO start-up,
//            then the recorded PDOs and heartbeats at their times;
//   cameras  timed frame files for the daemon's `v4l2-replay-host-clock:FILE` cameras (a V4L2
//            device without a kernel answering the driver's QUERYCAP, S_FMT, REQBUFS, mmap,
//            STREAMON), each recorded buffer due at its recorded dequeue time.
// Nothing streams before the offset makes it due, so the daemon can open every device and start
// the scan first.
#pragma once

#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "handscan/core/config.hpp"
#include "handscan/hil/recorded_streams.hpp"
#include "handscan/hokuyo_fake/fake_hokuyo_server.hpp"
#include "handscan/xsens_fake/fake_xsens.hpp"
#include "handscan/xsens_fake/pty_xsens.hpp"

namespace handscan::hil {

struct FakesOptions {
    bool hokuyo = true;
    bool xsens = true;
    bool motor = true;
    bool cameras = true;
    // Drop the laser's TCP connection this many seconds into the recording (mid-frame).
    std::optional<double> hokuyo_disconnect_s;
    // Seconds before the recording in which the fake laser repeats the first recorded scan (the
    // scanner held still where the recording begins), as a powered UTM-30LX-EW streams before
    // anyone records: the driver's scan watchdog (1 s) must not fire while the daemon starts.
    double hokuyo_preroll_s = 0.0;
};

class RecordingFakes {
public:
    // Starts the fakes (`rec` must outlive them); `offset` = host CLOCK_MONOTONIC - recording
    // time. Throws
    // std::runtime_error when a transport cannot be set up (no pty, no loopback port).
    // `motor`: the daemon's motor configuration (its start-up is answered as it will ask).
    RecordingFakes(const RecordedStreams& rec, const MotorConfig& motor, TimeNs offset,
                   const std::filesystem::path& dir, FakesOptions options);
    ~RecordingFakes();

    // Where the daemon finds each device (empty / 0 when that device is left out).
    int hokuyoPort() const { return hokuyo_ ? hokuyo_->port() : 0; }
    std::string xsensPath() const { return pty_ ? pty_->slavePath() : std::string(); }
    const std::filesystem::path& candumpPath() const { return candump_; }
    // For a daemon started again: a new CAN log whose start-up exchange begins at `startup_at`
    // (host time; the new daemon's MotorDevice start-up is answered as the first one's was, its
    // boot-up wait catching the boot-up), then the recorded frames due after it. The frames
    // before are gone, as on a bus nobody listened to. Becomes candumpPath(); empty without CAN.
    std::filesystem::path restartCandump(TimeNs startup_at);
    const std::string& trackFramesPath() const { return track_frames_; }
    const std::string& colourFramesPath() const { return colour_frames_; }

    // What was played: for stats.json.
    struct Counts {
        std::size_t scans_recorded = 0, scans_sent = 0, scans_skipped = 0;
        std::size_t hokuyo_connections = 0;
        std::size_t xsens_chunks_recorded = 0, xsens_chunks_sent = 0, xsens_chunks_lost = 0;
        std::size_t can_frames = 0;
        std::size_t track_frames = 0, colour_frames = 0;
    };
    Counts counts() const;

private:
    const RecordedStreams& rec_;
    MotorConfig motor_;
    TimeNs offset_;
    std::filesystem::path dir_;
    int restarts_ = 0;
    std::size_t scans_ = 0;
    std::size_t can_frames_ = 0;
    std::size_t xsens_chunks_ = 0;
    std::size_t track_frame_count_ = 0, colour_frame_count_ = 0;
    std::filesystem::path candump_;
    std::string track_frames_, colour_frames_;
    std::unique_ptr<hokuyo::FakeHokuyoServer> hokuyo_;
    std::unique_ptr<xsens::FakeXsens> xsens_;
    std::unique_ptr<xsens::PtyXsens> pty_;
};

}  // namespace handscan::hil
