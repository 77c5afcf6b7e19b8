#include "handscan/localize/localizer.hpp"

#include <algorithm>
#include <chrono>
#include <utility>

#include "handscan/core/se3.hpp"
#include "handscan/scan/voxel_key.hpp"

namespace handscan::localize {
namespace {

// The heading of a body's x axis on the horizontal plane (rad).
double headingOf(const Eigen::Matrix3d& R) {
    const Eigen::Vector3d x = R.col(0);
    return std::atan2(x.y(), x.x());
}

}  // namespace

Eigen::Isometry3d priorFromOdomAtHint(const Eigen::Isometry3d& hint,
                                      const Eigen::Isometry3d& T_odom_body) {
    // Both worlds are gravity aligned: only a turn about the vertical and a shift between them.
    const double dyaw = headingOf(hint.linear()) - headingOf(T_odom_body.linear());
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(dyaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    T.translation() = hint.translation() - T.linear() * T_odom_body.translation();
    return T;
}

Localizer::Localizer(const LocalizerConfig& config, std::shared_ptr<const PriorMap> prior,
                     std::optional<Eigen::Isometry3d> hint)
    : config_(config),
      prior_(std::move(prior)),
      hint_(std::move(hint)),
      stack_(config.stack),
      seen_(prior_->seenSpace()) {
    seen_.clear();
}

Localizer::~Localizer() {
    cancel_.store(true, std::memory_order_relaxed);
    if (running_.valid()) running_.wait();
}

LockState Localizer::lockState() const {
    if (locked_) return LockState::kLocked;
    // A place found that the next search is to confirm: still searching, not "not found".
    if (unconfirmed_) return LockState::kSearching;
    return stats_.lock_attempts > (running_.valid() ? 1u : 0u) ? LockState::kNotLocked
                                                               : LockState::kSearching;
}

bool Localizer::addSweep(TimeNs t_start, const Eigen::Isometry3d& T_odom_body,
                         std::shared_ptr<const scan::FeatureCloud> features) {
    if (!have_first_) {
        // The hint (or the prior session's start) is where this session's first sweep began.
        have_first_ = true;
        T_prior_odom_ = priorFromOdomAtHint(hint_ ? *hint_ : prior_->start(), T_odom_body);
        first_position_odom_ = T_odom_body.translation();
        last_attempt_t_ = t_start;
    }
    newest_t_ = t_start;
    stack_.add(t_start, T_odom_body, std::move(features));
    bool changed = false;
    if (running_.valid()) {
        const bool ready = config_.apply == MatchApply::kAtNextSweep ||
                           running_.wait_for(std::chrono::seconds(0)) == std::future_status::ready;
        if (!ready) return false;  // the next match waits for this one
        changed = apply(running_.get());
    }
    // A full stack before each match (the first one too: one still sweep sees little).
    if (t_start - last_attempt_t_ >= static_cast<TimeNs>(config_.period_s * 1e9)) {
        last_attempt_t_ = t_start;
        launch();
    }
    return changed;
}

bool Localizer::placeAt(const Eigen::Isometry3d& hint) {
    if (locked_) return false;
    hint_ = hint;
    have_first_ = false;  // the next sweep is where the hint holds; a full stack before a search
    return true;
}

bool Localizer::settle() { return running_.valid() && apply(running_.get()); }

void Localizer::launch() {
    running_on_ = {stack_.newestTime(), stack_.newestPose()};
    ++stats_.attempts;
    if (!locked_) ++stats_.lock_attempts;
    // The thread gets copies (the stack's sweeps are shared, immutable) and the prior map, which
    // is read-only; the localizer waits for it before it goes.
    const Eigen::Isometry3d T_start = T_prior_odom_ * running_on_.T_odom_new;
    std::optional<Eigen::Vector3d> pivot;
    if (config_.search_turns_about_first) pivot = T_prior_odom_ * first_position_odom_;
    running_ =
        std::async(std::launch::async, [this, stack = stack_, T_start, pivot, lock = !locked_] {
            const scan::FeatureCloud stacked = stack.stack();
            return lock ? searchLock(config_, *prior_, stacked, T_start, &cancel_, pivot)
                        : trackPrior(config_, *prior_, stacked, T_start);
        });
}

bool Localizer::confirmed(const PriorMatchOutcome& o) {
    const bool candidate = config_.confirm_margin > 0.0 && !o.cancelled &&
                           o.on_map >= config_.lock_min_on_map &&
                           o.on_map - o.runner_up >= config_.confirm_margin;
    if (!candidate) {
        unconfirmed_.reset();
        return false;
    }
    const Eigen::Isometry3d T = o.T_prior_new * running_on_.T_odom_new.inverse();
    const std::optional<Eigen::Isometry3d> before = std::exchange(unconfirmed_, T);
    if (!before) return false;
    const auto [dm, ddeg] = separation(*before, T);
    return dm <= config_.distinct_m && ddeg <= config_.distinct_deg;
}

bool Localizer::apply(const PriorMatchOutcome& o) {
    stats_.cpu_ms += o.cpu_ms;
    stats_.max_attempt_ms = std::max(stats_.max_attempt_ms, o.cpu_ms);
    stats_.max_apply_delay_s =
        std::max(stats_.max_apply_delay_s, toSeconds(newest_t_ - running_on_.t));
    stats_.last_on_map = o.on_map;
    if (o.kind == MatchKind::kLock) {
        stats_.lock_on_map = o.on_map;
        stats_.lock_runner_up = o.runner_up;
    }
    const bool alone = o.accepted && !(o.kind == MatchKind::kLock && config_.confirm_always);
    if (!alone && !(o.kind == MatchKind::kLock && confirmed(o))) {
        if (o.kind == MatchKind::kTrack) ++stats_.rejected_updates;
        return false;
    }
    if (o.kind == MatchKind::kLock) {
        locked_ = true;
        stats_.t_lock = running_on_.t;
    } else {
        ++stats_.updates;
        stats_.max_correction_m = std::max(stats_.max_correction_m, o.correction_m);
        stats_.sum_correction_m += o.correction_m;
    }
    // The stacked cloud's pose in the prior map: the odometry's world in it (eq. of section 9's
    // transform integration), valid for every pose of that world, earlier or later.
    T_prior_odom_ = o.T_prior_new * running_on_.T_odom_new.inverse();
    T_prior_odom_.linear() = orthonormalize(T_prior_odom_.linear());
    stats_.points_checked += o.points_checked;
    stats_.changed_points += o.changed_points;
    stats_.new_points += o.new_points;
    for (const auto& [cell, n] : o.change_cells) {
        change_cells_[cell].points += n;
        ++change_cells_[cell].matches;
    }
    seen_.add(o.seen_cells);
    return true;
}

std::vector<ChangeCell> Localizer::changes() const {
    std::vector<ChangeCell> out;
    const auto min_points = static_cast<std::uint64_t>(config_.change_cell_min_points);
    auto centre = [&](const std::tuple<int, int, int>& k) {
        const auto [x, y, z] = k;
        return Eigen::Vector3d((Eigen::Vector3d(x, y, z).array() + 0.5) * config_.change_cell_m);
    };
    for (const auto& [k, n] : change_cells_) {
        if (n.points < min_points ||
            n.matches < static_cast<std::uint64_t>(config_.change_cell_min_matches))
            continue;
        out.push_back({centre(k), ChangeKind::kAppeared, n.points, n.matches});
    }
    // Vanished: prior points whose place this session's rays went through, into their surface.
    const std::vector<Eigen::Vector3f>& planars = prior_->points().planars;
    const std::vector<Eigen::Vector3f>& normals = prior_->planarNormals();
    if (seen_.empty()) return out;
    std::map<std::tuple<int, int, int>, std::uint64_t> vanished;
    for (std::size_t i = 0; i < planars.size() && i < normals.size(); ++i) {
        if (!normals[i].allFinite()) continue;
        const Eigen::Vector3d p = planars[i].cast<double>();
        if (!seen_.seenThrough(p, normals[i].cast<double>())) continue;
        const scan::VoxelKey k = scan::voxelOf(p, config_.change_cell_m);
        ++vanished[{k.x(), k.y(), k.z()}];
    }
    for (const auto& [k, n] : vanished)
        if (n >= min_points) out.push_back({centre(k), ChangeKind::kVanished, n, 0});
    return out;
}

}  // namespace handscan::localize
