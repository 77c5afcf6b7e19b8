#include "handscan/report/scan_facts.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

namespace handscan::report {
namespace {

constexpr double kDropoutS = 1.0;  // a sensor silent this long counts as a dropout
constexpr std::size_t kMaxBins = 600;

// Poses more than a dropout apart leave a gap; the walk's length skips the jump across it.
void trajectoryFacts(std::span<const journal::TrajectoryPose> tr, double t0, ScanFacts& f) {
    for (std::size_t k = 1; k < tr.size(); ++k) {
        const double dt = tr[k].t_s - tr[k - 1].t_s;
        f.distance_m +=
            std::hypot(tr[k].x - tr[k - 1].x, tr[k].y - tr[k - 1].y, tr[k].z - tr[k - 1].z);
        if (dt > kDropoutS) f.pose_dropouts.push_back({tr[k - 1].t_s - t0, tr[k].t_s - t0, 0, {}});
    }
    if (tr.size() < 2) {
        f.loop_note = "no trajectory to close a loop";
        return;
    }
    const double gap = std::hypot(tr.back().x - tr.front().x, tr.back().y - tr.front().y,
                                  tr.back().z - tr.front().z);
    // A closed loop: the walker came back near the start after a real walk. The remaining
    // distance is the drift the pipeline accumulated plus how exactly the start was re-taken.
    const double near = std::max(2.0, 0.05 * f.distance_m);
    char note[200];
    if (f.distance_m >= 10.0 && gap <= near) {
        f.loop_gap_m = gap;
        std::snprintf(note, sizeof note,
                      "the walk ended %.3f m from where it started after %.1f m (%.2f %% of the "
                      "distance): drift plus how exactly the start was re-taken",
                      gap, f.distance_m, 100.0 * gap / f.distance_m);
    } else {
        std::snprintf(note, sizeof note,
                      "no closed loop: the walk ended %.1f m from its start after %.1f m", gap,
                      f.distance_m);
    }
    f.loop_note = note;
}

using nlohmann::json;

bool number(const json& j, const char* key) { return j.contains(key) && j[key].is_number(); }

std::string text(const json& j, const char* key) {
    return j.contains(key) && j[key].is_string() ? j[key].get<std::string>() : std::string();
}

// stats.json's [{begin_s, end_s (null: open at the end), reason?}] under block.key, from the
// scan's start.
std::vector<Interval> intervals(const json& stats, const char* block, const char* key, double t0,
                                double t_end) {
    std::vector<Interval> out;
    if (!stats.contains(block) || !stats[block].is_object()) return out;
    const json& list = stats[block].contains(key) ? stats[block][key] : json();
    if (!list.is_array()) return out;
    for (const json& i : list) {
        if (!number(i, "begin_s")) continue;
        Interval in;
        in.from_s = i["begin_s"].get<double>() - t0;
        in.to_s = (number(i, "end_s") ? i["end_s"].get<double>() : t_end) - t0;
        in.what = text(i, "reason");
        out.push_back(in);
    }
    return out;
}

// Consecutive degenerate sweeps make one interval, to the start of the next good sweep.
void degenerateIntervals(double t0, double t_end, ScanFacts& f) {
    const auto& sw = f.sweep_degenerate;
    for (std::size_t k = 0; k < sw.size(); ++k) {
        if (sw[k].second == 0) continue;
        Interval in{sw[k].first, sw[k].first, 0, {}};
        for (; k < sw.size() && sw[k].second > 0; ++k)
            in.directions = std::max(in.directions, sw[k].second);
        in.to_s = k < sw.size() ? sw[k].first : t_end - t0;
        f.degenerate.push_back(in);
    }
}

void sweepFacts(const std::string& stats_json, double t0, double t_end, ScanFacts& f) {
    if (stats_json.empty()) return;
    const auto stats = nlohmann::json::parse(stats_json, nullptr, false);
    if (!stats.is_object() || !stats.contains("per_sweep") || !stats["per_sweep"].is_array())
        return;
    f.have_sweep_stats = true;
    for (const auto& s : stats["per_sweep"]) {
        if (!number(s, "t_start_s") || !number(s, "degenerate_directions")) continue;
        const double t = s["t_start_s"].get<double>() - t0;
        const int degenerate = s["degenerate_directions"].get<int>();
        f.sweep_degenerate.emplace_back(t, degenerate);
        SweepModules m;
        m.t_s = t;
        // Older stats.json without the masks: the degenerate count is all there is.
        m.scan_mask = number(s, "solved_dof_mask")
                          ? static_cast<std::uint8_t>(s["solved_dof_mask"].get<int>() & 0x3F)
                          : static_cast<std::uint8_t>(degenerate == 0 ? 0x3F : 0);
        if (number(s, "vio_solved_dof_mask"))
            m.vio_mask = static_cast<std::uint8_t>(s["vio_solved_dof_mask"].get<int>() & 0x3F);
        const std::string tracking = text(s, "tracking");
        m.tracking = tracking == "lost" ? 'l' : tracking == "rejected" ? 'r' : 'o';
        f.sweep_modules.push_back(m);
    }
    f.tracking_lost = intervals(stats, "tracking", "lost_intervals", t0, t_end);
    if (stats.contains("vio") && stats["vio"].is_object()) {
        f.have_vio = true;
        f.vio_from_s = number(stats["vio"], "first_frame_s")
                           ? stats["vio"]["first_frame_s"].get<double>() - t0
                           : 0.0;
        f.vio_bypassed = intervals(stats, "vio", "bypassed", t0, t_end);
    }
    f.sweep_source = "stats.json";
    degenerateIntervals(t0, t_end, f);
}

// Consecutive sweeps for which `holds` is true make one interval, to the start of the next
// sweep for which it is not (or the scan's end); `what` of the interval's first sweep.
template <typename Holds, typename What>
std::vector<Interval> sweepIntervals(std::span<const journal::SweepRecord> sw, double t0,
                                     double t_end, Holds holds, What what) {
    std::vector<Interval> out;
    for (std::size_t k = 0; k < sw.size(); ++k) {
        if (!holds(sw[k])) continue;
        Interval in{sw[k].t_start_s - t0, 0.0, 0, what(sw[k])};
        while (k < sw.size() && holds(sw[k])) ++k;
        in.to_s = (k < sw.size() ? sw[k].t_start_s : t_end) - t0;
        out.push_back(in);
    }
    return out;
}

double rate(std::uint32_t count, double window_s) {
    return window_s > 0 ? static_cast<double>(count) / window_s : 0.0;
}

// The journal's per-sweep records: the daemon's and replay's scans alike.
void recordFacts(std::span<const journal::SweepRecord> sweeps, double t0, double t_end,
                 ScanFacts& f) {
    f.have_sweep_stats = true;
    f.sweep_source = "journal";
    for (const journal::SweepRecord& r : sweeps) {
        const double t = r.t_start_s - t0;
        f.sweep_degenerate.emplace_back(t, r.degenerateDirections());
        SweepModules m;
        m.t_s = t;
        m.scan_mask = r.solved_mask & 0x3F;
        m.vio_mask = r.vio_mask & 0x3F;
        m.tracking = r.tracking == journal::SweepTracking::kLost       ? 'l'
                     : r.tracking == journal::SweepTracking::kRejected ? 'r'
                                                                       : 'o';
        f.sweep_modules.push_back(m);
        const journal::DeviceCounts& d = r.devices;
        f.device_rates.push_back(
            {t, rate(d.laser_scans, d.window_s), rate(d.imu_samples, d.window_s),
             rate(d.encoder_samples, d.window_s), rate(d.colour_frames, d.window_s),
             rate(d.tracking_frames, d.window_s)});
    }
    using R = const journal::SweepRecord&;
    f.tracking_lost = sweepIntervals(
        sweeps, t0, t_end, [](R r) { return r.tracking == journal::SweepTracking::kLost; },
        [](R r) { return r.tracking_reason; });
    for (R r : sweeps) {
        if (r.vio == journal::SweepVio::kOff) continue;
        f.have_vio = true;
        f.vio_from_s = r.t_start_s - t0;
        break;
    }
    f.vio_bypassed = sweepIntervals(
        sweeps, t0, t_end, [](R r) { return r.vio == journal::SweepVio::kBypassed; },
        [](R) { return std::string(); });
    // A device that delivered somewhere but not in a sweep's window dropped out there.
    const struct {
        const char* name;
        std::uint32_t journal::DeviceCounts::*count;
    } devices[] = {{"laser", &journal::DeviceCounts::laser_scans},
                   {"IMU", &journal::DeviceCounts::imu_samples},
                   {"encoder", &journal::DeviceCounts::encoder_samples},
                   {"colour camera", &journal::DeviceCounts::colour_frames},
                   {"tracking camera", &journal::DeviceCounts::tracking_frames}};
    for (const auto& dev : devices) {
        const bool delivers =
            std::any_of(sweeps.begin(), sweeps.end(), [&](R r) { return r.devices.*dev.count; });
        if (!delivers) continue;
        for (Interval& in : sweepIntervals(
                 sweeps, t0, t_end,
                 [&](R r) { return r.devices.window_s > 0 && r.devices.*dev.count == 0; },
                 [&](R) { return std::string(dev.name); }))
            f.device_dropouts.push_back(in);
    }
    std::sort(f.device_dropouts.begin(), f.device_dropouts.end(),
              [](const Interval& a, const Interval& b) { return a.from_s < b.from_s; });
    degenerateIntervals(t0, t_end, f);
}

}  // namespace

void ScanFactsBuilder::add(std::span<const journal::MapPoint> points) {
    for (const journal::MapPoint& p : points) {
        if (!std::isfinite(p.t_s)) continue;
        const auto key = static_cast<std::int64_t>(std::floor(p.t_s));
        if (!last_ || key != last_key_) {  // points come in time order: one lookup per second
            last_ = &seconds_[key];
            last_key_ = key;
        }
        const bool coloured = journal::hasColour(p);
        ++last_->points;
        last_->coloured += coloured;
        coloured_ += coloured;
    }
    points_ += points.size();
}

ScanFacts ScanFactsBuilder::finish(std::span<const journal::TrajectoryPose> tr,
                                   std::span<const journal::SweepRecord> sweeps,
                                   const std::string& stats_json) const {
    ScanFacts f;
    f.points = points_;
    f.coloured = coloured_;
    double t0 = tr.empty() ? 0.0 : tr.front().t_s, t1 = tr.empty() ? 0.0 : tr.back().t_s;
    if (!seconds_.empty()) {
        t0 = tr.empty() ? double(seconds_.begin()->first)
                        : std::min(t0, double(seconds_.begin()->first));
        t1 = std::max(t1, double(seconds_.rbegin()->first + 1));
    }
    f.t0_s = t0;
    f.duration_s = std::max(0.0, t1 - t0);
    // Laser dropouts: whole seconds without a point between the first and the last.
    for (auto it = seconds_.begin(); it != seconds_.end(); ++it) {
        const auto next = std::next(it);
        if (next != seconds_.end() && next->first - it->first > 1)
            f.laser_dropouts.push_back(
                {double(it->first + 1) - t0, double(next->first) - t0, 0, {}});
    }
    // Health bins of a whole number of seconds, at most kMaxBins of them.
    const auto seconds = static_cast<std::size_t>(std::ceil(f.duration_s));
    const std::size_t per_bin = std::max<std::size_t>(1, (seconds + kMaxBins - 1) / kMaxBins);
    f.bin_s = double(per_bin);
    f.bins.resize(seconds == 0 ? 0 : (seconds + per_bin - 1) / per_bin);
    for (std::size_t b = 0; b < f.bins.size(); ++b) f.bins[b].t_s = double(b * per_bin);
    auto bin = [&](double t) -> HealthBin* {
        if (f.bins.empty() || t < t0) return nullptr;
        const auto b = static_cast<std::size_t>((t - t0) / f.bin_s);
        return b < f.bins.size() ? &f.bins[b] : &f.bins.back();
    };
    for (const auto& [key, s] : seconds_) {
        if (HealthBin* b = bin(double(key))) {
            b->points += s.points;
            b->coloured += s.coloured;
        }
    }
    for (const journal::TrajectoryPose& p : tr)
        if (HealthBin* b = bin(p.t_s)) ++b->poses;
    trajectoryFacts(tr, t0, f);
    if (!sweeps.empty())
        recordFacts(sweeps, t0, t1, f);
    else
        sweepFacts(stats_json, t0, t1, f);
    return f;
}

}  // namespace handscan::report
