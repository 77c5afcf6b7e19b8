#include "handscan/xsens/xsens_driver.hpp"

#include <algorithm>

#include "handscan/core/log.hpp"
#include "handscan/core/realtime.hpp"
#include "handscan/transport/serial_stream.hpp"
#include "handscan/transport/usb_stream.hpp"

namespace handscan::xsens {

Result<XsensLink> makeXsensLink(const XsensConfig& c) {
    XsensLink link;
    if (c.rate_hz <= 0 || c.rate_hz > 400 || 400 % c.rate_hz != 0) {
        return Status{StatusCode::kInvalidArgument,
                      "xsens.rate_hz: " + std::to_string(c.rate_hz) +
                          " is not a divisor of the MTi's 400 Hz (use 100, 200 or 400)"};
    }
    link.device.output_rate_hz = static_cast<std::uint16_t>(c.rate_hz);
    link.device.delta_q_delta_v = c.delta_q_v;
    link.device.frame_latency = fromSeconds(c.frame_latency_ms * 1e-3);
    if (c.transport == "serial") {
        if (!baudrateId(c.baud)) {
            return Status{StatusCode::kInvalidArgument,
                          "xsens.baud: " + std::to_string(c.baud) +
                              " is not an Xbus rate (921600, 460800, 230400, 115200)"};
        }
        auto serial = std::make_unique<transport::SerialStream>(
            transport::SerialConfig{c.serial_path, c.baud});
        transport::SerialStream* raw = serial.get();
        link.device.baudrate = c.baud;
        link.device.set_link_baudrate = [raw](int baud) { return raw->setBaudrate(baud); };
        link.stream = std::move(serial);
        return link;
    }
    if (c.transport == "usb") {
#if defined(HANDSCAN_WITH_LIBUSB) && HANDSCAN_WITH_LIBUSB
        link.stream = std::make_unique<transport::UsbStream>(transport::UsbConfig{},
                                                             transport::makeLibusbDeviceLayer());
        return link;
#else
        return Status{StatusCode::kUnsupported,
                      "xsens.transport: usb needs a build with HANDSCAN_WITH_LIBUSB=ON "
                      "(libusb-1.0); use serial"};
#endif
    }
    return Status{StatusCode::kInvalidArgument,
                  "xsens.transport: expected serial or usb, got '" + c.transport + "'"};
}

XsensDriver::XsensDriver(XsensLink link, Sink sink, RawTap* tap, XsensDriverOptions options)
    : link_(std::move(link)), sink_(std::move(sink)), options_(options) {
    device_ = std::make_unique<XsensDevice>(*link_.stream, link_.device, tap);
}

XsensDriver::~XsensDriver() { stop(); }

void XsensDriver::start() {
    std::lock_guard lock(mutex_);
    if (thread_.joinable()) return;
    stop_ = false;
    thread_ = std::thread([this] {
        (void)enterRealtimeThread("hs-xsens-rx", options_.fifo_priority);
        run();
    });
}

void XsensDriver::stop() {
    {
        std::lock_guard lock(mutex_);
        stop_ = true;
    }
    wake_.notify_all();
    if (thread_.joinable()) thread_.join();
    link_.stream->close();
    std::lock_guard lock(mutex_);
    health_.state = XsensDriverState::kStopped;
}

XsensHealth XsensDriver::health() const {
    std::lock_guard lock(mutex_);
    return health_;
}

void XsensDriver::setProblem(const std::string& problem) {
    log().warn("{}", problem);
    std::lock_guard lock(mutex_);
    health_.last_problem = problem;
}

bool XsensDriver::sleepFor(TimeNs t) {
    std::unique_lock lock(mutex_);
    return !wake_.wait_for(lock, std::chrono::nanoseconds(t), [this] { return stop_; });
}

void XsensDriver::run() {
    TimeNs backoff = options_.backoff_min;
    std::vector<ImuSample> samples;
    bool first = true;
    for (;;) {
        {
            std::lock_guard lock(mutex_);
            if (stop_) return;
            health_.state = XsensDriverState::kConnecting;
            if (!first) ++health_.reconnects;
        }
        first = false;
        // 1. Connect and configure; on failure wait and try again, longer each time.
        link_.stream->close();
        if (Status s = device_->configure(); !s) {
            setProblem(s.message() + "; retrying in " + std::to_string(backoff / kNsPerMs) + " ms");
            if (!sleepFor(backoff)) return;
            backoff = std::min(backoff * 2, options_.backoff_max);
            continue;
        }
        backoff = options_.backoff_min;
        {
            std::lock_guard lock(mutex_);
            health_.state = XsensDriverState::kStreaming;
        }
        // 2. Stream until the link fails or we are stopped.
        for (;;) {
            {
                std::lock_guard lock(mutex_);
                if (stop_) return;
            }
            samples.clear();
            Status s = device_->poll(samples, options_.poll_timeout);
            for (const auto& sample : samples) sink_(sample);
            {
                std::lock_guard lock(mutex_);
                health_.samples += samples.size();
                health_.stats = device_->stats();
                if (!device_->problems().empty()) health_.last_problem = device_->problems().back();
            }
            if (!s) {
                setProblem(s.message());
                break;
            }
        }
    }
}

}  // namespace handscan::xsens
