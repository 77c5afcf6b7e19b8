// A thin interface over GPIO character-device lines (libgpiod 1.6 semantics): inputs requested
// for both-edge events, outputs with a value. Levels are logical (active-low applied by the
// request, as libgpiod does). Implementations: libgpiod (gpiod_lines.cpp, the only file that
// includes <gpiod.h>) and a fake line layer for tests (fake_gpio_chip.hpp).
#pragma once

#include <memory>
#include <span>
#include <string>
#include <vector>

#include "handscan/core/samples.hpp"
#include "handscan/core/status.hpp"

namespace handscan::transport {

enum class Bias : std::uint8_t { kAsIs, kDisable, kPullUp, kPullDown };

struct InputRequest {
    bool active_low = true;  // buttons to ground with a pull-up read "pressed" as 1
    Bias bias = Bias::kPullUp;
};

class GpioInput {
public:
    virtual ~GpioInput() = default;
    // One kernel edge event (timestamp already on the host CLOCK_MONOTONIC); call after
    // GpioChip::waitAny() said this line is ready.
    [[nodiscard]] virtual Result<GpioEdge> readEvent() = 0;
    [[nodiscard]] virtual Result<bool> value() = 0;
    virtual unsigned offset() const = 0;
};

class GpioOutput {
public:
    virtual ~GpioOutput() = default;
    [[nodiscard]] virtual Status set(bool on) = 0;
    virtual unsigned offset() const = 0;
};

class GpioChip {
public:
    virtual ~GpioChip() = default;
    [[nodiscard]] virtual Result<std::unique_ptr<GpioInput>> requestInput(
        unsigned offset, const InputRequest& request) = 0;
    [[nodiscard]] virtual Result<std::unique_ptr<GpioOutput>> requestOutput(unsigned offset,
                                                                            bool active_low,
                                                                            bool initial_on) = 0;
    // Waits at most `timeout` for events; returns the indices of `inputs` that have one.
    [[nodiscard]] virtual Result<std::vector<std::size_t>> waitAny(
        std::span<GpioInput* const> inputs, TimeNs timeout) = 0;
    virtual TimeNs now() const = 0;  // the clock the event timestamps are on
    virtual std::string describe() const = 0;
};

// libgpiod 1.6: `name` as gpiod_chip_open_lookup takes it ("gpiochip0", "/dev/gpiochip0", a label).
Result<std::unique_ptr<GpioChip>> openGpiodChip(const std::string& name,
                                                const std::string& consumer = "handscan");

// Kernel line-event timestamps are CLOCK_MONOTONIC from Linux 5.7 on and CLOCK_REALTIME before
// (libgpiod 1.6 cannot choose). Given both clocks read just after the event, decide which one
// `event_ns` is on (the nearer) and return it on CLOCK_MONOTONIC.
TimeNs eventTimeToMonotonic(TimeNs event_ns, TimeNs monotonic_now, TimeNs realtime_now);

}  // namespace handscan::transport
