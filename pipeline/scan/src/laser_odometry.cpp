#include "handscan/scan/laser_odometry.hpp"

#include <algorithm>
#include <chrono>

namespace handscan::scan {
namespace {

double msSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

std::vector<Eigen::Vector3d> transformed(const Eigen::Isometry3d& T,
                                         const std::vector<Eigen::Vector3d>& pts) {
    std::vector<Eigen::Vector3d> out;
    out.reserve(pts.size());
    for (const Eigen::Vector3d& p : pts) {
        out.push_back(T * p);
    }
    return out;
}

}  // namespace

LaserOdometry::LaserOdometry(const LaserOdometryConfig& config)
    : config_(config), matcher_(config.matcher), map_(config.map) {
    config_.max_threads = std::clamp(config_.max_threads, 1, 4);
}

LaserOdometry::~LaserOdometry() {
    {
        std::lock_guard<std::mutex> lock(jobs_mutex_);
        stopping_ = true;
    }
    jobs_cv_.notify_all();
    for (auto& w : workers_) {
        if (w->thread.joinable()) {
            w->thread.join();
        }
    }
}

SweepResult LaserOdometry::run(const Sweep& sweep,
                               const std::optional<std::vector<PosePrior>>& priors_in, int thread,
                               const MergeGate& gate) {
    const auto t_total = std::chrono::steady_clock::now();
    SweepResult out;
    out.sweep_index = sweep.index;
    out.matcher_thread = thread;

    auto t0 = std::chrono::steady_clock::now();
    const auto shared_features =
        std::make_shared<const FeatureCloud>(extractFeatures(sweep, config_.features));
    const FeatureCloud& features = *shared_features;
    out.features = shared_features;
    out.edges = features.edges.size();
    out.planars = features.planars.size();
    out.features_ms = msSince(t0);

    t0 = std::chrono::steady_clock::now();
    std::vector<PosePrior> priors;
    LocalMap local(1.0, 1);
    {
        std::lock_guard<std::mutex> lock(map_mutex_);
        if (priors_in && !priors_in->empty()) {
            priors = *priors_in;
        } else {
            // eq. (16): T_m = T_{m-1} * (odometry motion from m-1 to m); with parallel matchers
            // m-1 may still be running, then the latest refined sweep stands in for it.
            PosePrior p;
            p.T_world_body = have_refined_ ? T_world_refined_ * T_world_refined_odom_.inverse() *
                                                 sweep.T_world_start_odom
                                           : sweep.T_world_start_odom;
            p.information.setZero();
            p.information.diagonal().head<3>().setConstant(
                1.0 / (config_.prior_sigma_rot_rad * config_.prior_sigma_rot_rad));
            p.information.diagonal().tail<3>().setConstant(
                1.0 / (config_.prior_sigma_trans_m * config_.prior_sigma_trans_m));
            priors.push_back(p);
        }
        out.T_world_prior = priors.front().T_world_body;
        map_.recenter(out.T_world_prior.translation());
        local = map_.extract(transformed(out.T_world_prior, features.edges),
                             transformed(out.T_world_prior, features.planars));
        out.map_sweeps = map_sweeps_;
    }
    out.local_map_points = local.size(FeatureKind::kEdge) + local.size(FeatureKind::kPlanar);
    out.extract_ms = msSince(t0);

    t0 = std::chrono::steady_clock::now();
    out.first_sweep = out.map_sweeps == 0;
    if (out.first_sweep) {
        out.match.T_world_body = out.T_world_prior;
        out.match.degeneracy = analyzeDegeneracy(Matrix6d::Zero(), 1.0);
    } else {
        out.match = matcher_.match(features, local, priors);
    }
    out.match_ms = msSince(t0);

    out.pose.t_host = sweep.t_start;
    out.pose.T_world_body = out.match.T_world_body;
    const Eigen::Matrix3d R = out.match.T_world_body.linear();
    out.solved_projector_world =
        out.first_sweep ? Matrix6d::Zero() : bodyToWorldAxes(out.match.degeneracy.projection, R);
    out.pose.solved_dof_mask = maskFromProjector(out.solved_projector_world);
    out.pose.covariance = bodyToWorldAxes(out.match.covariance, R);
    out.pose.source = PoseSource::kScanMatching;

    t0 = std::chrono::steady_clock::now();
    out.merged = !gate || gate(out);
    if (out.merged) {
        std::lock_guard<std::mutex> lock(map_mutex_);
        // Merge the scan into the map at its refined pose (6.3), at constant density.
        map_.insert(FeatureKind::kEdge, transformed(out.match.T_world_body, features.edges));
        map_.insert(FeatureKind::kPlanar, transformed(out.match.T_world_body, features.planars),
                    transformed(out.match.T_world_body, features.planar_origins));
        ++map_sweeps_;
        if (!have_refined_ || sweep.index >= refined_index_) {
            have_refined_ = true;
            refined_index_ = sweep.index;
            T_world_refined_ = out.match.T_world_body;
            T_world_refined_odom_ = sweep.T_world_start_odom;
        }
    }
    out.merge_ms = msSince(t0);

    out.total_ms = msSince(t_total);
    return out;
}

SweepResult LaserOdometry::process(const Sweep& sweep,
                                   const std::optional<std::vector<PosePrior>>& priors,
                                   const MergeGate& gate) {
    return run(sweep, priors, 0, gate);
}

void LaserOdometry::startWorkers() {
    if (!workers_.empty()) {
        return;
    }
    for (int i = 0; i < config_.max_threads; ++i) {
        workers_.push_back(std::make_unique<Worker>());
    }
    for (int i = 0; i < config_.max_threads; ++i) {
        workers_[static_cast<std::size_t>(i)]->thread = std::thread([this, i] { workerLoop(i); });
    }
}

void LaserOdometry::submit(Sweep sweep, std::optional<std::vector<PosePrior>> priors) {
    {
        std::lock_guard<std::mutex> lock(jobs_mutex_);
        startWorkers();
        in_flight_[sweep.index] = 1;
        // The first idle matcher takes it: processing stays on as few threads as possible (6.4).
        for (auto& w : workers_) {
            if (!w->job) {
                w->job = Job{std::move(sweep), std::move(priors)};
                jobs_cv_.notify_all();
                return;
            }
        }
        queued_.push_back(Job{std::move(sweep), std::move(priors)});
        if (queued_.size() > config_.max_queued) {
            // Every matcher is behind by more than the queue: drop the oldest waiting sweep
            // rather than fall further behind real time.
            in_flight_.erase(queued_.front().sweep.index);
            queued_.pop_front();
            ++dropped_;
        }
    }
    jobs_cv_.notify_all();
}

void LaserOdometry::workerLoop(int id) {
    auto& self = *workers_[static_cast<std::size_t>(id)];
    std::unique_lock<std::mutex> lock(jobs_mutex_);
    while (true) {
        jobs_cv_.wait(lock, [&] { return stopping_ || self.job.has_value(); });
        if (stopping_) {
            return;
        }
        Job job = std::move(*self.job);
        lock.unlock();
        SweepResult result = run(job.sweep, job.priors, id);
        lock.lock();
        finished_[result.sweep_index] = std::move(result);
        in_flight_.erase(job.sweep.index);
        self.job.reset();
        if (!queued_.empty()) {
            self.job = std::move(queued_.front());
            queued_.pop_front();
        }
        done_cv_.notify_all();
    }
}

std::vector<SweepResult> LaserOdometry::poll() {
    std::lock_guard<std::mutex> lock(jobs_mutex_);
    std::vector<SweepResult> out;
    const std::uint64_t limit = in_flight_.empty() ? UINT64_MAX : in_flight_.begin()->first;
    while (!finished_.empty() && finished_.begin()->first < limit) {
        out.push_back(std::move(finished_.begin()->second));
        finished_.erase(finished_.begin());
    }
    return out;
}

std::vector<SweepResult> LaserOdometry::drain() {
    {
        std::unique_lock<std::mutex> lock(jobs_mutex_);
        done_cv_.wait(lock, [&] { return in_flight_.empty(); });
    }
    return poll();
}

std::uint64_t LaserOdometry::droppedSweeps() const {
    std::lock_guard<std::mutex> lock(jobs_mutex_);
    return dropped_;
}

std::vector<Eigen::Vector3f> LaserOdometry::mapPoints() const {
    std::lock_guard<std::mutex> lock(map_mutex_);
    std::vector<Eigen::Vector3f> pts = map_.points(FeatureKind::kEdge);
    const std::vector<Eigen::Vector3f> planars = map_.points(FeatureKind::kPlanar);
    pts.insert(pts.end(), planars.begin(), planars.end());
    return pts;
}

FeatureMapPoints LaserOdometry::featureMap() const {
    std::lock_guard<std::mutex> lock(map_mutex_);
    return map_.featurePoints();
}

VoxelMapStats LaserOdometry::mapStats() const {
    std::lock_guard<std::mutex> lock(map_mutex_);
    return map_.stats();
}

}  // namespace handscan::scan
