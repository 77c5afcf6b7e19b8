#include "hil_outputs.hpp"

#include <cinttypes>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>

#include "handscan/journal/journal_reader.hpp"

namespace handscan::hil {
namespace {

namespace fs = std::filesystem;

Status writeTum(const fs::path& path, const std::vector<journal::TrajectoryPose>& poses,
                double shift_s) {
    std::ofstream out(path, std::ios::trunc);
    out << "# t x y z qx qy qz qw\n";
    char line[256];
    for (const journal::TrajectoryPose& p : poses) {
        std::snprintf(line, sizeof line, "%.9f %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n",
                      p.t_s - shift_s, p.x, p.y, p.z, p.qx, p.qy, p.qz, p.qw);
        out << line;
    }
    out.flush();
    if (!out) return Status(StatusCode::kIoError, path.string() + ": write failed");
    return Status::ok();
}

// The newest scan directory's journal under DIR/journal.
// The daemon's scans' journals, oldest first (scan-<UTC time>).
Result<std::vector<fs::path>> findScanJournals(const fs::path& root) {
    std::vector<fs::path> found;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(root, ec)) {
        if (fs::exists(e.path() / "journal.hsj", ec)) found.push_back(e.path() / "journal.hsj");
    }
    if (found.empty())
        return Status(StatusCode::kNotFound, root.string() + ": the daemon journaled no scan");
    std::sort(found.begin(), found.end());
    return found;
}

// The exported point cloud (PLY) under DIR/export, linked (or copied) to DIR/map.ply.
std::string linkExportedMap(const fs::path& out) {
    std::error_code ec;
    for (const auto& e : fs::recursive_directory_iterator(out / "export", ec)) {
        if (e.path().extension() != ".ply") continue;
        fs::remove(out / "map.ply", ec);
        fs::create_hard_link(e.path(), out / "map.ply", ec);
        if (ec) fs::copy_file(e.path(), out / "map.ply", ec);
        return e.path().string();
    }
    return {};
}

}  // namespace

std::uint64_t droppedSamplesInLog(const fs::path& log) {
    std::ifstream in(log);
    const std::regex queues(R"(samples dropped at full queues \((\d+) in all\))");
    // The worker's count of samples it had to drop at a shutdown (worker::PipelineWorker).
    const std::regex unprocessed(R"((\d+) samples not processed before shutdown)");
    std::uint64_t at_queues = 0, at_shutdown = 0;
    std::string line;
    std::smatch m;
    while (std::getline(in, line)) {
        // A restarted daemon counts from 0 again: add each life's last figure.
        if (line.find("handscan-pipeline: ") != std::string::npos &&
            line.find("devices, journal in") != std::string::npos) {
            at_shutdown += at_queues;
            at_queues = 0;
        }
        if (std::regex_search(line, m, queues)) at_queues = std::stoull(m[1]);
        if (std::regex_search(line, m, unprocessed)) at_shutdown += std::stoull(m[1]);
    }
    return at_queues + at_shutdown;
}

Status writeHilOutputs(const OutputsInputs& in, HilReport& report) {
    auto journals = findScanJournals(in.out / "journal");
    if (!journals.isOk()) return journals.status();
    const fs::path& path = journals->back();  // the last scan
    auto j = journal::JournalReader::open(path.string());
    if (!j.isOk()) return j.status();
    const journal::JournalSummary& js = j->summary();
    report.journal = path.string();
    std::string recovered_journal;
    if (in.options.kill_at_s && journals->size() >= 2) {
        recovered_journal = journals->front().string();
        auto r = journal::JournalReader::open(recovered_journal);
        if (!r.isOk()) return r.status();
        report.recovered_points = r->summary().points;
    }
    report.poses = js.trajectory.size();
    report.points = js.points;
    // Points the colour camera saw (the others carry their laser grey).
    std::uint64_t coloured = 0;
    if (Status st = j->forEachPoints([&](std::span<const journal::MapPoint> pts) {
            for (const journal::MapPoint& p : pts) coloured += journal::hasColour(p) ? 1 : 0;
        });
        !st.isOk())
        return st;
    report.coloured_points = coloured;
    const double shift_s = toSeconds(in.offset);
    if (Status s = writeTum(in.out / "trajectory.tum", js.trajectory, shift_s); !s.isOk()) return s;
    if (Status s = writeTum(in.out / "trajectory.host.tum", js.trajectory, 0.0); !s.isOk())
        return s;
    const std::string cloud = linkExportedMap(in.out);
    report.samples_dropped = droppedSamplesInLog(in.log);

    nlohmann::ordered_json s;
    s["recording"] = in.rec.path;
    s["recording_s"] = report.recording_s;
    s["time_offset_ns"] = in.offset;
    s["time_note"] =
        "trajectory.tum = daemon host times - time_offset_ns (the recording's clock); "
        "trajectory.host.tum keeps the host times";
    s["daemon"] = {{"user_cpu_s", report.daemon_user_cpu_s},
                   {"system_cpu_s", report.daemon_system_cpu_s},
                   {"cpu_s", report.daemon_user_cpu_s + report.daemon_system_cpu_s},
                   {"cpu_per_recording_s", (report.daemon_user_cpu_s + report.daemon_system_cpu_s) /
                                               std::max(1e-9, report.recording_s)},
                   {"peak_rss_mib", report.daemon_peak_rss_mib},
                   {"killed_and_restarted", in.options.kill_at_s.has_value()},
                   {"recovered_after_kill", report.recovered_after_kill}};
    if (in.options.kill_at_s) {
        s["recovered"] = {{"journal", recovered_journal},
                          {"points", report.recovered_points},
                          {"export_points", report.recovered_export_points},
                          {"note",
                           "the scan up to the kill, recovered by the restarted daemon and "
                           "exported to export-recovered/; journal, export and "
                           "trajectory.tum are the scan started after the restart"}};
    }
    s["samples_dropped"] = report.samples_dropped;
    s["journal"] = {{"path", report.journal},  {"poses", report.poses},
                    {"points", js.points},     {"coloured_points", coloured},
                    {"finished", js.finished}, {"damage", js.damage}};
    s["export"] = {{"cloud", cloud}, {"points", report.export_points}};
    const RecordingFakes::Counts& c = in.played;
    s["played"] = {{"hokuyo_scans_recorded", c.scans_recorded},
                   {"hokuyo_scans_sent", c.scans_sent},
                   {"hokuyo_scans_lost_while_disconnected", c.scans_skipped},
                   {"hokuyo_connections", c.hokuyo_connections},
                   {"xsens_reads_recorded", c.xsens_chunks_recorded},
                   {"xsens_reads_sent", c.xsens_chunks_sent},
                   {"xsens_reads_lost_in_config_mode", c.xsens_chunks_lost},
                   {"can_frames", c.can_frames},
                   {"tracking_camera_frames", c.track_frames},
                   {"colour_camera_frames", c.colour_frames}};
    std::ofstream out(in.out / "stats.json", std::ios::trunc);
    out << s.dump(2) << '\n';
    if (!out)
        return Status(StatusCode::kIoError, (in.out / "stats.json").string() + ": write failed");

    char line[512];
    std::snprintf(line, sizeof line,
                  "hil: %zu poses, %" PRIu64 " journal points (%.1f %% coloured), %" PRIu64
                  " samples dropped; daemon CPU %.1f s (%.2f s per recording s), peak RSS %.0f "
                  "MiB\n",
                  report.poses, report.points,
                  100.0 * static_cast<double>(coloured) /
                      static_cast<double>(std::max<std::uint64_t>(1, report.points)),
                  report.samples_dropped, report.daemon_user_cpu_s + report.daemon_system_cpu_s,
                  (report.daemon_user_cpu_s + report.daemon_system_cpu_s) /
                      std::max(1e-9, report.recording_s),
                  report.daemon_peak_rss_mib);
    report.summary = line;
    if (!report.calibration.empty()) report.summary += "calibrate: " + report.calibration + "\n";
    return Status::ok();
}

}  // namespace handscan::hil
