// SampleSource: where the pipeline worker's samples come from, live or recorded, behind one
// interface (ouster-sdk's PacketSource is the model). A source decodes each device's bytes with
// that device's driver (stream decoders in drivers/<device>/), so a sample carries the same time
// stamp whether it came from the device now or from a recording of it. The worker merges the
// samples of all devices by that time (worker/sample_merger.hpp), which needs the source's clock:
// no sample still to come was received before it.
#pragma once

#include <optional>
#include <variant>
#include <vector>

#include "handscan/core/samples.hpp"
#include "handscan/core/status.hpp"

namespace handscan::sources {

// A frame of the tracking camera (the visual-inertial odometry's, section 5), kept apart from the
// colour camera's Image: both are V4L2 frames, but they go to different modules.
struct TrackingFrame {
    TimeNs t_host = 0;  // mid-exposure, as image.t_host
    Image image;
};

// One decoded sample of any device the pipeline consumes. (New kinds go last: the merger breaks
// ties between kinds by this order.)
using Sample = std::variant<ImuSample, EncoderSample, LaserScan, Image, TrackingFrame>;

inline TimeNs sampleTime(const Sample& s) {
    return std::visit([](const auto& v) { return v.t_host; }, s);
}

class SampleSource {
public:
    virtual ~SampleSource() = default;

    // Appends the samples decoded since the last call to `out` and returns the source's clock
    // (host receive time): every sample still to come is received after it. A live source
    // returns now; a recording the log time of the message it just read. nullopt: the end of
    // the stream (a recording read to its end); an error: the stream cannot be read on.
    [[nodiscard]] virtual Result<std::optional<TimeNs>> next(std::vector<Sample>& out) = 0;
};

}  // namespace handscan::sources
