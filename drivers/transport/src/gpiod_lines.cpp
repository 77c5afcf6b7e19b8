// The GPIO transport: libgpiod 1.6 (C API). The only file that includes <gpiod.h>.
#include <gpiod.h>
#include <poll.h>
#include <time.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

#include "handscan/transport/gpio_lines.hpp"

namespace handscan::transport {
namespace {

std::string err(const std::string& what) { return what + ": " + std::strerror(errno); }

TimeNs clockNs(clockid_t id) {
    timespec ts{};
    clock_gettime(id, &ts);
    return static_cast<TimeNs>(ts.tv_sec) * kNsPerSec + ts.tv_nsec;
}

int biasFlags(Bias b) {
    switch (b) {
        case Bias::kDisable:
            return GPIOD_LINE_REQUEST_FLAG_BIAS_DISABLE;
        case Bias::kPullUp:
            return GPIOD_LINE_REQUEST_FLAG_BIAS_PULL_UP;
        case Bias::kPullDown:
            return GPIOD_LINE_REQUEST_FLAG_BIAS_PULL_DOWN;
        case Bias::kAsIs:
            break;
    }
    return 0;
}

class GpiodInput final : public GpioInput {
public:
    GpiodInput(gpiod_line* line, unsigned offset, std::string where)
        : line_(line), offset_(offset), where_(std::move(where)) {}
    ~GpiodInput() override { gpiod_line_release(line_); }
    Result<GpioEdge> readEvent() override {
        gpiod_line_event ev{};
        if (gpiod_line_event_read(line_, &ev) < 0)
            return Status(StatusCode::kIoError, err(where_ + ": gpiod_line_event_read"));
        const TimeNs raw = static_cast<TimeNs>(ev.ts.tv_sec) * kNsPerSec + ev.ts.tv_nsec;
        GpioEdge e;
        e.t_host = eventTimeToMonotonic(raw, clockNs(CLOCK_MONOTONIC), clockNs(CLOCK_REALTIME));
        e.line = offset_;
        e.edge = ev.event_type == GPIOD_LINE_EVENT_RISING_EDGE ? GpioEdgeType::kRising
                                                               : GpioEdgeType::kFalling;
        return e;
    }
    Result<bool> value() override {
        const int v = gpiod_line_get_value(line_);
        if (v < 0) return Status(StatusCode::kIoError, err(where_ + ": gpiod_line_get_value"));
        return v == 1;
    }
    unsigned offset() const override { return offset_; }
    int fd() const { return gpiod_line_event_get_fd(line_); }

private:
    gpiod_line* line_;
    unsigned offset_;
    std::string where_;
};

class GpiodOutput final : public GpioOutput {
public:
    GpiodOutput(gpiod_line* line, unsigned offset, std::string where)
        : line_(line), offset_(offset), where_(std::move(where)) {}
    ~GpiodOutput() override { gpiod_line_release(line_); }
    Status set(bool on) override {
        if (gpiod_line_set_value(line_, on ? 1 : 0) < 0)
            return {StatusCode::kIoError, err(where_ + ": gpiod_line_set_value")};
        return Status::ok();
    }
    unsigned offset() const override { return offset_; }

private:
    gpiod_line* line_;
    unsigned offset_;
    std::string where_;
};

class GpiodChip final : public GpioChip {
public:
    GpiodChip(gpiod_chip* chip, std::string name, std::string consumer)
        : chip_(chip), name_(std::move(name)), consumer_(std::move(consumer)) {}
    ~GpiodChip() override { gpiod_chip_close(chip_); }

    Result<std::unique_ptr<GpioInput>> requestInput(unsigned offset,
                                                    const InputRequest& r) override {
        gpiod_line* line = gpiod_chip_get_line(chip_, offset);
        const std::string where = describe() + " line " + std::to_string(offset);
        if (line == nullptr)
            return Status(StatusCode::kNotFound, err(where + ": gpiod_chip_get_line"));
        const int flags =
            biasFlags(r.bias) | (r.active_low ? GPIOD_LINE_REQUEST_FLAG_ACTIVE_LOW : 0);
        if (gpiod_line_request_both_edges_events_flags(line, consumer_.c_str(), flags) < 0) {
            return Status(StatusCode::kDeviceError,
                          err(where + ": request for edge events (line busy? see gpioinfo)"));
        }
        return std::unique_ptr<GpioInput>(new GpiodInput(line, offset, where));
    }

    Result<std::unique_ptr<GpioOutput>> requestOutput(unsigned offset, bool active_low,
                                                      bool initial_on) override {
        gpiod_line* line = gpiod_chip_get_line(chip_, offset);
        const std::string where = describe() + " line " + std::to_string(offset);
        if (line == nullptr)
            return Status(StatusCode::kNotFound, err(where + ": gpiod_chip_get_line"));
        if (gpiod_line_request_output_flags(line, consumer_.c_str(),
                                            active_low ? GPIOD_LINE_REQUEST_FLAG_ACTIVE_LOW : 0,
                                            initial_on ? 1 : 0) < 0) {
            return Status(StatusCode::kDeviceError,
                          err(where + ": request as output (line busy? see gpioinfo)"));
        }
        return std::unique_ptr<GpioOutput>(new GpiodOutput(line, offset, where));
    }

    Result<std::vector<std::size_t>> waitAny(std::span<GpioInput* const> inputs,
                                             TimeNs timeout) override {
        std::vector<pollfd> fds;
        for (GpioInput* in : inputs)
            fds.push_back({static_cast<GpiodInput*>(in)->fd(), POLLIN | POLLPRI, 0});
        const int ms = timeout <= 0 ? 0 : static_cast<int>((timeout + kNsPerMs - 1) / kNsPerMs);
        const int n = ::poll(fds.data(), fds.size(), ms);
        if (n < 0) {
            if (errno == EINTR) return std::vector<std::size_t>{};
            return Status(StatusCode::kIoError, err(describe() + ": poll"));
        }
        std::vector<std::size_t> ready;
        for (std::size_t i = 0; i < fds.size(); ++i) {
            if (fds[i].revents & (POLLERR | POLLNVAL))
                return Status(StatusCode::kDisconnected, describe() + ": line event fd failed");
            if (fds[i].revents & (POLLIN | POLLPRI)) ready.push_back(i);
        }
        return ready;
    }

    TimeNs now() const override { return clockNs(CLOCK_MONOTONIC); }
    std::string describe() const override { return "gpio " + name_; }

private:
    gpiod_chip* chip_;
    std::string name_;
    std::string consumer_;
};

}  // namespace

Result<std::unique_ptr<GpioChip>> openGpiodChip(const std::string& name,
                                                const std::string& consumer) {
    gpiod_chip* chip = gpiod_chip_open_lookup(name.c_str());
    if (chip == nullptr) {
        return Status(StatusCode::kNotFound,
                      err("gpio: cannot open chip '" + name + "' (gpiodetect lists the chips)"));
    }
    return std::unique_ptr<GpioChip>(new GpiodChip(chip, name, consumer));
}

}  // namespace handscan::transport
