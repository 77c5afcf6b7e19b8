// The device-level view of a recording's raw channels for `handscan info`: each raw stream is
// decoded with the drivers' stream decoders replay uses (sources/stream_config.hpp; the camera
// codec's frame records; the GPIO edge record), and the rate is counted in decoded samples on their
// own time stamps - Hokuyo scans (step-0 time from the sensor's millisecond clock), Xsens samples
// (SampleTimeFine), encoder positions (TPDO1 on the encoder's cyclic timer), camera frames (V4L2
// buffer timestamps), GPIO edges - instead of TCP segments, serial reads or CAN frames.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string_view>
#include <vector>

#include "handscan/core/config.hpp"
#include "handscan/core/time.hpp"
#include "handscan/recording/recording_summary.hpp"

namespace handscan::replay {

class DeviceRateMeter {
public:
    // `device` gives what the streams do not carry: the encoder's node id, counts per revolution
    // and TPDO period, the Hokuyo's frame latency.
    explicit DeviceRateMeter(const DeviceConfig& device);
    ~DeviceRateMeter();
    DeviceRateMeter(const DeviceRateMeter&) = delete;
    DeviceRateMeter& operator=(const DeviceRateMeter&) = delete;

    // One recorded message (any channel; only known raw channels are decoded), in log-time order.
    void feed(std::string_view topic, TimeNs log_time, std::span<const std::uint8_t> data);
    // One entry per raw channel seen, in the order of recording::knownChannels().
    std::vector<recording::DeviceSummary> summaries() const;

private:
    struct Streams;
    std::unique_ptr<Streams> s_;
};

}  // namespace handscan::replay
