#include "handscan/prior_map/prior_map_loader.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <sstream>
#include <unordered_set>
#include <vector>

#include "handscan/core/log.hpp"
#include "handscan/journal/journal_reader.hpp"
#include "handscan/prior_map/feature_map_file.hpp"
#include "handscan/scan/voxel_key.hpp"
#include "handscan/scan/voxel_map.hpp"
#include "handscan/tum/tum_file.hpp"

namespace handscan::prior_map {
namespace {

namespace fs = std::filesystem;

// Where the earlier scan started: its journal's first pose, else its trajectory.tum's.
Result<Eigen::Isometry3d> startOf(const std::string& dir) {
    const fs::path journal = fs::path(dir) / "journal.hsj";
    if (fs::exists(journal)) {
        auto j = journal::JournalReader::open(journal.string());
        if (j.isOk() && !j->summary().trajectory.empty()) {
            const journal::TrajectoryPose& p = j->summary().trajectory.front();
            Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
            T.linear() = Eigen::Quaterniond(p.qw, p.qx, p.qy, p.qz).normalized().toRotationMatrix();
            T.translation() = Eigen::Vector3d(p.x, p.y, p.z);
            return T;
        }
    }
    const fs::path tum_path = fs::path(dir) / "trajectory.tum";
    auto tum = tum::readTum(tum_path.string());
    if (!tum.isOk()) return tum.status();
    if (tum->empty())
        return Status(StatusCode::kInvalidArgument,
                      tum_path.string() + ": empty trajectory (where did the scan start?)");
    return tum->front().T;
}

}  // namespace

Result<scan::FeatureMapPoints> featuresFromJournal(const std::string& journal_path) {
    auto j = journal::JournalReader::open(journal_path);
    if (!j.isOk()) return j.status();
    const std::vector<journal::TrajectoryPose>& path = j->summary().trajectory;
    // Where the laser was when it saw a point: the body at the nearest journaled pose (the
    // laser sits centimetres from the body's origin).
    const auto centreAt = [&](double t) -> Eigen::Vector3f {
        if (path.empty()) return Eigen::Vector3f::Constant(std::numeric_limits<float>::quiet_NaN());
        auto it = std::lower_bound(
            path.begin(), path.end(), t,
            [](const journal::TrajectoryPose& p, double time) { return p.t_s < time; });
        if (it == path.end() || (it != path.begin() && t - std::prev(it)->t_s < it->t_s - t)) --it;
        return Eigen::Vector3f(static_cast<float>(it->x), static_cast<float>(it->y),
                               static_cast<float>(it->z));
    };
    // One point per planar leaf of the odometry's map: the journal's surfaces at its density.
    const double leaf = scan::VoxelMapConfig{}.planar_leaf_m;
    scan::FeatureMapPoints out;
    std::unordered_set<scan::VoxelKey, scan::VoxelKeyHash> taken;
    const Status read = j->forEachPoints([&](std::span<const journal::MapPoint> chunk) {
        for (const journal::MapPoint& m : chunk) {
            const Eigen::Vector3f p(m.x, m.y, m.z);
            if (!p.allFinite() || !taken.insert(scan::voxelOf(p.cast<double>(), leaf)).second)
                continue;
            out.planars.push_back(p);
            out.planar_origins.push_back(centreAt(m.t_s));
        }
    });
    if (!read.isOk()) return read;
    return out;
}

Result<std::shared_ptr<const localize::PriorMap>> loadPriorMap(const std::string& scan_dir) {
    if (!fs::is_directory(scan_dir))
        return Status(StatusCode::kNotFound,
                      scan_dir + ": not a directory (give an earlier scan's output directory)");
    const fs::path features = fs::path(scan_dir) / kFeatureMapFile;
    const fs::path journal = fs::path(scan_dir) / "journal.hsj";
    // A scan without its feature map (made before scans kept one, or the file lost): its
    // journal's points stand in, as planar features only.
    const bool from_journal = !fs::exists(features) && fs::exists(journal);
    if (from_journal)
        log().warn("{}: no {}: localizing on its journal's points (planar only)", scan_dir,
                   kFeatureMapFile);
    auto points =
        from_journal ? featuresFromJournal(journal.string()) : readFeatureMap(features.string());
    if (!points.isOk()) return points.status();
    if (points->edges.size() + points->planars.size() < 100)
        return Status(StatusCode::kInvalidArgument,
                      scan_dir + ": the feature map holds almost nothing to localize on");
    auto start = startOf(scan_dir);
    if (!start.isOk()) return start.status();
    return std::shared_ptr<const localize::PriorMap>(
        std::make_shared<localize::PriorMap>(*points, *start));
}

Result<Eigen::Isometry3d> parsePose(const std::string& text) {
    std::vector<double> v;
    std::stringstream ss(text);
    std::string item;
    while (std::getline(ss, item, ',')) {
        try {
            std::size_t used = 0;
            v.push_back(std::stod(item, &used));
            if (used != item.size()) throw std::invalid_argument(item);
        } catch (const std::exception&) {
            return Status(StatusCode::kInvalidArgument,
                          "pose '" + text + "': '" + item + "' is not a number");
        }
    }
    if (v.size() != 7)
        return Status(StatusCode::kInvalidArgument,
                      "pose '" + text + "': expected x,y,z,qx,qy,qz,qw (7 numbers), got " +
                          std::to_string(v.size()));
    const Eigen::Quaterniond q(v[6], v[3], v[4], v[5]);
    if (std::abs(q.norm() - 1.0) > 1e-3)
        return Status(StatusCode::kInvalidArgument,
                      "pose '" + text + "': the quaternion is not of unit length");
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = q.normalized().toRotationMatrix();
    T.translation() = Eigen::Vector3d(v[0], v[1], v[2]);
    return T;
}

}  // namespace handscan::prior_map
