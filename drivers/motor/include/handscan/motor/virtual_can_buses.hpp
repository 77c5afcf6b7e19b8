// CAN buses without a kernel, both running on a virtual clock so the motor state machine can be
// driven faster than real time and deterministically:
//   EmulatedCanBus  - emulated nodes (node_emulators.hpp) on the wire; can write every frame as a
//                     candump -l line (that is how the simulator produces /motor/can traffic).
//   CandumpLogBus   - replays a candump log (-l/-L or default format with -t) in the log's own
//                     time and writes what the master sends as candump -l lines. Lines that do
//                     not parse are counted and skipped (named in lastError()), the rest plays.
// receive(timeout) delivers the next frame due within `timeout` of now() and advances now() to
// its time, or advances now() by `timeout` and returns kTimeout.
#pragma once

#include <istream>
#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "handscan/motor/candump_format.hpp"
#include "handscan/motor/node_emulators.hpp"
#include "handscan/transport/can_bus.hpp"

namespace handscan::motor {

class EmulatedCanBus final : public transport::CanBus {
public:
    explicit EmulatedCanBus(TimeNs start_time = 0, std::string interface = "can0");
    void addNode(CanNodeEmulator* node) { nodes_.push_back(node); }
    // Every frame on the wire (both directions) as a candump -l line, when set.
    void setRecorder(std::ostream* out) { recorder_ = out; }
    TimeNs now() const { return now_; }
    void advanceTo(TimeNs t) { now_ = t > now_ ? t : now_; }
    // Makes the bus fail like an interface that went down.
    void setDown(bool down) { down_ = down; }

    Status open() override;
    void close() override { open_ = false; }
    bool isOpen() const override { return open_; }
    Status setFilters(std::span<const CanFilter> filters) override;
    Result<TimedCanFrame> receive(TimeNs timeout) override;
    Status send(const CanFrame& frame) override;
    std::string describe() const override { return "emulated " + interface_; }
    const std::vector<TimedCanFrame>& sent() const { return sent_; }

private:
    void record(TimeNs t, const CanFrame& f);

    TimeNs now_;
    std::string interface_;
    std::vector<CanNodeEmulator*> nodes_;
    std::vector<CanFilter> filters_;
    std::vector<TimedCanFrame> sent_;
    std::ostream* recorder_ = nullptr;
    bool open_ = true;
    bool down_ = false;
};

class CandumpLogBus final : public transport::CanBus {
public:
    // `in`: the log to play; `out` (may be null): where sent frames go as candump -l lines.
    CandumpLogBus(std::unique_ptr<std::istream> in, std::ostream* out, std::string name);
    static Result<std::unique_ptr<CandumpLogBus>> openFile(const std::string& path,
                                                           std::ostream* out = nullptr);

    TimeNs now() const { return now_; }
    // Drops the frames logged before `t` (frames sent while nobody listened are gone, as on a
    // bus); the clock moves to `t` at least.
    void skipBefore(TimeNs t);
    std::uint64_t badLines() const { return bad_lines_; }
    const std::string& lastError() const { return last_error_; }

    Status open() override { return Status::ok(); }
    void close() override { open_ = false; }
    bool isOpen() const override { return open_; }
    Status setFilters(std::span<const CanFilter> filters) override;
    Result<TimedCanFrame> receive(TimeNs timeout) override;
    Status send(const CanFrame& frame) override;
    std::string describe() const override { return "candump log " + name_; }

private:
    bool fillNext();  // reads ahead one valid record into next_; false at end of file

    std::unique_ptr<std::istream> in_;
    std::ostream* out_;
    std::string name_;
    std::vector<CanFilter> filters_;
    std::optional<CandumpRecord> next_;
    std::uint64_t line_no_ = 0;
    std::uint64_t bad_lines_ = 0;
    std::string last_error_;
    std::string interface_ = "can0";
    TimeNs now_ = 0;
    bool started_ = false;
    bool open_ = true;
};

}  // namespace handscan::motor
