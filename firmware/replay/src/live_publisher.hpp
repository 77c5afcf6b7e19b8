// Publishes a replay into the live-map shared memory exactly as the daemon does: 200 Hz poses,
// display points (voxel-downsampled, only voxels not shown yet), and the status block, so the
// touch-screen UI can show any recording.
#pragma once

#include <memory>

#include "handscan/lio/laser_inertial_odometry.hpp"
#include "handscan/replay/stream_decoders.hpp"
#include "handscan/shm/display_voxel_filter.hpp"
#include "handscan/shm/live_map_writer.hpp"
#include "replay_outputs.hpp"

namespace handscan::replay {

class LivePublisher {
public:
    // `storage_dir`: where the replay writes (its free space is shown as the device's storage).
    static Result<std::unique_ptr<LivePublisher>> create(const std::string& name, std::string storage_dir);

    void pose(const PoseEstimate& pose);
    void sweep(const lio::RegisteredSweep& sweep, const lio::LaserInertialOdometry& pipeline);
    void status(const lio::LaserInertialOdometry& pipeline, const StreamCounters& hokuyo, const StreamCounters& xsens,
                const StreamCounters& encoder, const ReplayOutputs& outputs, bool finished = false);
    void heartbeat() { writer_->heartbeat(); }

private:
    LivePublisher(std::unique_ptr<shm::LiveMapWriter> writer, std::string storage_dir)
        : writer_(std::move(writer)), storage_dir_(std::move(storage_dir)) {}

    std::unique_ptr<shm::LiveMapWriter> writer_;
    std::string storage_dir_;
    shm::DisplayVoxelFilter shown_voxels_;  // the touch screen shows one point per 5 cm voxel
    TimeNs first_pose_t_ = 0;
    TimeNs last_pose_t_ = 0;
    std::uint8_t last_solved_mask_ = 0x3F;
};

}  // namespace handscan::replay
