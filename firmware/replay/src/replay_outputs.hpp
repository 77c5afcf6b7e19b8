// What a replay leaves in its output directory: trajectory.tum, map.ply and stats.json.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "handscan/core/call_timer.hpp"
#include "handscan/core/samples.hpp"
#include "handscan/core/status.hpp"
#include "handscan/core/stream_counters.hpp"
#include "handscan/export/safe_file.hpp"
#include "handscan/journal/sweep_record.hpp"
#include "handscan/lio/laser_inertial_odometry.hpp"
#include "handscan/localize/localizer.hpp"
#include "handscan/replay/replay_engine.hpp"
#include "handscan/replay/tiled_voxel_map.hpp"
#include "handscan/worker/calibration_check.hpp"
#include "handscan/worker/visual_stage.hpp"

namespace handscan::replay {

struct StatsInputs {
    const ReplayReport& report;
    std::map<std::string, CallStats> calls;
    const lio::LaserInertialOdometry& pipeline;
    const worker::VisualStage* visual = nullptr;  // null: no visual-inertial odometry
    StreamCounters hokuyo, xsens, encoder;
    double peak_rss_mib = 0.0;
    bool recording_truncated = false;
    std::size_t recording_dropped_regions = 0;
    const localize::Localizer* localizer = nullptr;  // null: not continuing a prior scan
    std::uint64_t sweeps_before_lock = 0;            // dropped before the lock
    std::uint64_t sweeps_held = 0;                   // held and handed on at the lock
    const worker::CalibrationCheck* calibration_check = nullptr;
};

class ReplayOutputs {
public:
    ReplayOutputs(std::string out_dir, TiledMapConfig map);

    // Opens trajectory.tum (written as the poses come, committed by writeTrajectory()).
    [[nodiscard]] Status open();
    [[nodiscard]] Status addPose(const PoseEstimate& pose);
    // `points`: the sweep's registered points as journaled (coloured where the camera saw them),
    // into map.ply. Fails only when the map cannot flush tiles to its spill file (disk full,
    // write error).
    [[nodiscard]] Status addSweep(const lio::RegisteredSweep& sweep,
                                  std::span<const journal::MapPoint> points);
    // Every sweep's record (also those kept out of the map), for stats.json's per_sweep.
    void addSweepRecord(const journal::SweepRecord& record) { sweeps_.push_back(record); }

    Status writeTrajectory();
    // Streams the map into map.ply (once: the map is consumed).
    Result<std::uint64_t> writeMap();
    Result<std::string> writeStats(const StatsInputs& in) const;

    std::uint64_t poses() const { return poses_; }
    double distance_m() const { return distance_m_; }
    std::uint64_t registeredPoints() const { return registered_points_; }
    const std::vector<journal::SweepRecord>& sweeps() const { return sweeps_; }

private:
    std::string dir_;
    std::unique_ptr<exporter::SafeFileWriter> trajectory_;
    std::string tum_;  // lines not yet handed to trajectory_
    std::uint64_t poses_ = 0;
    double distance_m_ = 0.0;
    Eigen::Vector3d last_position_ = Eigen::Vector3d::Zero();
    TiledVoxelMap map_;  // map.ply within a memory budget
    std::uint64_t registered_points_ = 0;
    std::vector<journal::SweepRecord> sweeps_;
};

}  // namespace handscan::replay
