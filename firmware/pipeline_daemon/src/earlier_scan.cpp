#include "handscan/pipeline_daemon/earlier_scan.hpp"

#include <algorithm>
#include <filesystem>
#include <sstream>

#include "handscan/journal/journal_reader.hpp"
#include "handscan/prior_map/feature_map_file.hpp"
#include "handscan/prior_map/prior_map_loader.hpp"
#include "handscan/shm/display_voxel_filter.hpp"

namespace handscan::pipeline_daemon {
namespace {

namespace fs = std::filesystem;

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
    std::error_code ec;
    std::vector<std::string> dirs;
    for (const auto& e : fs::directory_iterator(journal_root, ec)) {
        if (e.is_directory(ec) && canContinue(e.path().string())) dirs.push_back(e.path());
    }
    if (dirs.empty())
        return Status(StatusCode::kNotFound,
                      "no earlier scan to continue in " + journal_root + ": scan and stop first");
    return *std::max_element(dirs.begin(), dirs.end());  // scan-<UTC time>: the newest
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
