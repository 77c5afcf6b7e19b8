// The Xsens source: XsensDriver runs its own thread (configure, stream, reconnect with back-off);
// this thread builds the link, watches the driver's health and mirrors it for the status bar.
#include "handscan/pipeline_daemon/sensor_sources.hpp"
#include "handscan/xsens/xsens_driver.hpp"

namespace handscan::pipeline_daemon {
namespace {

class XsensSource final : public SensorSource {
public:
    explicit XsensSource(const SourceContext& c)
        : SensorSource("xsens", static_cast<float>(c.config.xsens.rate_hz)),
          config_(c.config.xsens),
          c_(c) {}
    ~XsensSource() override { stop(); }

private:
    void run() override {
        Backoff backoff(kNsPerSec, 10 * kNsPerSec);
        std::unique_ptr<xsens::XsensDriver> driver;
        while (!stopping() && !driver) {
            auto link = c_.links.xsens(config_);
            if (link.isOk()) {
                driver = std::make_unique<xsens::XsensDriver>(
                    std::move(*link),
                    [this](const ImuSample& s) {
                        health_.addSample(s.t_host);
                        if (!c_.queues.imu.tryPush(s))
                            c_.queues.dropped.fetch_add(1, std::memory_order_relaxed);
                    },
                    c_.taps.xsens, driverOptions());
                break;
            }
            health_.setLost("xsens: " + link.status().message());
            health_.markAttempted();
            if (!sleepFor(backoff.next())) return;
        }
        if (!driver) return;
        driver->start();
        while (sleepFor(50 * kNsPerMs)) {
            const xsens::XsensHealth h = driver->health();
            if (h.state == xsens::XsensDriverState::kStreaming) {
                health_.setConnected();
                health_.markAttempted();
            } else if (!h.last_problem.empty()) {
                health_.setLost("xsens " + config_.serial_path + ": " + h.last_problem);
                health_.markAttempted();
            }
        }
        driver->stop();
    }

    // The driver's reading thread is the one that time-stamps the bytes: it gets the priority.
    xsens::XsensDriverOptions driverOptions() const {
        xsens::XsensDriverOptions o;
        o.fifo_priority = fifoPriority();
        return o;
    }

    XsensConfig config_;
    SourceContext c_;
};

}  // namespace

std::unique_ptr<SensorSource> makeXsensSource(const SourceContext& c) {
    return std::make_unique<XsensSource>(c);
}

}  // namespace handscan::pipeline_daemon
