#include "handscan/pipeline_daemon/earlier_scan.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <filesystem>
#include <functional>
#include <sstream>

#include "handscan/journal/journal_reader.hpp"
#include "handscan/prior_map/feature_map_file.hpp"
#include "handscan/prior_map/prior_map_loader.hpp"
#include "handscan/shm/display_voxel_filter.hpp"
#include "handscan/shm/text_field.hpp"

namespace handscan::pipeline_daemon {
namespace {

namespace fs = std::filesystem;

// The directories of `journal_root` holding a scan that can be continued, newest first (their
// names, scan-<UTC time>, sort by time).
std::vector<fs::path> continuableDirs(const std::string& journal_root) {
    std::error_code ec;
    std::vector<fs::path> dirs;
    for (const auto& e : fs::directory_iterator(journal_root, ec)) {
        if (e.is_directory(ec) && canContinue(e.path().string())) dirs.push_back(e.path());
    }
    std::sort(dirs.begin(), dirs.end(), std::greater<>());
    return dirs;
}

}  // namespace

Result<ContinueRequest> parseContinueArgument(const std::string& argument) {
    ContinueRequest r;
    std::istringstream in(argument);
    std::string token;
    while (in >> token) {
        if (token.rfind("scan=", 0) == 0) {
            r.scan = token.substr(5);
            if (r.scan.empty() || r.scan.find('/') != std::string::npos || r.scan == "." ||
                r.scan == "..")
                return Status(StatusCode::kInvalidArgument,
                              "continue: scan='" + r.scan + "': give a scan's directory name");
        } else if (token.rfind("pose=", 0) == 0) {
            auto pose = prior_map::parsePose(token.substr(5));
            if (!pose.isOk())
                return Status(StatusCode::kInvalidArgument, "continue: " + pose.status().message());
            r.initial_pose = *pose;
        } else {
            return Status(StatusCode::kInvalidArgument,
                          "continue: unknown '" + token +
                              "' (expected scan=NAME and/or pose=x,y,z,qx,qy,qz,qw)");
        }
    }
    return r;
}

bool canContinue(const std::string& scan_dir) {
    // Its journal is enough (without its feature map the localizer uses the journal's points).
    std::error_code ec;
    return fs::exists(fs::path(scan_dir) / "journal.hsj", ec);
}

Result<std::string> newestContinuableScan(const std::string& journal_root) {
    const std::vector<fs::path> dirs = continuableDirs(journal_root);
    if (dirs.empty())
        return Status(StatusCode::kNotFound,
                      "no earlier scan to continue in " + journal_root + ": scan and stop first");
    return dirs.front().string();
}

shm::ScanList continuableScans(const std::string& journal_root, const std::string& own_dir,
                               bool own_scanning) {
    shm::ScanList list;
    const fs::path own = own_dir.empty() ? fs::path() : fs::path(own_dir).lexically_normal();
    for (const fs::path& dir : continuableDirs(journal_root)) {
        const bool is_own = !own.empty() && dir.lexically_normal() == own;
        const std::string name = dir.filename().string();
        // A scan being made is not an earlier one; a name the command cannot carry is not listed.
        if ((is_own && own_scanning) || name.size() >= sizeof(shm::ListedScan::name)) continue;
        ++list.total;
        if (list.count == shm::kMaxListedScans) continue;
        shm::ListedScan& l = list.scans[list.count++];
        shm::setText(l.name, name);
        struct stat st {};
        if (::stat((dir / "journal.hsj").c_str(), &st) == 0) {
            l.modified_unix_s = st.st_mtime;
            l.journal_bytes = static_cast<std::uint64_t>(st.st_size);
        }
        l.current = is_own ? 1 : 0;
    }
    return list;
}

Result<std::shared_ptr<const EarlierScan>> loadEarlierScan(const std::string& scan_dir) {
    auto out = std::make_shared<EarlierScan>();
    out->dir = scan_dir;
    auto prior = prior_map::loadPriorMap(scan_dir);
    if (!prior.isOk()) return prior.status();
    out->prior = *prior;
    auto journal = journal::JournalReader::open((fs::path(scan_dir) / "journal.hsj").string());
    if (!journal.isOk()) return journal.status();
    out->trajectory = journal->summary().trajectory;
    // Thinned while read: a long scan's millions of points never sit in memory at once.
    shm::DisplayVoxelFilter shown;
    const Status read = journal->forEachPoints([&](std::span<const journal::MapPoint> chunk) {
        for (const journal::MapPoint& m : chunk) {
            const auto level = static_cast<std::uint8_t>(std::min(255, m.intensity / 16));
            const shm::DisplayPoint d{m.x, m.y, m.z, m.r, m.g, m.b, level};
            if (shown.insert(d)) out->display.push_back(d);
        }
    });
    if (!read.isOk()) return read;
    return std::shared_ptr<const EarlierScan>(std::move(out));
}

}  // namespace handscan::pipeline_daemon
