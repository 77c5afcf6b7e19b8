#include "handscan/viz/journal_viz.hpp"

#include <cmath>
#include <filesystem>
#include <vector>

#include "handscan/journal/journal_reader.hpp"
#include "handscan/recording/mcap_reader.hpp"
#include "handscan/viz/recorded_extras.hpp"

namespace handscan::viz {
namespace {

PoseEstimate poseOf(const journal::TrajectoryPose& p, TimeNs t) {
    PoseEstimate e;
    e.t_host = t;
    e.T_world_body.linear() = Eigen::Quaterniond(p.qw, p.qx, p.qy, p.qz).normalized().matrix();
    e.T_world_body.translation() = Eigen::Vector3d(p.x, p.y, p.z);
    return e;
}

// The recording's extras, pulled in log-time order up to a time (none without a recording).
class RecordingExtrasFeed {
public:
    Status open(const std::string& path) {
        if (path.empty()) return Status::ok();
        auto reader = recording::McapReader::open(path);
        if (!reader.isOk()) return reader.status();
        reader_ = std::move(*reader);
        recording::ReadOptions o;
        o.topics = RecordedExtras::topics(true);
        it_.emplace(reader_->messages(o));
        have_ = it_->next(msg_);
        return it_->status();
    }
    // Every message up to `t` into `writer`.
    Status until(TimeNs t, VizWriter& writer, std::uint64_t& count) {
        while (have_ && msg_.log_time <= t) {
            if (Status s = extras_.add(msg_, writer); !s.isOk()) return s;
            ++count;
            have_ = it_->next(msg_);
        }
        return it_ ? it_->status() : Status::ok();
    }

private:
    std::unique_ptr<recording::McapReader> reader_;
    std::optional<recording::MessageIterator> it_;
    recording::RecordedMessage msg_;
    bool have_ = false;
    RecordedExtras extras_{true};
};

}  // namespace

Result<JournalVizReport> writeJournalViz(const JournalVizOptions& o,
                                         const Calibration& calibration) {
    std::string journal_path = o.journal;
    if (std::filesystem::is_directory(journal_path))
        journal_path = (std::filesystem::path(journal_path) / "journal.hsj").string();
    auto reader = journal::JournalReader::open(journal_path);
    if (!reader.isOk()) return reader.status();
    const auto& trajectory = reader->summary().trajectory;
    auto writer = VizWriter::create(o.out, calibration, o.config);
    if (!writer.isOk()) return writer.status();
    VizWriter& viz = **writer;
    RecordingExtrasFeed extras;
    if (Status s = extras.open(o.recording); !s.isOk()) return s;

    JournalVizReport r;
    // The journal's scan-clock seconds on the viz file's clock (the recording's, for hil).
    const auto timeOf = [&](double t_s) {
        return static_cast<TimeNs>(std::llround(t_s * 1e9)) - o.journal_minus_recording_ns;
    };
    std::size_t next_pose = 0;
    // Everything due by `t`: the recording's frames and ground truth, then the poses.
    const auto upTo = [&](TimeNs t) -> Status {
        for (; next_pose < trajectory.size() && timeOf(trajectory[next_pose].t_s) <= t;
             ++next_pose) {
            const TimeNs tp = timeOf(trajectory[next_pose].t_s);
            if (Status s = extras.until(tp, viz, r.recorded_messages); !s.isOk()) return s;
            if (Status s = viz.pose(poseOf(trajectory[next_pose], tp)); !s.isOk()) return s;
            ++r.poses;
        }
        return extras.until(t, viz, r.recorded_messages);
    };
    std::vector<journal::MapPoint> window;
    double window_start = 0.0;
    Status failure;
    const auto flush = [&]() -> Status {
        if (window.empty()) return Status::ok();
        const TimeNs t = timeOf(window.back().t_s);
        if (Status s = upTo(t); !s.isOk()) return s;
        if (Status s = viz.mapPoints(t, window); !s.isOk()) return s;
        r.points += window.size();
        ++r.windows;
        window.clear();
        return Status::ok();
    };
    Status read = reader->forEachPoints([&](std::span<const journal::MapPoint> points) {
        for (const journal::MapPoint& p : points) {
            if (!failure.isOk()) return;
            if (!window.empty() && p.t_s - window_start >= o.window_s) failure = flush();
            if (window.empty()) window_start = p.t_s;
            window.push_back(p);
        }
    });
    if (!read.isOk()) return read;
    if (!failure.isOk()) return failure;
    if (Status s = flush(); !s.isOk()) return s;
    if (Status s = upTo(std::numeric_limits<TimeNs>::max()); !s.isOk()) return s;
    if (Status s = viz.close(); !s.isOk()) return s;
    r.bytes = viz.bytesWritten();
    r.messages = viz.messageCount();
    return r;
}

}  // namespace handscan::viz
