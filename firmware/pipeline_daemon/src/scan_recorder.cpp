#include "handscan/pipeline_daemon/scan_recorder.hpp"

#include <sys/statvfs.h>

#include <algorithm>
#include <filesystem>
#include <thread>
#include <vector>

#include "handscan/core/log.hpp"

namespace handscan::pipeline_daemon {
namespace {

namespace fs = std::filesystem;

std::string mib(std::uint64_t bytes) { return std::to_string(bytes >> 20) + " MiB"; }

std::uint64_t freeBytes(const std::string& dir) {
    struct statvfs vfs {};
    if (::statvfs(dir.c_str(), &vfs) != 0) return 0;
    return static_cast<std::uint64_t>(vfs.f_bavail) * vfs.f_frsize;
}

}  // namespace

void SwitchableTap::onRaw(TimeNs t_host_rx, std::span<const std::uint8_t> bytes) {
    if (capturing_.load(std::memory_order_relaxed)) {
        std::lock_guard lock(preamble_mutex_);
        if (preamble_bytes_ + bytes.size() <= kMaxPreambleBytes) {
            preamble_.emplace_back(t_host_rx,
                                   std::vector<std::uint8_t>(bytes.begin(), bytes.end()));
            preamble_bytes_ += bytes.size();
        }
    }
    // busy_ is raised before the target is read: detach() waits for every call that may still
    // hold the old target (sequentially consistent, so either the call sees nullptr or detach
    // sees the count).
    busy_.fetch_add(1, std::memory_order_seq_cst);
    if (RawTap* t = target_.load(std::memory_order_seq_cst)) t->onRaw(t_host_rx, bytes);
    busy_.fetch_sub(1, std::memory_order_release);
}

void SwitchableTap::attach(RawTap* target) {
    {
        // The target is not reachable by the driver yet: this thread is its only producer until
        // the store below publishes it.
        std::lock_guard lock(preamble_mutex_);
        for (const auto& [t, bytes] : preamble_) target->onRaw(t, bytes);
    }
    target_.store(target, std::memory_order_seq_cst);
}

void SwitchableTap::beginPreamble() {
    std::lock_guard lock(preamble_mutex_);
    preamble_.clear();
    preamble_bytes_ = 0;
    capturing_.store(true, std::memory_order_relaxed);
}

void SwitchableTap::endPreamble() { capturing_.store(false, std::memory_order_relaxed); }

void SwitchableTap::detach() {
    target_.store(nullptr, std::memory_order_seq_cst);
    while (busy_.load(std::memory_order_seq_cst) != 0) std::this_thread::yield();
}

ScanRecorder::~ScanRecorder() {
    if (auto r = stop(); !r.isOk()) log().error("{}", r.status().message());
}

std::string ScanRecorder::start(const std::string& scan_dir) {
    if (!options_.enabled) return "raw streams not recorded (storage.record_scans: false)";
    if (recorder_) return "already recording to " + path_;
    const std::uint64_t free = freeBytes(scan_dir);
    if (free < options_.min_free_bytes) {
        return "raw streams not recorded: " + mib(free) + " free, the recording keeps " +
               mib(options_.min_free_bytes) + " for the journal (storage.min_free_gib)";
    }
    fs::path path = fs::path(scan_dir) / "raw.mcap";
    for (int i = 2; fs::exists(path); ++i)
        path = fs::path(scan_dir) / ("raw-" + std::to_string(i) + ".mcap");
    auto recorder = recording::Recorder::create(path.string());
    if (!recorder.isOk()) return "raw streams not recorded: " + recorder.status().message();
    const struct {
        const recording::ChannelSpec& spec;
        SwitchableTap& tap;
    } channels[] = {{recording::channels::kHokuyoRaw, hokuyo_},
                    {recording::channels::kXsensRaw, xsens_},
                    {recording::channels::kMotorCan, motor_}};
    std::vector<std::pair<SwitchableTap*, RawTap*>> taps;
    for (const auto& c : channels) {
        auto tap = (*recorder)->addChannel(c.spec);
        if (!tap.isOk()) return "raw streams not recorded: " + tap.status().message();
        taps.emplace_back(&c.tap, *tap);
    }
    if (Status s = (*recorder)->start(); !s.isOk())
        return "raw streams not recorded: " + s.message();
    recorder_ = std::move(*recorder);
    path_ = path.string();
    for (auto& [from, to] : taps) from->attach(to);
    return "recording the raw streams to " + path.filename().string();
}

Result<std::string> ScanRecorder::stop() {
    if (!recorder_) return std::string();
    for (SwitchableTap* t : {&hokuyo_, &xsens_, &motor_}) t->detach();
    const Status s = recorder_->stop();
    std::uint64_t messages = 0, dropped = 0;
    for (const recording::ChannelCounters& c : recorder_->counters()) {
        messages += c.written;
        dropped += c.dropped;
    }
    recorder_.reset();
    if (!s.isOk()) return Status(s.code(), "recording " + path_ + ": " + s.message());
    return path_ + ": " + std::to_string(messages) + " messages, " + std::to_string(dropped) +
           " dropped";
}

void ScanRecorder::checkSpace() {
    if (!recorder_) return;
    const TimeNs now = monotonicNow();
    if (now - last_check_ < kNsPerSec) return;
    last_check_ = now;
    const std::uint64_t free = freeBytes(fs::path(path_).parent_path().string());
    if (free >= options_.min_free_bytes) return;
    auto r = stop();
    log().warn(
        "raw recording stopped: {} free, {} kept for the journal (storage.min_free_gib); "
        "the scan goes on{}",
        mib(free), mib(options_.min_free_bytes),
        r.isOk() ? "; " + *r : "; " + r.status().message());
}

std::string scanRecording(const std::string& scan_dir) {
    std::error_code ec;
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(scan_dir, ec)) {
        const std::string name = e.path().filename().string();
        if (name.rfind("raw", 0) == 0 && e.path().extension() == ".mcap") files.push_back(e.path());
    }
    if (files.empty()) return {};
    // raw.mcap, raw-2.mcap (a resumed scan), ...: the longest stretch walked.
    std::sort(files.begin(), files.end(), [](const fs::path& a, const fs::path& b) {
        std::error_code e;
        return fs::file_size(a, e) < fs::file_size(b, e);
    });
    return files.back().string();
}

}  // namespace handscan::pipeline_daemon
