// `handscan eval`: accuracy of a replay against ground truth.
//   handscan eval --gt GT.tum --est EST.tum [--plot out.png]   trajectory: ATE, segment drift, end
//   point handscan eval --map MAP.ply --mesh scene.ply               map: point-to-surface distance
//   handscan eval --map MAP.ply --mesh scene.ply --gt GT.tum --est EST.tum
//       both; the map is first moved into the ground truth's frame by the trajectory's SE(3)
//       alignment (the pipeline's world frame is its own gravity-aligned start frame, not the
//       scene's).
// Exit 0 on success, 2 on unreadable or inconsistent input (message says which file and why).
#include <fmt/format.h>

#include <iostream>

#include "command_registry.hpp"
#include "handscan/eval/mesh_distance.hpp"
#include "handscan/eval/ply_reader.hpp"
#include "handscan/eval/trajectory_metrics.hpp"
#include "handscan/eval/trajectory_plot.hpp"
#include "handscan/report/map_images.hpp"

namespace handscan::cli {
namespace {

struct EvalOptions {
    std::string gt, est, plot, map, mesh;
    // A second session in the first's frame: the first session's ground truth and estimate,
    // whose alignment replaces the second's own (issue 14).
    std::string frame_gt, frame_est;
    bool start_in_frame = false;
    double max_gap_s = 0.25;
};

int fail(const Status& s) {
    std::cerr << "handscan eval: " << s.message() << "\n";
    return 2;
}

// Prints the trajectory figures; `T_gt_est` receives the ATE alignment.
int evalTrajectory(const EvalOptions& o, Eigen::Isometry3d& T_gt_est) {
    auto gt = eval::readTum(o.gt);
    if (!gt) return fail(gt.status());
    auto est = eval::readTum(o.est);
    if (!est) return fail(est.status());
    const auto pairs = eval::associate(*gt, *est, o.max_gap_s);
    if (pairs.size() < 3) {
        return fail(Status(
            StatusCode::kInvalidArgument,
            fmt::format("only {} of {} estimated poses fall within the ground truth's time span "
                        "[{:.3f}, {:.3f}] s; are both files on the same clock?",
                        pairs.size(), est->size(), gt->empty() ? 0.0 : gt->front().t_s,
                        gt->empty() ? 0.0 : gt->back().t_s)));
    }
    Eigen::Isometry3d T_frame = Eigen::Isometry3d::Identity();
    if (!o.frame_gt.empty()) {
        auto fgt = eval::readTum(o.frame_gt);
        if (!fgt) return fail(fgt.status());
        auto fest = eval::readTum(o.frame_est);
        if (!fest) return fail(fest.status());
        const auto frame_pairs = eval::associate(*fgt, *fest, o.max_gap_s);
        if (frame_pairs.size() < 3)
            return fail(
                Status(StatusCode::kInvalidArgument,
                       o.frame_est + ": fewer than 3 poses within " + o.frame_gt + "'s time span"));
        T_frame = eval::computeAte(frame_pairs).T_gt_est;
    }
    const auto ate =
        o.frame_gt.empty() ? eval::computeAte(pairs) : eval::computeAteWith(pairs, T_frame);
    T_gt_est = ate.T_gt_est;
    if (o.start_in_frame) {
        // Where the ground truth starts, in the estimate's frame (a hint for --initial-pose).
        const Eigen::Quaterniond qa(T_gt_est.linear());
        std::cout << fmt::format(
            "alignment (estimate to ground truth): "
            "{:.6f},{:.6f},{:.6f},{:.9f},{:.9f},{:.9f},{:.9f}\n",
            T_gt_est.translation().x(), T_gt_est.translation().y(), T_gt_est.translation().z(),
            qa.x(), qa.y(), qa.z(), qa.w());
        const Eigen::Isometry3d S = T_gt_est.inverse() * gt->front().T;
        const Eigen::Quaterniond q(S.linear());
        std::cout << fmt::format(
            "start in the estimate's frame: {:.6f},{:.6f},{:.6f},{:.9f},{:.9f},{:.9f},{:.9f}\n",
            S.translation().x(), S.translation().y(), S.translation().z(), q.x(), q.y(), q.z(),
            q.w());
    }
    const auto drift = eval::computeDrift(pairs);
    const auto end = eval::computeEndPoint(pairs);
    std::cout << fmt::format(
        "poses: {} associated of {} estimated; path length {:.2f} m over {:.1f} s\n", pairs.size(),
        est->size(), drift.path_length_m, pairs.back().t_s - pairs.front().t_s);
    const auto& t = ate.translation_m;
    std::cout << fmt::format(
        "ATE ({}) [m]: rmse {:.4f}  mean {:.4f}  median {:.4f}  max {:.4f}\n",
        o.frame_gt.empty() ? "SE(3)-aligned" : "in the frame of --frame-est's alignment", t.rmse,
        t.mean, t.median, t.max);
    std::cout << fmt::format("rotation error (aligned) [deg]: rmse {:.3f}  max {:.3f}\n",
                             ate.rotation_deg.rmse, ate.rotation_deg.max);
    if (ate.orientation_chose_branch) {
        std::cout << "alignment: the path is planar and its positions fit the mirrored, "
                     "upside-down branch "
                     "better; the orientations chose the upright one (the estimate is distorted in "
                     "plane)\n";
    }
    for (const auto& d : drift.per_length) {
        if (d.segments == 0) {
            std::cout << fmt::format("drift {:>4.0f} m: no segment (path too short)\n", d.length_m);
            continue;
        }
        std::cout << fmt::format("drift {:>4.0f} m: {:.3f} %  {:.4f} deg/m  ({} segments)\n",
                                 d.length_m, d.translation_percent, d.rotation_deg_per_m,
                                 d.segments);
    }
    std::cout << fmt::format("drift mean: {:.3f} %  {:.4f} deg/m\n", drift.mean_translation_percent,
                             drift.mean_rotation_deg_per_m);
    std::cout << fmt::format(
        "end point: {:.4f} m ({:.3f} % of path), {:.3f} deg; ground truth {} (start-end gap "
        "{:.3f} m)\n",
        end.error_m, end.error_percent, end.rotation_error_deg,
        end.is_loop ? "is a loop" : "is not a loop", end.gt_start_end_gap_m);
    if (!o.plot.empty()) {
        if (Status s = eval::plotTopView(o.plot, pairs, ate.T_gt_est); !s) return fail(s);
        std::cout << "plot: " << o.plot << "\n";
    }
    return 0;
}

// The export report's map views (handscan::report) of the map in the ground truth's frame, with
// the aligned estimate drawn over them: <plot>_map_top.png and <plot>_map_side.png.
Status plotMapViews(const EvalOptions& o, const std::vector<Eigen::Vector3d>& vertices,
                    const Eigen::Isometry3d& T_gt_est) {
    report::MapRaster top(report::View::kTop), side(report::View::kSide);
    std::vector<journal::MapPoint> pts;
    pts.reserve(vertices.size());
    for (const Eigen::Vector3d& v : vertices) {
        pts.push_back({0.0, static_cast<float>(v.x()), static_cast<float>(v.y()),
                       static_cast<float>(v.z()), 0, 0, 0, 0});
    }
    top.add(pts);
    side.add(pts);
    std::vector<journal::TrajectoryPose> trajectory;
    if (!o.est.empty()) {
        auto est = eval::readTum(o.est);
        if (!est) return est.status();
        for (const eval::StampedPose& p : *est) {
            const Eigen::Vector3d t = (T_gt_est * p.T).translation();
            trajectory.push_back({p.t_s, t.x(), t.y(), t.z()});
        }
    }
    const std::string stem = o.plot.size() > 4 && o.plot.ends_with(".png")
                                 ? o.plot.substr(0, o.plot.size() - 4)
                                 : o.plot;
    for (const auto& [raster, name] : {std::pair{&top, "_map_top.png"}, {&side, "_map_side.png"}}) {
        auto img = report::renderMap(*raster, report::Colouring::kHeight, trajectory,
                                     std::string("map ") +
                                         (raster == &top ? "from above" : "from the side") +
                                         ", coloured by height");
        if (!img) return img.status();
        if (Status s = report::writePng(stem + name, *img); !s) return s;
        std::cout << "plot: " << stem + name << "\n";
    }
    return Status::ok();
}

int evalMap(const EvalOptions& o, const Eigen::Isometry3d& T_gt_est) {
    auto map = eval::readPly(o.map);
    if (!map) return fail(map.status());
    for (Eigen::Vector3d& v : map->vertices) v = T_gt_est * v;
    if (!o.plot.empty()) {
        if (Status s = plotMapViews(o, map->vertices, T_gt_est); !s) return fail(s);
    }
    auto mesh = eval::readPly(o.mesh);
    if (!mesh) return fail(mesh.status());
    auto index = eval::MeshDistance::build(std::move(*mesh));
    if (!index)
        return fail(Status(index.status().code(), o.mesh + ": " + index.status().message()));
    const auto r = eval::computeMapError(map->vertices, **index);
    if (r.points == 0)
        return fail(Status(StatusCode::kInvalidArgument, o.map + ": the map has no points"));
    std::cout << fmt::format(
        "map error{} over {} points against {} triangles [m]: median {:.4f}  p90 {:.4f}  "
        "p99 {:.4f}  mean {:.4f}  max {:.4f}\n",
        o.gt.empty() ? "" : " (map aligned by the trajectory)", r.points, (*index)->triangles(),
        r.median_m, r.p90_m, r.p99_m, r.mean_m, r.max_m);
    return 0;
}

const RegisterCommand kEval{
    "eval", "Accuracy against ground truth: trajectory (ATE, drift) or map error",
    [](CLI::App& sub) {
        auto o = std::make_shared<EvalOptions>();
        sub.add_option("--gt", o->gt, "ground-truth trajectory (TUM)");
        sub.add_option("--est", o->est, "estimated trajectory (TUM)");
        sub.add_option("--plot", o->plot,
                       "write a top-view PNG of both trajectories (with --map also the export "
                       "report's map views, <plot>_map_top.png and <plot>_map_side.png)");
        sub.add_option("--max-gap", o->max_gap_s,
                       "do not interpolate ground truth over gaps longer than this (s)");
        sub.add_option("--frame-gt", o->frame_gt,
                       "with --frame-est: measure in the frame these two align to (a second "
                       "session localized on the first: the first's ground truth)");
        sub.add_option("--frame-est", o->frame_est,
                       "the first session's estimated trajectory (TUM)");
        sub.add_flag("--start-in-frame", o->start_in_frame,
                     "print the alignment and where --gt starts in the estimate's frame "
                     "(x,y,z,qx,qy,qz,qw: an --initial-pose for replay --prior-map)");
        sub.add_option("--map", o->map, "registered map (PLY)");
        sub.add_option("--mesh", o->mesh, "true scene surfaces (PLY mesh)");
        return std::function<int()>([o] {
            const bool traj = !o->gt.empty() || !o->est.empty();
            const bool map = !o->map.empty() || !o->mesh.empty();
            if ((!traj && !map) || (traj && (o->gt.empty() || o->est.empty())) ||
                (map && (o->map.empty() || o->mesh.empty()))) {
                std::cerr << "handscan eval: give --gt and --est (trajectory), --map and --mesh "
                             "(map), or all four "
                             "(map aligned by the trajectory)\n";
                return 2;
            }
            if (o->frame_gt.empty() != o->frame_est.empty()) {
                std::cerr << "handscan eval: --frame-gt and --frame-est go together\n";
                return 2;
            }
            Eigen::Isometry3d T_gt_est = Eigen::Isometry3d::Identity();
            if (traj) {
                if (const int rc = evalTrajectory(*o, T_gt_est); rc != 0 || !map) return rc;
            }
            return evalMap(*o, T_gt_est);
        });
    }};

}  // namespace
}  // namespace handscan::cli
