#include "handscan/sources/live_source.hpp"

namespace handscan::sources {
namespace {

template <typename T>
void drain(SpscQueue<T>& q, std::vector<Sample>& out) {
    while (auto v = q.tryPop()) out.emplace_back(std::move(*v));
}

}  // namespace

Result<std::optional<TimeNs>> LiveSource::next(std::vector<Sample>& out) {
    // The clock first: whatever a driver queues after this was received after it.
    const TimeNs now = now_();
    drain(queues_.imu, out);
    drain(queues_.encoder, out);
    drain(queues_.scans, out);
    drain(queues_.colour_images, out);
    while (auto image = queues_.tracking_images.tryPop()) {
        const TimeNs t = image->t_host;
        out.emplace_back(TrackingFrame{t, std::move(*image)});
    }
    return std::optional<TimeNs>(now);
}

}  // namespace handscan::sources
