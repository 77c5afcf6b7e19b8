// `handscan calibrate`: self-calibration from an ordinary walk, no target. Each round replays the
// recording with the current calibration (the one pipeline, as `handscan replay` runs it) to get
// the scan-matched trajectory, keeps the sweeps the tracking monitor trusted, and solves the
// half-revolution consistency (half_revolution_consistency.hpp) for the spin-observable
// parameters (spin_solver.hpp); the next round replays with the result, so trajectory and
// calibration improve together. A parameter the recording does not determine keeps its starting
// value and is named. The last replay, with the written calibration, gives the "after" figures.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "handscan/calibrate/camchain_check.hpp"
#include "handscan/core/config.hpp"
#include "handscan/core/status.hpp"
#include "handscan/spin_calibration/half_revolution_consistency.hpp"
#include "handscan/spin_calibration/spin_solver.hpp"

namespace handscan::calibrate {

struct SelfCalibrationOptions {
    std::string recording;
    std::string start_calibration;  // default: <config dir>/calibration.yaml
    std::string device_config;      // default: <config dir>/device.yaml
    std::string out;                // the calibration.yaml to write
    std::string work_dir;           // the rounds' replays (default: a temporary folder, removed)
    int max_rounds = 4;
    ObservationOptions observations;
    AssociationOptions association;
    SolverOptions solver;
    std::function<void(const std::string&)> log;  // one line per step
    // The camchain checked against the recording's camera frames with the final calibration
    // (camchain_check.hpp); only that (one replay with START, nothing written): camchain_only.
    bool check_camchain = true;
    bool camchain_only = false;
    CamchainCheckOptions camchain;
};

struct ParameterEstimate {
    const char* name = "";
    const char* unit = "";
    double start = 0.0;  // in `unit`
    double value = 0.0;
    double std = 0.0;  // inf when not estimated
    bool written = false;
};

struct SelfCalibrationReport {
    Calibration calibration;  // as written
    std::vector<ParameterEstimate> parameters;
    std::vector<std::string> notes;  // the parameters the data did not determine, and why
    int rounds = 0;
    double consistency_before_m = 0.0;  // robust std of half-to-half distances, START
    double consistency_after_m = 0.0;   // ... with the written calibration
    std::size_t residuals_before = 0, residuals_after = 0;
    double sweeps_ok_before = 0.0, sweeps_ok_after = 0.0;  // fraction the tracking trusted
    // Per camera with frames in the recording (none without cameras, or when it could not run:
    // then camchain_note says why).
    CamchainCheck camchain;
    std::string camchain_note;
};

Result<SelfCalibrationReport> selfCalibrate(const SelfCalibrationOptions& options);

}  // namespace handscan::calibrate
