// A fake GPIO line layer on a virtual clock: scripted input edges (bounces included), output
// writes recorded with their time. waitAny() advances the clock to the next scripted edge or by
// the timeout, like poll() on the line event fds would.
#pragma once

#include <deque>
#include <map>
#include <set>
#include <vector>

#include "handscan/gpio/gpio_lines.hpp"

namespace handscan::gpio {

class FakeGpioChip final : public GpioChip {
public:
    explicit FakeGpioChip(unsigned num_lines = 32, TimeNs start = 0)
        : num_lines_(num_lines), now_(start) {}

    // An edge on input `line` at time t (logical level after it: rising = 1).
    void inject(unsigned line, TimeNs t, GpioEdgeType edge);
    // A press with contact bounce: `bounces` extra edge pairs every `bounce_period` after t.
    void injectBouncyPress(unsigned line, TimeNs t, int bounces, TimeNs bounce_period, bool press);

    struct Write {
        TimeNs t;
        unsigned line;
        bool on;
    };
    const std::vector<Write>& writes() const { return writes_; }
    bool outputLevel(unsigned line) const;
    void advanceTo(TimeNs t) { now_ = t > now_ ? t : now_; }

    Result<std::unique_ptr<GpioInput>> requestInput(unsigned offset,
                                                    const InputRequest& request) override;
    Result<std::unique_ptr<GpioOutput>> requestOutput(unsigned offset, bool active_low,
                                                      bool initial_on) override;
    Result<std::vector<std::size_t>> waitAny(std::span<GpioInput* const> inputs,
                                             TimeNs timeout) override;
    TimeNs now() const override { return now_; }
    std::string describe() const override { return "fake gpiochip"; }

    // Used by the fake lines.
    Result<GpioEdge> pop(unsigned line);
    bool level(unsigned line) const;
    void write(unsigned line, bool on) {
        writes_.push_back({now_, line, on});
        outputs_[line] = on;
    }
    void release(unsigned line) { requested_.erase(line); }

private:
    unsigned num_lines_;
    TimeNs now_;
    std::map<unsigned, std::deque<GpioEdge>> events_;
    std::map<unsigned, bool> levels_;
    std::map<unsigned, bool> outputs_;
    std::set<unsigned> requested_;
    std::vector<Write> writes_;
};

}  // namespace handscan::gpio
