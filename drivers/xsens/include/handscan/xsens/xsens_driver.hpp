// The Xsens driver thread: owns the link and the XsensDevice, configures the device, streams
// ImuSamples to a sink, and when the link drops or the device stops answering, reports it and
// reconnects with exponential back-off, resuming the stream. makeXsensLink() builds the link
// (serial tty with baud probing, or USB) from the `xsens:` section of device.yaml.
#pragma once

#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "handscan/core/config.hpp"
#include "handscan/xsens/xsens_device.hpp"

namespace handscan::xsens {

struct XsensLink {
    std::unique_ptr<transport::ByteStream> stream;
    XsensDeviceConfig device;  // rate, precision, outputs, and the serial retune hook
};

// Serial: SerialStream at `baud` with probing/switching; usb: UsbStream over libusb (fails with
// kUnsupported when built without HANDSCAN_WITH_LIBUSB). Bad values fail naming the key.
Result<XsensLink> makeXsensLink(const XsensConfig& config);

enum class XsensDriverState { kStopped, kConnecting, kStreaming };

struct XsensHealth {
    XsensDriverState state = XsensDriverState::kStopped;
    XsensDeviceStats stats;     // of the current connection
    std::uint64_t samples = 0;  // handed to the sink since start()
    int reconnects = 0;
    std::string last_problem;  // what went wrong last (empty when nothing did)
};

struct XsensDriverOptions {
    TimeNs poll_timeout = 100 * kNsPerMs;
    TimeNs backoff_min = 100 * kNsPerMs;
    TimeNs backoff_max = 5 * kNsPerSec;
    int fifo_priority = 0;  // of the driver's thread (core/realtime.hpp); 0 = normal scheduling
};

class XsensDriver {
public:
    using Sink = std::function<void(const ImuSample&)>;

    XsensDriver(XsensLink link, Sink sink, RawTap* tap = nullptr, XsensDriverOptions options = {});
    ~XsensDriver();
    XsensDriver(const XsensDriver&) = delete;
    XsensDriver& operator=(const XsensDriver&) = delete;

    void start();
    void stop();  // returns once the thread has ended and the link is closed
    XsensHealth health() const;

private:
    void run();
    void setProblem(const std::string& problem);
    bool sleepFor(TimeNs t);  // false when stop() was called meanwhile

    XsensLink link_;
    Sink sink_;
    XsensDriverOptions options_;
    std::unique_ptr<XsensDevice> device_;
    mutable std::mutex mutex_;
    std::condition_variable wake_;
    bool stop_ = false;
    XsensHealth health_;
    std::thread thread_;
};

}  // namespace handscan::xsens
