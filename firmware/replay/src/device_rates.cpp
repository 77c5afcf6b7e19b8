#include "handscan/replay/device_rates.hpp"

#include <string>

#include "handscan/camera/frame_record.hpp"
#include "handscan/camera/frame_timing.hpp"
#include "handscan/recording/channels.hpp"
#include "handscan/sources/stream_config.hpp"

namespace handscan::replay {
namespace {

namespace ch = recording::channels;

// Decoded samples of one device and the span of their time stamps.
struct SampleCount {
    bool seen = false;  // the raw channel had at least one message
    std::uint64_t samples = 0;
    TimeNs first = 0;
    TimeNs last = 0;
    std::uint64_t lost = 0;
    std::uint64_t errors = 0;
    std::string last_error;

    void add(TimeNs t) {
        if (samples == 0) first = t;
        last = t;
        ++samples;
    }
    void fail(std::string why) {
        ++errors;
        last_error = std::move(why);
    }
};

struct CameraStream {
    SampleCount count;
    camera::SequenceTracker sequence;
};

recording::DeviceSummary summary(const char* device, const recording::ChannelSpec& spec,
                                 const char* unit, const SampleCount& c) {
    recording::DeviceSummary d;
    d.device = device;
    d.topic = std::string(spec.topic);
    d.unit = unit;
    d.samples = c.samples;
    d.first = c.first;
    d.last = c.last;
    if (c.samples >= 2 && c.last > c.first)
        d.rate_hz = static_cast<double>(c.samples - 1) / toSeconds(c.last - c.first);
    d.lost = c.lost;
    d.errors = c.errors;
    d.last_error = c.last_error;
    return d;
}

// Folds a stream decoder's counters into a count.
void takeCounters(const StreamCounters& s, SampleCount& c) {
    c.lost = s.gaps;
    c.errors = s.checksum_failures + s.resyncs + s.errors;
    c.last_error = s.last_error;
}

}  // namespace

struct DeviceRateMeter::Streams {
    explicit Streams(const DeviceConfig& device)
        : hokuyo(sources::hokuyoTiming(device)),
          xsens("Xsens", sources::xsensTiming(device)),
          encoder(sources::encoderStreamConfig(device)) {}

    hokuyo::ScanStreamDecoder hokuyo;
    xsens::ImuStreamDecoder xsens;
    motor::EncoderStreamDecoder encoder;
    SampleCount scans, imu, positions, edges;
    CameraStream track, colour;
    std::vector<LaserScan> scan_out;
    std::vector<ImuSample> imu_out;
    std::vector<EncoderSample> encoder_out;

    void frame(CameraStream& cam, std::span<const std::uint8_t> data) {
        cam.count.seen = true;
        // The V4L2 metadata is all a rate needs: coded payloads stay coded.
        auto rec = camera::decodeFrameRecord(data, camera::FramePayload::kHeaderOnly);
        if (!rec) {
            cam.count.fail(rec.status().message());
            return;
        }
        cam.count.lost += cam.sequence.update(rec->header.sequence);
        cam.count.add(rec->header.timestamp_ns);
    }
};

DeviceRateMeter::DeviceRateMeter(const DeviceConfig& device)
    : s_(std::make_unique<Streams>(device)) {}
DeviceRateMeter::~DeviceRateMeter() = default;

void DeviceRateMeter::feed(std::string_view topic, TimeNs log_time,
                           std::span<const std::uint8_t> data) {
    Streams& s = *s_;
    if (topic == ch::kHokuyoRaw.topic) {
        s.scans.seen = true;
        s.scan_out.clear();
        s.hokuyo.feed(log_time, data, s.scan_out);
        for (const LaserScan& scan : s.scan_out) s.scans.add(scan.t_host);
    } else if (topic == ch::kXsensRaw.topic) {
        s.imu.seen = true;
        s.imu_out.clear();
        s.xsens.feed(log_time, data, s.imu_out);
        for (const ImuSample& sample : s.imu_out) s.imu.add(sample.t_host);
    } else if (topic == ch::kMotorCan.topic) {
        s.positions.seen = true;
        s.encoder_out.clear();
        s.encoder.feed(log_time, data, s.encoder_out);
        for (const EncoderSample& sample : s.encoder_out) s.positions.add(sample.t_host);
    } else if (topic == ch::kCameraTrack.topic) {
        s.frame(s.track, data);
    } else if (topic == ch::kCameraColour.topic) {
        s.frame(s.colour, data);
    } else if (topic == ch::kGpioEvents.topic) {
        s.edges.seen = true;
        auto edge = recording::decodeGpioEdge(data);
        if (edge) {
            s.edges.add(edge->t_host);
        } else {
            s.edges.fail(edge.status().message());
        }
    }
}

std::vector<recording::DeviceSummary> DeviceRateMeter::summaries() const {
    const Streams& s = *s_;
    SampleCount scans = s.scans, imu = s.imu, positions = s.positions;
    takeCounters(s.hokuyo.counters(), scans);
    takeCounters(s.xsens.counters(), imu);
    takeCounters(s.encoder.counters(), positions);
    std::vector<recording::DeviceSummary> out;
    if (scans.seen) out.push_back(summary("Hokuyo laser", ch::kHokuyoRaw, "scans/s", scans));
    if (imu.seen) out.push_back(summary("Xsens IMU", ch::kXsensRaw, "IMU samples/s", imu));
    if (positions.seen)
        out.push_back(summary("motor encoder", ch::kMotorCan, "positions/s", positions));
    if (s.track.count.seen)
        out.push_back(summary("tracking camera", ch::kCameraTrack, "frames/s", s.track.count));
    if (s.colour.count.seen)
        out.push_back(summary("colour camera", ch::kCameraColour, "frames/s", s.colour.count));
    if (s.edges.seen) out.push_back(summary("GPIO", ch::kGpioEvents, "edges/s", s.edges));
    return out;
}

}  // namespace handscan::replay
