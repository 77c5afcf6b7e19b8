#include "replay_outputs.hpp"

#include <time.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <vector>

#include "handscan/core/json.hpp"
#include "handscan/export/point_formats.hpp"
#include "handscan/export/safe_file.hpp"

namespace handscan::replay {
namespace {

namespace fs = std::filesystem;

Json callsJson(const std::map<std::string, CallStats>& calls) {
    Json j = Json::object();
    for (const auto& [name, c] : calls) {
        j[name] = {{"calls", c.calls},   {"mean_us", c.mean_us}, {"p50_us", c.p50_us},
                   {"p99_us", c.p99_us}, {"max_us", c.max_us},   {"total_ms", c.total_ms}};
    }
    return j;
}

Json streamJson(const StreamCounters& c) {
    return {{"messages", c.messages},
            {"checksum_failures", c.checksum_failures},
            {"resyncs", c.resyncs},
            {"gaps", c.gaps},
            {"errors", c.errors}};
}

// An interval's end, or null while it is still open at the end of the recording.
Json endSeconds(TimeNs t_end) { return t_end != 0 ? Json(toSeconds(t_end)) : Json(nullptr); }

// The tracking monitor's intervals with tracking lost (sweep start times, s) and the sweeps it
// kept out of the map.
Json trackingJson(const fusion::TrackingMonitor& m) {
    std::uint64_t lost_sweeps = 0;
    Json intervals = Json::array();
    for (const auto& i : m.intervals()) {
        lost_sweeps += i.sweeps;
        intervals.push_back({{"begin_s", toSeconds(i.t_begin)},
                             {"flagged_s", toSeconds(i.t_flagged)},
                             {"end_s", endSeconds(i.t_end)},
                             {"sweeps", i.sweeps},
                             {"reason", fusion::lostReasonName(i.reason)},
                             {"detail", i.detail}});
    }
    return {{"lost_now", m.lost()},
            {"inconsistent_sweeps", m.rejectedSweeps()},
            {"lost_sweeps", lost_sweeps},
            {"lost_intervals", intervals}};
}

// The clocks tracked online (lio::ClockTracker): the offsets applied at the end on top of the
// configured latencies (device.yaml or calibration.yaml time_offsets), in ms.
Json clocksJson(const lio::ClockTracker& c) {
    const lio::ClockTrackerStats& s = c.stats();
    auto finite = [](double v) { return std::isfinite(v) ? Json(v) : Json(nullptr); };
    return {{"solves", s.solves},
            {"determined", s.determined},
            {"rejected_solves", s.rejected_solves},
            {"imu_offset_ms", s.imu_offset_s * 1e3},
            {"encoder_offset_ms", s.encoder_offset_s * 1e3},
            {"imu_wanted_ms", s.imu_target_s * 1e3},
            {"encoder_wanted_ms", s.encoder_target_s * 1e3},
            {"imu_std_ms", finite(s.imu_std_s * 1e3)},
            {"shaft_turn_std_deg", finite(s.turn_std_rad * 180.0 / M_PI)},
            {"imu_at_bound", s.imu_at_bound},
            {"encoder_at_bound", s.encoder_at_bound},
            {"shaft_speed_rev_s", s.shaft_speed_radps / (2.0 * M_PI)},
            {"pairs", s.pairs}};
}

// The check of the scan's calibration on its first seconds (worker::CalibrationCheck).
Json calibrationCheckJson(const worker::CalibrationCheck& c) {
    const worker::CalibrationCheckReport& r = c.report();
    return {{"verdict", worker::calibrationVerdictName(r.verdict)},
            {"checked_after_s", r.checked_after_s},
            {"attempts", r.attempts},
            {"laser_rotation_deg", r.rotation_rad * 180.0 / M_PI},
            {"laser_rotation_std_deg", r.rotation_std_rad * 180.0 / M_PI},
            {"laser_shift_mm", r.shift_m * 1e3},
            {"laser_shift_std_mm", r.shift_std_m * 1e3},
            {"halves_sigma_mm", r.sigma_before_m * 1e3},
            {"halves_sigma_corrected_mm", r.sigma_after_m * 1e3},
            {"planes", r.residuals},
            {"solve_ms", r.solve_ms},
            {"message", r.message}};
}

// The visual-inertial odometry (section 5): frames, how many solved something / everything, the
// mean features and depth kinds, and the stretches it was bypassed (section 8: dark,
// texture-less; recording times in s).
Json visualJson(const worker::VisualStage& v) {
    const worker::VisualStageStats& s = v.stats();
    const double n = s.processed > 0 ? static_cast<double>(s.processed) : 1.0;
    Json bypassed = Json::array();
    for (const worker::BypassInterval& b : v.bypassed()) {
        bypassed.push_back({{"begin_s", toSeconds(b.t_begin)},
                            {"end_s", endSeconds(b.t_end)},
                            {"frames", b.frames}});
    }
    return {{"first_frame_s", toSeconds(s.t_first)},
            {"frames", s.frames},
            {"processed", s.processed},
            {"used", s.used},
            {"all_solved", s.all_solved},
            {"keyframes", s.keyframes},
            {"errors", s.errors},
            {"mean_features", static_cast<double>(s.features_sum) / n},
            {"mean_with_laser_depth", static_cast<double>(s.laser_depth_sum) / n},
            {"mean_triangulated", static_cast<double>(s.triangulated_sum) / n},
            {"bypassed", bypassed}};
}

// The localization on a prior map (section 9): the lock, the matches to the prior at 0.5 Hz,
// their cost, and where the scene changed (cells where something appeared in space the earlier
// session saw through, or vanished from where this session sees through).
Json localizationJson(const localize::Localizer& l, std::uint64_t sweeps_before_lock,
                      std::uint64_t sweeps_held, double recording_s) {
    const localize::LocalizerStats& s = l.stats();
    Json changes = Json::array();
    std::uint64_t appeared = 0, vanished = 0;
    // The report's own cost: the daemon makes it once per used match (0.5 Hz) for the screen.
    timespec t0{}, t1{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t0);
    const std::vector<localize::ChangeCell> cells = l.changes();
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t1);
    const double report_ms = static_cast<double>(t1.tv_sec - t0.tv_sec) * 1e3 +
                             static_cast<double>(t1.tv_nsec - t0.tv_nsec) * 1e-6;
    for (const localize::ChangeCell& c : cells) {
        const bool app = c.kind == localize::ChangeKind::kAppeared;
        ++(app ? appeared : vanished);
        changes.push_back({{"x", c.centre.x()},
                           {"y", c.centre.y()},
                           {"z", c.centre.z()},
                           {"kind", app ? "appeared" : "vanished"},
                           {"points", c.points},
                           {"matches", c.matches}});
    }
    const Eigen::Isometry3d& T = l.priorFromOdom();
    const Eigen::Quaterniond q(T.linear());
    return {{"locked", l.locked()},
            {"lock_s", s.t_lock != 0 ? Json(toSeconds(s.t_lock)) : Json(nullptr)},
            {"lock_on_map", s.lock_on_map},
            {"lock_runner_up", s.lock_runner_up},
            {"attempts", s.attempts},
            {"lock_attempts", s.lock_attempts},
            {"updates", s.updates},
            {"rejected_updates", s.rejected_updates},
            {"last_on_map", s.last_on_map},
            {"max_correction_m", s.max_correction_m},
            {"mean_correction_m",
             s.updates > 0 ? s.sum_correction_m / static_cast<double>(s.updates) : 0.0},
            {"sweeps_before_lock", sweeps_before_lock},
            {"sweeps_held_until_lock", sweeps_held},
            {"cpu_ms", s.cpu_ms},
            {"max_attempt_ms", s.max_attempt_ms},
            {"max_apply_delay_s", s.max_apply_delay_s},
            {"cpu_share_of_core", recording_s > 0 ? s.cpu_ms * 1e-3 / recording_s : 0.0},
            {"prior_from_odom_xyz_qxyzw",
             {T.translation().x(), T.translation().y(), T.translation().z(), q.x(), q.y(), q.z(),
              q.w()}},
            {"change_check",
             {{"points", s.points_checked},
              {"changed", s.changed_points},
              {"new", s.new_points},
              {"appeared_cells", appeared},
              {"vanished_cells", vanished},
              {"cell_m", l.config().change_cell_m},
              {"seen_cell_m", l.prior().seenSpace().cellSize()},
              {"far_m", l.config().change_m},
              {"report_cpu_ms", report_ms}}},
            {"changes", changes}};
}

// One sweep's record as stats.json's per_sweep entry.
Json perSweepJson(const journal::SweepRecord& s) {
    const journal::DeviceCounts& d = s.devices;
    Json e = {{"index", s.index},
              {"t_start_s", s.t_start_s},
              {"degenerate_directions", s.degenerateDirections()},
              {"solved_dof_mask", static_cast<int>(s.solved_mask)},
              {"vio_solved_dof_mask", static_cast<int>(s.vio_mask)},
              {"vio", s.vio == journal::SweepVio::kOff        ? "off"
                      : s.vio == journal::SweepVio::kBypassed ? "bypassed"
                                                              : "running"},
              {"points", s.points},
              {"edges", s.edges},
              {"planars", s.planars},
              {"associations", s.associations},
              {"rms_m", s.rms_m},
              {"total_ms", s.total_ms},
              {"tracking", journal::sweepTrackingName(s.tracking)},
              {"in_map", s.in_map},
              {"devices",
               {{"window_s", d.window_s},
                {"laser_scans", d.laser_scans},
                {"imu_samples", d.imu_samples},
                {"encoder_samples", d.encoder_samples},
                {"colour_frames", d.colour_frames},
                {"tracking_frames", d.tracking_frames}}}};
    if (!s.tracking_reason.empty()) e["tracking_reason"] = s.tracking_reason;
    e["pose_xyz_qxyzw"] = std::vector<double>(s.pose, s.pose + 7);
    e["prior_xyz"] = std::vector<double>(s.prior_xyz, s.prior_xyz + 3);
    return e;
}

}  // namespace

ReplayOutputs::ReplayOutputs(std::string out_dir, TiledMapConfig map)
    : dir_(std::move(out_dir)), map_(std::move(map)) {}

Status ReplayOutputs::open() {
    trajectory_ =
        std::make_unique<exporter::SafeFileWriter>((fs::path(dir_) / "trajectory.tum").string());
    return trajectory_->open();
}

Status ReplayOutputs::addPose(const PoseEstimate& pose) {
    const Eigen::Vector3d t = pose.T_world_body.translation();
    const Eigen::Quaterniond q(pose.T_world_body.linear());
    char line[200];
    std::snprintf(line, sizeof line, "%.9f %.6f %.6f %.6f %.9f %.9f %.9f %.9f\n",
                  toSeconds(pose.t_host), t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w());
    tum_ += line;
    if (poses_ > 0) distance_m_ += (t - last_position_).norm();
    last_position_ = t;
    ++poses_;
    // Handed on in 1 MiB pieces: memory stays constant however long the recording.
    if (tum_.size() < (std::size_t{1} << 20)) return Status::ok();
    Status s =
        trajectory_->write({reinterpret_cast<const std::uint8_t*>(tum_.data()), tum_.size()});
    tum_.clear();
    return s;
}

Status ReplayOutputs::addSweep(const lio::RegisteredSweep& s,
                               std::span<const journal::MapPoint> pts) {
    if (!s.tracking.enters_map) return Status::ok();
    // The sensor's position at the sweep start decides which map tiles stay in memory.
    if (Status st = map_.add(pts, s.result.pose.T_world_body.translation()); !st.isOk()) return st;
    registered_points_ += pts.size();
    return Status::ok();
}

Status ReplayOutputs::writeTrajectory() {
    if (Status s =
            trajectory_->write({reinterpret_cast<const std::uint8_t*>(tum_.data()), tum_.size()});
        !s.isOk())
        return s;
    tum_.clear();
    return trajectory_->commit();
}

Result<std::uint64_t> ReplayOutputs::writeMap() {
    exporter::SafeFileWriter file((fs::path(dir_) / "map.ply").string());
    if (Status s = file.open(); !s.isOk()) return s;
    auto writer = exporter::makePlyWriter(file);
    auto n = map_.drain([&](std::uint64_t total) { return writer->begin(total); },
                        [&](std::span<const journal::MapPoint> pts) { return writer->write(pts); });
    if (!n.isOk()) return n.status();
    if (Status s = writer->end(); !s.isOk()) return s;
    return *n;
}

Result<std::string> ReplayOutputs::writeStats(const StatsInputs& in) const {
    const ReplayReport& r = in.report;
    Json j;
    j["recording_s"] = r.recording_s;
    j["wall_s"] = r.wall_s;
    j["realtime_factor"] = r.realtime_factor;
    j["poses"] = r.poses;
    j["distance_m"] = distance_m_;
    j["sweeps"] = sweeps_.size();
    j["registered_points"] = registered_points_;
    j["map_points"] = r.map_points;
    j["peak_rss_mib"] = in.peak_rss_mib;
    const TiledMapStats& m = map_.stats();
    constexpr double kMiB = 1.0 / (1 << 20);
    j["map"] = {
        {"voxel_m", map_.config().voxel_m},
        {"tile_m", map_.config().tile_m},
        {"memory_budget_mib", static_cast<double>(map_.config().memory_budget_bytes) * kMiB},
        {"tiles", m.tiles},
        {"peak_resident_mib", static_cast<double>(m.peak_resident_bytes) * kMiB},
        {"fragments_flushed", m.fragments_flushed},
        {"voxels_flushed", m.cells_flushed},
        {"consolidations", m.consolidations},
        {"compactions", m.compactions},
        {"peak_spill_mib", static_cast<double>(m.peak_spill_bytes) * kMiB},
        {"spill_written_mib", static_cast<double>(m.spill_written_bytes) * kMiB}};
    j["modules"] = callsJson(in.calls);
    j["streams"] = {{"hokuyo", streamJson(in.hokuyo)},
                    {"xsens", streamJson(in.xsens)},
                    {"encoder", streamJson(in.encoder)}};
    const auto& a = in.pipeline.assemblerStats();
    j["sweep_assembly"] = {{"scans", a.scans},
                           {"points", a.points},
                           {"dropped_invalid_range", a.dropped_invalid_range},
                           {"dropped_no_encoder", a.dropped_no_encoder},
                           {"dropped_scans_late", a.dropped_scans_late}};
    const auto& p = in.pipeline.predictor().stats();
    j["imu"] = {
        {"aligned", in.pipeline.aligned()}, {"samples", p.samples},
        {"rejected", p.rejected_samples},   {"gaps", p.gaps},
        {"corrections", p.corrections},     {"rejected_corrections", p.rejected_corrections}};
    j["recording"] = {{"truncated", in.recording_truncated},
                      {"dropped_regions", in.recording_dropped_regions}};
    j["tracking"] = trackingJson(in.pipeline.tracking());
    j["clocks"] = clocksJson(in.pipeline.clocks());
    if (in.calibration_check != nullptr)
        j["calibration_check"] = calibrationCheckJson(*in.calibration_check);
    if (in.visual != nullptr && in.visual->stats().frames > 0) j["vio"] = visualJson(*in.visual);
    if (in.localizer != nullptr)
        j["localization"] =
            localizationJson(*in.localizer, in.sweeps_before_lock, in.sweeps_held, r.recording_s);
    // Degenerate directions per sweep (section 8): 6 minus the DOFs the matcher solved.
    std::vector<std::size_t> histogram(7, 0);
    for (const journal::SweepRecord& s : sweeps_)
        ++histogram[static_cast<std::size_t>(s.degenerateDirections())];
    j["degenerate_directions_histogram"] = histogram;
    Json per_sweep = Json::array();
    for (const journal::SweepRecord& s : sweeps_) per_sweep.push_back(perSweepJson(s));
    j["per_sweep"] = std::move(per_sweep);
    const std::string path = (fs::path(dir_) / "stats.json").string();
    if (Status s = exporter::writeSmallFile(path, jsonText(j, 2) + "\n"); !s.isOk()) return s;
    return path;
}

}  // namespace handscan::replay
