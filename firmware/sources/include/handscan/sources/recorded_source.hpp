// The recorded source: a recording's raw device channels (/hokuyo/raw SCIP bytes, /xsens/raw
// Xbus bytes, /motor/can candump lines, /camera/colour and /camera/track frame records), read in
// log-time order
// and decoded by the drivers' stream decoders with each message's log time as its receive time,
// as the live drivers decode the bytes they receive. As fast as possible (deterministic: the
// recording's own clock is the source's clock), or paced on the wall clock at the recording's
// pace (times `speed`).
#pragma once

#include <array>
#include <chrono>
#include <functional>
#include <memory>
#include <string>

#include "handscan/camera/frame_stream_decoder.hpp"
#include "handscan/core/call_timer.hpp"
#include "handscan/core/config.hpp"
#include "handscan/recording/mcap_reader.hpp"
#include "handscan/sources/sample_source.hpp"
#include "handscan/sources/stream_config.hpp"

namespace handscan::sources {

inline constexpr const char* kHokuyoTopic = "/hokuyo/raw";
inline constexpr const char* kXsensTopic = "/xsens/raw";
inline constexpr const char* kCanTopic = "/motor/can";
inline constexpr const char* kColourTopic = "/camera/colour";
inline constexpr const char* kTrackingTopic = "/camera/track";

struct RecordedSourceOptions {
    bool laser = true;      // /hokuyo/raw and /motor/can (false: IMU only)
    bool colour = true;     // /camera/colour when recorded
    bool tracking = false;  // /camera/track when recorded (the visual-inertial odometry)
    // The paper's "2x speed" (Table 3): every other sample of every stream is dropped after
    // decoding (IMU 100 Hz, scans 20 Hz, encoder 100 Hz, cameras at half rate).
    bool skip_every_other = false;
    bool fast = true;            // as fast as possible; else paced at the recording's pace
    double speed = 1.0;          // pace multiplier without `fast`
    CallTimer* timer = nullptr;  // decode_* costs, when set
    // Also read these topics (a viewer's: /camera/track, /groundtruth/pose), and hand every
    // message read, of any topic, to `tap` before it is decoded; the samples are the same.
    std::vector<std::string> extra_topics;
    std::function<void(const recording::RecordedMessage&)> tap;
};

class RecordedSource final : public SampleSource {
public:
    // Fails when the file is not a readable recording or lacks a channel the options need.
    [[nodiscard]] static Result<std::unique_ptr<RecordedSource>> open(
        const std::string& path, const DeviceConfig& device, RecordedSourceOptions options);

    // One message per call: its decoded samples, and its log time as the source's clock.
    [[nodiscard]] Result<std::optional<TimeNs>> next(std::vector<Sample>& out) override;

    const recording::McapReader& reader() const { return *reader_; }
    bool hasColour() const { return colour_; }
    bool hasTracking() const { return tracking_; }
    // Log time of the first and the latest message read (0 before the first).
    TimeNs firstTime() const { return t_first_; }
    TimeNs lastTime() const { return t_last_; }
    double durationHint() const;  // recorded span from the summary, s (0 if unknown)
    StreamCounters hokuyo() const { return hokuyo_.counters(); }
    StreamCounters xsens() const { return xsens_.counters(); }
    StreamCounters encoder() const { return encoder_.counters(); }
    StreamCounters colourFrames() const { return colour_decoder_.counters(); }
    StreamCounters trackingFrames() const { return tracking_decoder_.counters(); }

private:
    RecordedSource(std::unique_ptr<recording::McapReader> reader, const DeviceConfig& device,
                   RecordedSourceOptions options);
    void pace(TimeNs log_time);
    // --skip-every-other: false for every other sample of the stream `kind` (a Sample index).
    bool keep(std::size_t kind);
    template <typename Fn>
    void timed(const char* module, Fn&& fn) {
        if (options_.timer != nullptr)
            options_.timer->time(module, fn);
        else
            fn();
    }

    std::unique_ptr<recording::McapReader> reader_;
    RecordedSourceOptions options_;
    bool colour_ = false;
    bool tracking_ = false;
    recording::MessageIterator it_;
    recording::RecordedMessage msg_;
    hokuyo::ScanStreamDecoder hokuyo_;
    xsens::ImuStreamDecoder xsens_;
    motor::EncoderStreamDecoder encoder_;
    camera::FrameStreamDecoder colour_decoder_;
    camera::FrameStreamDecoder tracking_decoder_;
    std::array<std::uint64_t, std::variant_size_v<Sample>> decoded_{};
    std::vector<LaserScan> scans_;
    std::vector<ImuSample> imu_;
    std::vector<EncoderSample> positions_;
    TimeNs t_first_ = 0;
    TimeNs t_last_ = 0;
    std::chrono::steady_clock::time_point wall_start_;
};

}  // namespace handscan::sources
