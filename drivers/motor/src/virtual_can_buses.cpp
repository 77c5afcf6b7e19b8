#include "handscan/motor/virtual_can_buses.hpp"

#include <algorithm>
#include <fstream>

namespace handscan::motor {

EmulatedCanBus::EmulatedCanBus(TimeNs start_time, std::string interface)
    : now_(start_time), interface_(std::move(interface)) {}

Status EmulatedCanBus::open() {
    open_ = true;
    return Status::ok();
}

Status EmulatedCanBus::setFilters(std::span<const CanFilter> filters) {
    if (filters.size() > kCanMaxFilters)
        return {StatusCode::kInvalidArgument, "more than 512 CAN filters"};
    filters_.assign(filters.begin(), filters.end());
    return Status::ok();
}

void EmulatedCanBus::record(TimeNs t, const CanFrame& f) {
    if (recorder_ == nullptr) return;
    CandumpRecord rec;
    rec.setTimeNs(t);
    rec.interface = interface_;
    rec.frame = f;
    *recorder_ << formatCandumpLogLine(rec) << '\n';
}

Result<TimedCanFrame> EmulatedCanBus::receive(TimeNs timeout) {
    if (!open_ || down_) return Status(StatusCode::kDisconnected, describe() + " is down");
    const TimeNs deadline = now_ + (timeout > 0 ? timeout : 0);
    for (;;) {
        CanNodeEmulator* first = nullptr;
        for (CanNodeEmulator* n : nodes_) {
            if (n->nextTime() <= deadline &&
                (first == nullptr || n->nextTime() < first->nextTime()))
                first = n;
        }
        if (first == nullptr) {
            now_ = deadline;
            return Status(StatusCode::kTimeout, "no frame");
        }
        TimedCanFrame f = first->pop();
        if (f.t_host > now_) now_ = f.t_host;
        f.t_host = now_;
        record(now_, f.frame);
        if (canFilterMatches(filters_, f.frame)) return f;
    }
}

Status EmulatedCanBus::send(const CanFrame& frame) {
    if (!open_ || down_) return {StatusCode::kDisconnected, describe() + " is down"};
    record(now_, frame);
    sent_.push_back({now_, frame});
    for (CanNodeEmulator* n : nodes_) n->receive(now_, frame);
    return Status::ok();
}

CandumpLogBus::CandumpLogBus(std::unique_ptr<std::istream> in, std::ostream* out, std::string name)
    : in_(std::move(in)), out_(out), name_(std::move(name)) {
    // The log's clock starts at its first frame, so that now() means something before the first
    // receive() (PacedCanBus anchors the host clock to it).
    if (fillNext()) {
        now_ = next_->timeNs();
        started_ = true;
        interface_ = next_->interface;
    }
}

Result<std::unique_ptr<CandumpLogBus>> CandumpLogBus::openFile(const std::string& path,
                                                               std::ostream* out) {
    auto in = std::make_unique<std::ifstream>(path);
    if (!*in) return Status(StatusCode::kNotFound, path + ": cannot open candump log for reading");
    return std::make_unique<CandumpLogBus>(std::move(in), out, path);
}

void CandumpLogBus::skipBefore(TimeNs t) {
    while (fillNext() && next_->timeNs() < t) next_.reset();
    now_ = std::max(now_, t);
    started_ = true;
}

Status CandumpLogBus::setFilters(std::span<const CanFilter> filters) {
    if (filters.size() > kCanMaxFilters)
        return {StatusCode::kInvalidArgument, "more than 512 CAN filters"};
    filters_.assign(filters.begin(), filters.end());
    return Status::ok();
}

bool CandumpLogBus::fillNext() {
    std::string line;
    while (!next_ && std::getline(*in_, line)) {
        ++line_no_;
        if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
        auto rec = parseCandumpAnyLine(line);
        if (!rec || !rec->has_time) {
            ++bad_lines_;
            last_error_ =
                name_ + ":" + std::to_string(line_no_) + ": " +
                (rec ? std::string("line has no timestamp; record with candump -l or -t a")
                     : rec.status().message());
            continue;
        }
        next_ = std::move(*rec);
    }
    return next_.has_value();
}

Result<TimedCanFrame> CandumpLogBus::receive(TimeNs timeout) {
    if (!open_) return Status(StatusCode::kDisconnected, describe() + " is closed");
    for (;;) {
        if (!fillNext())
            return Status(StatusCode::kDisconnected,
                          describe() + ": end of log after line " + std::to_string(line_no_));
        const TimeNs t = next_->timeNs();
        if (!started_) {
            now_ = t;  // the log's clock starts at its first frame
            started_ = true;
            interface_ = next_->interface;
        }
        if (t > now_ + timeout) {
            now_ += timeout;
            return Status(StatusCode::kTimeout, "no frame");
        }
        TimedCanFrame f{t > now_ ? t : now_, next_->frame};
        now_ = f.t_host;
        next_.reset();
        if (canFilterMatches(filters_, f.frame)) return f;
    }
}

Status CandumpLogBus::send(const CanFrame& frame) {
    if (!open_) return {StatusCode::kDisconnected, describe() + " is closed"};
    if (out_ == nullptr) return Status::ok();
    CandumpRecord rec;
    rec.setTimeNs(now_);
    rec.interface = interface_;
    rec.frame = frame;
    *out_ << formatCandumpLogLine(rec) << '\n';
    if (!*out_) return {StatusCode::kIoError, describe() + ": writing sent frames failed"};
    return Status::ok();
}

}  // namespace handscan::motor
