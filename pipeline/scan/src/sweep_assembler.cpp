#include "handscan/scan/sweep_assembler.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "handscan/core/se3.hpp"

namespace handscan::scan {

Eigen::Isometry3d SpinGeometry::bodyFromLaser(double encoder_angle_rad) const {
    Eigen::Isometry3d spin = Eigen::Isometry3d::Identity();
    spin.linear() =
        Eigen::AngleAxisd(encoder_angle_rad - encoder_zero_offset_rad, Eigen::Vector3d::UnitZ())
            .toRotationMatrix();
    return T_body_shaftbase * spin * T_shaft_laser;
}

SweepAssembler::SweepAssembler(const SpinGeometry& geometry, const SweepAssemblerConfig& config,
                               PoseAtFn pose_at)
    : geometry_(geometry), config_(config), pose_at_(std::move(pose_at)) {
    if (!pose_at_) {
        pose_at_ = [](TimeNs) { return Eigen::Isometry3d::Identity(); };
    }
}

Status SweepAssembler::addEncoder(const EncoderSample& sample) {
    if (!encoder_.empty() && sample.t_host <= encoder_.back().t_host) {
        ++stats_.encoder_out_of_order;
        return {StatusCode::kInvalidArgument,
                "SweepAssembler: encoder sample at t=" + std::to_string(sample.t_host) +
                    " ns is not after the previous one (" + std::to_string(encoder_.back().t_host) +
                    " ns); dropped - check the CAN receive timestamps"};
    }
    encoder_.push_back(sample);
    processReadyScans(false);
    return Status::ok();
}

Status SweepAssembler::addScan(const LaserScan& scan) {
    if (scan.ranges_m.empty()) {
        return {StatusCode::kInvalidArgument,
                "SweepAssembler: scan at t=" + std::to_string(scan.t_host) + " ns has no steps"};
    }
    if (scan.step_period_ns < 0 || scan.angle_increment_rad == 0.0) {
        return {StatusCode::kInvalidArgument,
                "SweepAssembler: scan at t=" + std::to_string(scan.t_host) +
                    " ns has no step period / angle increment; the driver must fill them"};
    }
    if (!scan.intensities.empty() && scan.intensities.size() != scan.ranges_m.size()) {
        return {StatusCode::kInvalidArgument,
                "SweepAssembler: scan at t=" + std::to_string(scan.t_host) + " ns has " +
                    std::to_string(scan.intensities.size()) + " intensities for " +
                    std::to_string(scan.ranges_m.size()) + " ranges"};
    }
    pending_.push_back(scan);
    processReadyScans(false);
    return Status::ok();
}

std::vector<Sweep> SweepAssembler::takeSweeps() {
    std::vector<Sweep> out;
    out.swap(done_);
    return out;
}

Sweep SweepAssembler::flush() {
    processReadyScans(true);
    Sweep out;
    if (current_ && !current_->points.empty()) {
        out = std::move(*current_);
        ++stats_.sweeps;
    }
    current_.reset();
    return out;
}

void SweepAssembler::processReadyScans(bool force) {
    while (!pending_.empty()) {
        const LaserScan& scan = pending_.front();
        const TimeNs t_last = scan.stepTime(scan.size() - 1);
        const bool covered = !encoder_.empty() && encoder_.back().t_host >= t_last;
        const bool stale = pending_.back().t_host - t_last > config_.max_encoder_latency_ns;
        if (!covered && !force && !stale) {
            break;
        }
        if (!covered) {
            ++stats_.dropped_scans_late;
        }
        processScan(scan);
        pending_.pop_front();
    }
    // Keep the encoder samples a pending scan, or one still in flight from the laser (up to the
    // latency limit behind the encoder), can need.
    if (encoder_.empty()) {
        return;
    }
    TimeNs oldest_needed = encoder_.back().t_host - config_.max_encoder_latency_ns;
    if (!pending_.empty()) {
        oldest_needed = std::min(oldest_needed, pending_.front().t_host);
    }
    while (encoder_.size() > 2 && encoder_[1].t_host <= oldest_needed) {
        encoder_.pop_front();
    }
}

std::optional<double> SweepAssembler::encoderAngleAt(TimeNs t) const {
    if (encoder_.empty() || t < encoder_.front().t_host || t > encoder_.back().t_host) {
        return std::nullopt;
    }
    auto it = std::lower_bound(encoder_.begin(), encoder_.end(), t,
                               [](const EncoderSample& s, TimeNs v) { return s.t_host < v; });
    if (it->t_host == t) {
        return it->angle_rad;
    }
    const EncoderSample& b = *it;
    const EncoderSample& a = *(it - 1);
    if (b.t_host - a.t_host > config_.max_encoder_gap_ns) {
        return std::nullopt;
    }
    const double s = static_cast<double>(t - a.t_host) / static_cast<double>(b.t_host - a.t_host);
    return a.angle_rad + s * (b.angle_rad - a.angle_rad);
}

std::int64_t SweepAssembler::boundaryIndex(double encoder_angle_rad) const {
    const double period = config_.boundary == SweepBoundary::kHalfRevolution ? M_PI : 2.0 * M_PI;
    return static_cast<std::int64_t>(
        std::floor((encoder_angle_rad - geometry_.encoder_zero_offset_rad) / period));
}

void SweepAssembler::startSweep(TimeNs t) {
    current_.emplace();
    current_->t_start = t;
    current_->t_end = t;
    current_->index = next_index_++;
    current_->T_world_start_odom = pose_at_(t);
    T_start_world_ = current_->T_world_start_odom.inverse();
}

void SweepAssembler::closeSweep() {
    if (current_ && !current_->points.empty()) {
        done_.push_back(std::move(*current_));
        ++stats_.sweeps;
    }
    current_.reset();
}

void SweepAssembler::processScan(const LaserScan& scan) {
    ++stats_.scans;
    const std::size_t n = scan.size();
    // Sample the motion estimate along the scan (the IMU runs at 200 Hz; finer is pointless).
    const TimeNs t0 = scan.t_host;
    const TimeNs duration = scan.stepTime(n - 1) - t0;
    const TimeNs dt = std::max<TimeNs>(1, config_.pose_sample_period_ns);
    const std::size_t samples = static_cast<std::size_t>(duration / dt) + 2;
    std::vector<Eigen::Isometry3d> poses(samples);
    for (std::size_t k = 0; k < samples; ++k) {
        poses[k] = pose_at_(t0 + static_cast<TimeNs>(k) * dt);
    }
    auto poseAt = [&](TimeNs t) {
        const double u = static_cast<double>(t - t0) / static_cast<double>(dt);
        const std::size_t k = std::min(samples - 2, static_cast<std::size_t>(std::max(0.0, u)));
        return interpolate(poses[k], poses[k + 1],
                           std::clamp(u - static_cast<double>(k), 0.0, 1.0));
    };

    bool line_open = false;
    auto closeLine = [&]() {
        if (line_open && current_) {
            current_->lines.back().end = current_->points.size();
            if (current_->lines.back().end == current_->lines.back().begin) {
                current_->lines.pop_back();
            }
        }
        line_open = false;
    };
    for (std::size_t i = 0; i < n; ++i) {
        const float r = scan.ranges_m[i];
        if (!std::isfinite(r) || r < config_.min_range_m || r > config_.max_range_m) {
            ++stats_.dropped_invalid_range;
            continue;
        }
        const TimeNs t = scan.stepTime(i);
        const std::optional<double> angle = encoderAngleAt(t);
        if (!angle) {
            ++stats_.dropped_no_encoder;
            continue;
        }
        const std::int64_t boundary = boundaryIndex(*angle);
        if (current_ && boundary != current_boundary_) {
            closeLine();
            closeSweep();
        }
        if (!current_) {
            startSweep(t);
            current_boundary_ = boundary;
        }
        if (!line_open) {
            current_->lines.push_back(
                {current_->points.size(), current_->points.size(), scan.angle_increment_rad});
            line_open = true;
        }
        const double a = scan.stepAngle(i);
        const Eigen::Vector3d p_laser(r * std::cos(a), r * std::sin(a), 0.0);
        const Eigen::Isometry3d T_body_laser = geometry_.bodyFromLaser(*angle);
        const Eigen::Isometry3d T_world_body = poseAt(t);
        SweepPoint pt;
        pt.p_body = T_body_laser * p_laser;
        pt.origin_body = T_body_laser.translation();
        pt.t = t;
        pt.p_start = T_start_world_ * (T_world_body * pt.p_body);
        pt.origin_start = T_start_world_ * (T_world_body * pt.origin_body);
        pt.range_m = r;
        pt.intensity = scan.intensities.empty() ? 0.0F : static_cast<float>(scan.intensities[i]);
        pt.step = static_cast<std::uint16_t>(static_cast<int>(i) + scan.first_step);
        current_->points.push_back(pt);
        current_->t_end = t;
        ++stats_.points;
    }
    closeLine();
}

}  // namespace handscan::scan
