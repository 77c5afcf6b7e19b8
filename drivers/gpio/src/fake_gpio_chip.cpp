#include "handscan/gpio/fake_gpio_chip.hpp"

#include <algorithm>

namespace handscan::gpio {
namespace {

class FakeInput final : public GpioInput {
public:
    FakeInput(FakeGpioChip& chip, unsigned offset) : chip_(chip), offset_(offset) {}
    ~FakeInput() override { chip_.release(offset_); }
    Result<GpioEdge> readEvent() override { return chip_.pop(offset_); }
    Result<bool> value() override { return chip_.level(offset_); }
    unsigned offset() const override { return offset_; }

private:
    FakeGpioChip& chip_;
    unsigned offset_;
};

class FakeOutput final : public GpioOutput {
public:
    FakeOutput(FakeGpioChip& chip, unsigned offset) : chip_(chip), offset_(offset) {}
    ~FakeOutput() override { chip_.release(offset_); }
    Status set(bool on) override {
        chip_.write(offset_, on);
        return Status::ok();
    }
    unsigned offset() const override { return offset_; }

private:
    FakeGpioChip& chip_;
    unsigned offset_;
};

}  // namespace

void FakeGpioChip::inject(unsigned line, TimeNs t, GpioEdgeType edge) {
    auto& q = events_[line];
    GpioEdge e{t, line, edge};
    q.insert(std::upper_bound(q.begin(), q.end(), t,
                              [](TimeNs a, const GpioEdge& b) { return a < b.t_host; }),
             e);
}

void FakeGpioChip::injectBouncyPress(unsigned line, TimeNs t, int bounces, TimeNs period,
                                     bool press) {
    const GpioEdgeType to = press ? GpioEdgeType::kRising : GpioEdgeType::kFalling;
    const GpioEdgeType back = press ? GpioEdgeType::kFalling : GpioEdgeType::kRising;
    inject(line, t, to);
    for (TimeNs i = 1; i <= bounces; ++i) {
        inject(line, t + (2 * i - 1) * period, back);
        inject(line, t + 2 * i * period, to);
    }
}

bool FakeGpioChip::outputLevel(unsigned line) const {
    auto it = outputs_.find(line);
    return it != outputs_.end() && it->second;
}

Result<std::unique_ptr<GpioInput>> FakeGpioChip::requestInput(unsigned offset,
                                                              const InputRequest&) {
    if (offset >= num_lines_)
        return Status(StatusCode::kNotFound, describe() + ": no line " + std::to_string(offset));
    if (!requested_.insert(offset).second)
        return Status(StatusCode::kDeviceError,
                      describe() + " line " + std::to_string(offset) + ": busy");
    return std::unique_ptr<GpioInput>(new FakeInput(*this, offset));
}

Result<std::unique_ptr<GpioOutput>> FakeGpioChip::requestOutput(unsigned offset, bool,
                                                                bool initial_on) {
    if (offset >= num_lines_)
        return Status(StatusCode::kNotFound, describe() + ": no line " + std::to_string(offset));
    if (!requested_.insert(offset).second)
        return Status(StatusCode::kDeviceError,
                      describe() + " line " + std::to_string(offset) + ": busy");
    outputs_[offset] = initial_on;
    return std::unique_ptr<GpioOutput>(new FakeOutput(*this, offset));
}

Result<std::vector<std::size_t>> FakeGpioChip::waitAny(std::span<GpioInput* const> inputs,
                                                       TimeNs timeout) {
    const TimeNs deadline = now_ + (timeout > 0 ? timeout : 0);
    TimeNs first = deadline + 1;
    for (GpioInput* in : inputs) {
        auto it = events_.find(in->offset());
        if (it != events_.end() && !it->second.empty())
            first = std::min(first, it->second.front().t_host);
    }
    if (first > deadline) {
        now_ = deadline;
        return std::vector<std::size_t>{};
    }
    now_ = std::max(now_, first);
    std::vector<std::size_t> ready;
    for (std::size_t i = 0; i < inputs.size(); ++i) {
        auto it = events_.find(inputs[i]->offset());
        if (it != events_.end() && !it->second.empty() && it->second.front().t_host <= now_)
            ready.push_back(i);
    }
    return ready;
}

Result<GpioEdge> FakeGpioChip::pop(unsigned line) {
    auto& q = events_[line];
    if (q.empty() || q.front().t_host > now_)
        return Status(StatusCode::kTimeout, "no event on line " + std::to_string(line));
    GpioEdge e = q.front();
    q.pop_front();
    levels_[line] = e.edge == GpioEdgeType::kRising;
    return e;
}

bool FakeGpioChip::level(unsigned line) const {
    auto it = levels_.find(line);
    return it != levels_.end() && it->second;
}

}  // namespace handscan::gpio
