// The live source: the daemon's device threads (one per device, each running its driver over its
// real transport: pipeline_daemon/*_source.cpp) push decoded samples into these SPSC queues, and
// LiveSource drains them on the pipeline thread. A full queue drops the sample and counts it (a
// driver never waits for the pipeline).
#pragma once

#include <atomic>
#include <functional>

#include "handscan/core/spsc_queue.hpp"
#include "handscan/sources/sample_source.hpp"

namespace handscan::sources {

// Driver threads -> pipeline thread, one queue per stream (one producer each).
struct SampleQueues {
    SpscQueue<ImuSample> imu{4096};          // 20 s at 200 Hz
    SpscQueue<EncoderSample> encoder{8192};  // 40 s at 200 Hz
    SpscQueue<LaserScan> scans{512};         // 12 s at 40 Hz
    SpscQueue<Image> colour_images{8};       // large frames: a few are enough for colouring
    SpscQueue<Image> tracking_images{32};    // 0.6 s at 50 Hz (the visual-inertial odometry)
    std::atomic<std::uint64_t> dropped{0};
    std::atomic<float> camera_brightness{0};  // mean grey level of the tracking camera
};

class LiveSource final : public SampleSource {
public:
    explicit LiveSource(SampleQueues& queues, std::function<TimeNs()> now = monotonicNow)
        : queues_(queues), now_(std::move(now)) {}
    // Never ends: the devices stream until the daemon stops.
    [[nodiscard]] Result<std::optional<TimeNs>> next(std::vector<Sample>& out) override;

private:
    SampleQueues& queues_;
    std::function<TimeNs()> now_;
};

}  // namespace handscan::sources
