// The Hokuyo thread: HokuyoDevice over the TCP link; the device's own state machine reconnects
// with back-off, this thread only moves scans and mirrors its state into the health record.
#include "handscan/hokuyo/hokuyo_device.hpp"
#include "handscan/pipeline_daemon/sensor_sources.hpp"

namespace handscan::pipeline_daemon {
namespace {

class HokuyoSource final : public SensorSource {
public:
    explicit HokuyoSource(const SourceContext& c)
        : SensorSource("hokuyo", 40.0f),
          config_(c.config.hokuyo),
          queues_(c.queues),
          tap_(c.taps.hokuyo),
          link_(c.links.hokuyo(config_)) {}
    ~HokuyoSource() override { stop(); }

private:
    void run() override {
        hokuyo::HokuyoDeviceConfig cfg = hokuyo::hokuyoDeviceConfig(config_);
        cfg.timing.extra_latency_ns = fromSeconds(config_.frame_latency_ms * 1e-3);
        hokuyo::HokuyoDevice device(*link_, cfg, tap_);
        std::vector<LaserScan> scans;
        std::uint64_t faults_seen = 0;
        bool was_streaming = false;
        if (tap_) tap_->beginPreamble();
        while (!stopping()) {
            scans.clear();
            const Status st = device.poll(scans);
            for (LaserScan& s : scans) {
                health_.addSample(s.t_host);
                if (!queues_.scans.tryPush(std::move(s)))
                    queues_.dropped.fetch_add(1, std::memory_order_relaxed);
            }
            const bool streaming = device.state() == hokuyo::HokuyoDevice::State::kStreaming;
            // A recording starting later needs this connection's start-up (the PP reply).
            if (tap_ && streaming != was_streaming) {
                if (streaming)
                    tap_->endPreamble();
                else
                    tap_->beginPreamble();
            }
            was_streaming = streaming;
            const auto stats = device.stats();
            if (streaming && !scans.empty()) {
                health_.setConnected();
            } else if (!streaming && stats.faults + stats.connect_failures > faults_seen) {
                std::string what = device.lastFault();
                if (what.find(link_->describe()) == std::string::npos)
                    what = "hokuyo " + link_->describe() + ": " + what;
                health_.setLost(what + " (check the laser's power and Ethernet cable; retrying)");
            }
            if (!st.isOk() && streaming) health_.setWarning(st.message());
            faults_seen = stats.faults + stats.connect_failures;
            if (streaming || stats.connect_failures > 0 || stats.faults > 0)
                health_.markAttempted();
        }
        (void)device.stop();
    }

    HokuyoConfig config_;
    SampleQueues& queues_;
    SwitchableTap* tap_;
    std::unique_ptr<transport::ByteStream> link_;
};

}  // namespace

std::unique_ptr<SensorSource> makeHokuyoSource(const SourceContext& c) {
    return std::make_unique<HokuyoSource>(c);
}

}  // namespace handscan::pipeline_daemon
