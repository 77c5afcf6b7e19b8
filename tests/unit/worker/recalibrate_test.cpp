// A calibration installed while the daemon runs (the UI's "calibrate") is used from the next scan:
// not by the scan in progress, and then with its clocks as offsets from the drivers' stamps,
// superseding the clocks the previous scan tracked.
#include <gtest/gtest.h>

#include "handscan/worker/pipeline_worker.hpp"

namespace handscan::worker {
namespace {

class NullSink final : public WorkerSink {
public:
    Status pose(const PoseEstimate&) override { return Status::ok(); }
    Status trajectoryPose(const PoseEstimate&) override { return Status::ok(); }
    Status sweep(const lio::RegisteredSweep&, std::span<const journal::MapPoint>) override {
        return Status::ok();
    }
};

TEST(PipelineWorkerRecalibrate, TheNewCalibrationAndItsClocksApplyFromTheNextScan) {
    WorkerConfig config;
    config.colourise = false;
    NullSink sink;
    const Calibration factory;
    PipelineWorker worker(config, factory, sink);
    EXPECT_EQ(worker.lio().clocks().imuOffset(), 0);

    Calibration field = factory;
    field.T_shaft_laser.translation() = Eigen::Vector3d(0.0, 0.01, 0.02);
    field.encoder_zero_offset_rad = 0.004;
    worker.recalibrate(field, 0.0025, -0.0015);
    // The scan in progress keeps what it started with.
    EXPECT_TRUE(worker.calibration().T_shaft_laser.isApprox(factory.T_shaft_laser));
    EXPECT_EQ(worker.lio().clocks().imuOffset(), 0);
    EXPECT_EQ(worker.lio().clocks().encoderOffset(), 0);

    worker.reset();  // the next scan
    EXPECT_TRUE(worker.calibration().T_shaft_laser.isApprox(field.T_shaft_laser));
    EXPECT_EQ(worker.calibration().encoder_zero_offset_rad, 0.004);
    EXPECT_EQ(worker.lio().clocks().imuOffset(), fromSeconds(0.0025));
    EXPECT_EQ(worker.lio().clocks().encoderOffset(), fromSeconds(-0.0015));

    worker.reset();  // and the one after: still the new calibration, not the factory's clocks
    EXPECT_TRUE(worker.calibration().T_shaft_laser.isApprox(field.T_shaft_laser));
    EXPECT_EQ(worker.lio().clocks().imuOffset(), fromSeconds(0.0025));
}

}  // namespace
}  // namespace handscan::worker
