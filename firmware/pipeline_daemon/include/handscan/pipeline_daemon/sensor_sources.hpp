// The daemon's device threads. Each SensorSource owns one device through its real driver, opens
// it, streams its samples into the live source's SPSC queues (sources::LiveSource), and when the
// device is absent or vanishes reports it in its SensorHealth and retries with back-off; the other
// devices and the pipeline keep running. A full queue drops the sample and counts it (a driver
// never waits for the pipeline).
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <string>
#include <thread>

#include "handscan/core/config.hpp"
#include "handscan/core/samples.hpp"
#include "handscan/gpio/led_pattern.hpp"
#include "handscan/pipeline_daemon/device_links.hpp"
#include "handscan/pipeline_daemon/scan_recorder.hpp"
#include "handscan/pipeline_daemon/sensor_health.hpp"
#include "handscan/sources/live_source.hpp"

namespace handscan::pipeline_daemon {

// Driver threads -> pipeline thread: the live source's queues (sources/live_source.hpp).
using sources::SampleQueues;

// The operator's panel: what a button asks for, what the LEDs show.
enum class ButtonAction { kToggleScan, kExport };
struct PanelLeds {
    std::atomic<gpio::LedPattern> ready{gpio::LedPattern::kDoubleFlash};
    std::atomic<gpio::LedPattern> scanning{gpio::LedPattern::kOff};
    std::atomic<gpio::LedPattern> fault{gpio::LedPattern::kOff};
    std::atomic<gpio::LedPattern> exporting{gpio::LedPattern::kOff};
};

class SensorSource {
public:
    explicit SensorSource(std::string name, float expected_rate_hz)
        : health_(std::move(name), expected_rate_hz) {}
    virtual ~SensorSource();
    SensorSource(const SensorSource&) = delete;
    SensorSource& operator=(const SensorSource&) = delete;

    // Starts the device thread, SCHED_FIFO at `fifo_priority` when permitted (0: normal).
    void start(int fifo_priority = 0);
    // Ends the thread (within one poll slice) and closes the device.
    void stop();
    SensorHealth& health() { return health_; }

protected:
    virtual void run() = 0;
    bool stopping() const { return stop_.load(std::memory_order_acquire); }
    // Sleeps `t` unless stop() comes first; false when stopping.
    bool sleepFor(TimeNs t);
    // Runs `session` (open the device, stream until a fault) again and again until stop(): each
    // session that ends without stop() marks the device lost with "<what>: <reason><hint>" and is
    // retried after a back-off growing from `first_wait` to `max_wait`.
    void runSessions(TimeNs first_wait, TimeNs max_wait, const std::string& what, const char* hint,
                     const std::function<Status()>& session);
    // The priority start() gave this device's thread, for a driver thread of its own.
    int fifoPriority() const { return fifo_priority_; }
    SensorHealth health_;

private:
    int fifo_priority_ = 0;
    std::atomic<bool> stop_{false};
    std::thread thread_;
};

// The raw-stream taps of a scan's recording (scan_recorder.hpp); null: not recorded.
struct RawTaps {
    SwitchableTap* hokuyo = nullptr;  // keeps the laser's start-up exchange (its geometry)
    RawTap* xsens = nullptr;
    RawTap* motor = nullptr;
};

struct SourceContext {
    const DeviceConfig& config;
    DeviceLinks& links;
    SampleQueues& queues;
    RawTaps taps = {};
};

std::unique_ptr<SensorSource> makeHokuyoSource(const SourceContext& context);
std::unique_ptr<SensorSource> makeXsensSource(const SourceContext& context);
std::unique_ptr<SensorSource> makeMotorSource(const SourceContext& context);
// `colour`: the colour camera (frames to the colouriser); else the tracking camera (brightness).
std::unique_ptr<SensorSource> makeCameraSource(const SourceContext& context, bool colour);
std::unique_ptr<SensorSource> makeGpioSource(const SourceContext& context, PanelLeds& leds,
                                             std::function<void(ButtonAction)> on_button);

}  // namespace handscan::pipeline_daemon
