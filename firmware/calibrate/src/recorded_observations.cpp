#include "handscan/calibrate/recorded_observations.hpp"

#include <algorithm>
#include <variant>

#include "handscan/sources/recorded_source.hpp"

namespace handscan::calibrate {
namespace {

struct Decoded {
    std::vector<LaserScan> scans;
    std::vector<EncoderSample> encoder;
};

Result<Decoded> decode(const std::string& recording, const DeviceConfig& device) {
    sources::RecordedSourceOptions options;
    options.laser = true;
    options.colour = false;
    options.fast = true;
    auto opened = sources::RecordedSource::open(recording, device, options);
    if (!opened.isOk()) return opened.status();
    Decoded d;
    std::vector<sources::Sample> samples;
    for (;;) {
        samples.clear();
        auto clock = (*opened)->next(samples);
        if (!clock.isOk()) return clock.status();
        for (auto& s : samples) {
            if (auto* scan = std::get_if<LaserScan>(&s)) d.scans.push_back(std::move(*scan));
            if (auto* e = std::get_if<EncoderSample>(&s)) d.encoder.push_back(*e);
        }
        if (!clock->has_value()) break;
    }
    std::stable_sort(
        d.encoder.begin(), d.encoder.end(),
        [](const EncoderSample& a, const EncoderSample& b) { return a.t_host < b.t_host; });
    if (d.scans.empty() || d.encoder.size() < 2)
        return Status{StatusCode::kInvalidArgument,
                      recording + ": needs /hokuyo/raw scans and /motor/can encoder positions (" +
                          std::to_string(d.scans.size()) + " scans, " +
                          std::to_string(d.encoder.size()) + " encoder samples decoded)"};
    return d;
}

}  // namespace

Result<std::vector<SpinObservation>> loadObservations(
    const std::string& recording, const DeviceConfig& device, const Calibration& base,
    const tum::Trajectory& trajectory, const std::vector<std::pair<double, double>>& excluded_s,
    const std::vector<ImuSample>& imu, const ObservationOptions& options) {
    auto decoded = decode(recording, device);
    if (!decoded.isOk()) return decoded.status();
    auto out = pairObservations(decoded->scans, decoded->encoder, base, trajectory, excluded_s, imu,
                                options);
    if (!out.isOk()) return Status(out.status().code(), recording + ": " + out.status().message());
    return out;
}

}  // namespace handscan::calibrate
