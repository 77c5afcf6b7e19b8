#include "handscan/merge/session_merge.hpp"

#include <filesystem>

#include "handscan/core/json.hpp"
#include "handscan/export/point_formats.hpp"
#include "handscan/export/safe_file.hpp"
#include "handscan/journal/journal_reader.hpp"
#include "handscan/tum/tum_file.hpp"

namespace handscan::merge {
namespace {

namespace fs = std::filesystem;

std::string canonical(const std::string& p) {
    std::error_code ec;
    const fs::path c = fs::weakly_canonical(fs::path(p), ec);
    return ec ? p : c.string();
}

// Every `stride`-th point of a journal, for the consistency check.
Result<std::vector<Eigen::Vector3f>> samplePoints(const journal::JournalReader& j,
                                                  std::uint64_t stride) {
    std::vector<Eigen::Vector3f> out;
    std::uint64_t n = 0;
    Status s = j.forEachPoints([&](std::span<const journal::MapPoint> pts) {
        for (const journal::MapPoint& p : pts)
            if (n++ % stride == 0) out.emplace_back(p.x, p.y, p.z);
    });
    if (!s.isOk()) return s;
    return out;
}

}  // namespace

Result<MergeReport> mergeSessions(const std::vector<std::string>& dirs,
                                  const std::string& out_dir) {
    if (dirs.size() < 2)
        return Status(StatusCode::kInvalidArgument, "merge: give at least two scan directories");
    std::vector<journal::JournalReader> journals;
    MergeReport report;
    for (std::size_t i = 0; i < dirs.size(); ++i) {
        const std::string path = (fs::path(dirs[i]) / "journal.hsj").string();
        auto j = journal::JournalReader::open(path);
        if (!j.isOk())
            return Status(j.status().code(),
                          "merge: session " + std::to_string(i + 1) + ": " + j.status().message());
        SessionSummary s;
        s.dir = dirs[i];
        s.points = j->summary().points;
        s.poses = j->summary().trajectory.size();
        const Json meta = Json::parse(j->summary().metadata_json, nullptr, false);
        if (meta.is_object() && meta.contains("prior_map") && meta["prior_map"].is_string())
            s.prior_map = meta["prior_map"].get<std::string>();
        if (i > 0) {
            s.in_frame = false;
            for (std::size_t k = 0; k < i; ++k)
                s.in_frame = s.in_frame ||
                             (!s.prior_map.empty() && canonical(s.prior_map) == canonical(dirs[k]));
        }
        report.points += s.points;
        report.sessions.push_back(s);
        journals.push_back(std::move(*j));
    }
    std::error_code ec;
    fs::create_directories(out_dir, ec);
    if (ec)
        return Status(StatusCode::kIoError,
                      "merge: cannot create " + out_dir + ": " + ec.message());

    // One pass over every journal: PLY and LAS side by side, each point tagged with its session.
    exporter::SafeFileWriter ply_file((fs::path(out_dir) / "map.ply").string());
    exporter::SafeFileWriter las_file((fs::path(out_dir) / "map.las").string());
    for (auto* f : {&ply_file, &las_file})
        if (Status s = f->open(); !s.isOk()) return s;
    auto ply = exporter::makePlyWriter(
        ply_file,
        {"handscan merged multi-session point cloud, metres, frame of session 1",
         "session: 1 = first directory given, 2 = second, ..."},
        /*with_session=*/true);
    auto las = exporter::makeLasWriter(las_file);
    for (auto* w : {ply.get(), las.get()})
        if (Status s = w->begin(report.points); !s.isOk()) return s;
    std::vector<journal::MapPoint> buf;
    for (std::size_t i = 0; i < journals.size(); ++i) {
        Status write_status;
        Status s = journals[i].forEachPoints([&](std::span<const journal::MapPoint> pts) {
            if (!write_status.isOk()) return;
            buf.assign(pts.begin(), pts.end());
            for (journal::MapPoint& p : buf) p.session = static_cast<std::uint16_t>(i + 1);
            write_status = ply->write(buf);
            if (write_status.isOk()) write_status = las->write(buf);
        });
        if (!s.isOk()) return s;
        if (!write_status.isOk()) return write_status;
        tum::Trajectory t;
        for (const journal::TrajectoryPose& p : journals[i].summary().trajectory) {
            tum::StampedPose sp;
            sp.t_s = p.t_s;
            sp.T.linear() =
                Eigen::Quaterniond(p.qw, p.qx, p.qy, p.qz).normalized().toRotationMatrix();
            sp.T.translation() = Eigen::Vector3d(p.x, p.y, p.z);
            t.push_back(sp);
        }
        const std::string tum_path =
            (fs::path(out_dir) / ("trajectory_" + std::to_string(i + 1) + ".tum")).string();
        if (Status st = tum::writeTum(tum_path, t); !st.isOk()) return st;
    }
    for (auto* w : {ply.get(), las.get()})
        if (Status s = w->end(); !s.isOk()) return s;

    // Consistency of each later session with the first where they overlap.
    const std::uint64_t stride0 = std::max<std::uint64_t>(1, report.sessions[0].points / 2000000);
    auto first = samplePoints(journals[0], stride0);
    if (!first.isOk()) return first.status();
    Json sessions = Json::array();
    Json consistency;
    for (std::size_t i = 0; i < journals.size(); ++i) {
        SessionSummary& s = report.sessions[i];
        Json e = {{"session", i + 1},         {"dir", s.dir},
                  {"points", s.points},       {"poses", s.poses},
                  {"prior_map", s.prior_map}, {"in_frame", s.in_frame}};
        if (i > 0) {
            auto later = samplePoints(journals[i], std::max<std::uint64_t>(1, s.points / 200000));
            if (!later.isOk()) return later.status();
            s.against_first = measureConsistency(*first, *later);
            const Consistency& c = s.against_first;
            e["against_session_1"] = {{"sampled", c.sampled},
                                      {"overlap_points", c.overlap_points},
                                      {"median_m", c.median_m},
                                      {"p90_m", c.p90_m},
                                      {"mean_m", c.mean_m}};
            if (i == 1) consistency = e["against_session_1"];
        }
        sessions.push_back(std::move(e));
    }
    Json j = {{"points", report.points},
              {"frame", "session 1"},
              {"sessions", sessions},
              {"consistency", consistency}};
    report.sessions_json = (fs::path(out_dir) / "sessions.json").string();
    if (Status s = exporter::writeSmallFile(report.sessions_json, jsonText(j, 2) + "\n"); !s.isOk())
        return s;
    return report;
}

}  // namespace handscan::merge
