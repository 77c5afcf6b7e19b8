#include "handscan/sources/recorded_source.hpp"

#include <algorithm>
#include <thread>
#include <type_traits>

#include "handscan/core/log.hpp"

namespace handscan::sources {
namespace {

// Each stream's index in Sample (the --skip-every-other counters).
constexpr std::size_t kImuKind = 0, kEncoderKind = 1, kScanKind = 2, kColourKind = 3,
                      kTrackingKind = 4;
static_assert(std::is_same_v<std::variant_alternative_t<kImuKind, Sample>, ImuSample>);
static_assert(std::is_same_v<std::variant_alternative_t<kEncoderKind, Sample>, EncoderSample>);
static_assert(std::is_same_v<std::variant_alternative_t<kScanKind, Sample>, LaserScan>);
static_assert(std::is_same_v<std::variant_alternative_t<kColourKind, Sample>, Image>);
static_assert(std::is_same_v<std::variant_alternative_t<kTrackingKind, Sample>, TrackingFrame>);

}  // namespace

Result<std::unique_ptr<RecordedSource>> RecordedSource::open(const std::string& path,
                                                             const DeviceConfig& device,
                                                             RecordedSourceOptions options) {
    auto reader = recording::McapReader::open(path);
    if (!reader.isOk()) return reader.status();
    if ((*reader)->truncated())
        log().warn("{}: recording was cut short; replaying every intact chunk", path);
    for (const char* topic : {kXsensTopic, kHokuyoTopic, kCanTopic}) {
        const bool needed = std::string(topic) == kXsensTopic || options.laser;
        if (needed && !(*reader)->findTopic(topic)) {
            return Status(StatusCode::kNotFound,
                          path + ": no " + std::string(topic) +
                              " channel; the pipeline needs it (or choose --modules imu)");
        }
    }
    return std::unique_ptr<RecordedSource>(new RecordedSource(std::move(*reader), device, options));
}

RecordedSource::RecordedSource(std::unique_ptr<recording::McapReader> reader,
                               const DeviceConfig& device, RecordedSourceOptions options)
    : reader_(std::move(reader)),
      options_(options),
      colour_(options.colour && reader_->findTopic(kColourTopic) != nullptr),
      tracking_(options.tracking && reader_->findTopic(kTrackingTopic) != nullptr),
      it_(reader_->messages({[&] {
          std::vector<std::string> topics{kXsensTopic};
          if (colour_) topics.push_back(kColourTopic);
          if (tracking_) topics.push_back(kTrackingTopic);
          if (options.laser) {
              topics.push_back(kHokuyoTopic);
              topics.push_back(kCanTopic);
          }
          for (const std::string& t : options.extra_topics) {
              if (std::find(topics.begin(), topics.end(), t) == topics.end()) topics.push_back(t);
          }
          return topics;
      }()})),
      hokuyo_(hokuyoTiming(device)),
      xsens_("Xsens", xsensTiming(device)),
      encoder_(encoderStreamConfig(device)),
      // Frames are stamped at mid-exposure by the live camera's rule, with its readout.
      colour_decoder_(fromSeconds(device.colour_camera.readout_ms * 1e-3)),
      tracking_decoder_(fromSeconds(device.tracking_camera.readout_ms * 1e-3)),
      wall_start_(std::chrono::steady_clock::now()) {}

double RecordedSource::durationHint() const {
    const auto& s = reader_->statistics();
    return s ? toSeconds(s->message_end_time - s->message_start_time) : 0.0;
}

bool RecordedSource::keep(std::size_t kind) {
    return !options_.skip_every_other || (decoded_[kind]++ % 2) == 0;
}

void RecordedSource::pace(TimeNs log_time) {
    if (options_.fast) return;
    // Recorded pace on the wall clock.
    const auto due =
        wall_start_ +
        std::chrono::nanoseconds(static_cast<std::int64_t>(
            static_cast<double>(log_time - t_first_) / std::max(0.01, options_.speed)));
    std::this_thread::sleep_until(due);
}

Result<std::optional<TimeNs>> RecordedSource::next(std::vector<Sample>& out) {
    if (!it_.next(msg_)) {
        if (!it_.status().isOk()) return it_.status();
        return std::optional<TimeNs>();
    }
    if (t_first_ == 0) {
        t_first_ = msg_.log_time;
        wall_start_ = std::chrono::steady_clock::now();
    }
    t_last_ = msg_.log_time;
    pace(msg_.log_time);
    if (options_.tap) options_.tap(msg_);
    const std::string& topic = msg_.channel->topic;
    if (topic == kXsensTopic) {
        imu_.clear();
        timed("decode_xsens", [&] { xsens_.feed(msg_.log_time, msg_.data, imu_); });
        for (ImuSample& s : imu_)
            if (keep(kImuKind)) out.emplace_back(std::move(s));
    } else if (topic == kHokuyoTopic) {
        scans_.clear();
        timed("decode_hokuyo", [&] { hokuyo_.feed(msg_.log_time, msg_.data, scans_); });
        for (LaserScan& s : scans_)
            if (keep(kScanKind)) out.emplace_back(std::move(s));
    } else if (topic == kCanTopic) {
        positions_.clear();
        timed("decode_can", [&] { encoder_.feed(msg_.log_time, msg_.data, positions_); });
        for (EncoderSample& s : positions_)
            if (keep(kEncoderKind)) out.emplace_back(s);
    } else if (topic == kColourTopic && colour_) {  // else read only for the tap
        timed("decode_colour", [&] {
            auto img = colour_decoder_.decode(msg_.log_time, msg_.data);
            if (img.isOk() && keep(kColourKind)) out.emplace_back(std::move(*img));
        });
    } else if (topic == kTrackingTopic && tracking_) {  // else read only for the tap
        timed("decode_tracking", [&] {
            auto img = tracking_decoder_.decode(msg_.log_time, msg_.data);
            if (img.isOk() && keep(kTrackingKind)) {
                const TimeNs t = img->t_host;
                out.emplace_back(TrackingFrame{t, std::move(*img)});
            }
        });
    }
    return std::optional<TimeNs>(msg_.log_time);
}

}  // namespace handscan::sources
