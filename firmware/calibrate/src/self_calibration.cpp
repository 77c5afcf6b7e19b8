#include "handscan/calibrate/self_calibration.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "handscan/calibrate/calibration_writer.hpp"
#include "handscan/calibrate/gyro_alignment.hpp"
#include "handscan/calibrate/recorded_observations.hpp"
#include "handscan/core/se3.hpp"
#include "handscan/replay/replay_engine.hpp"
#include "handscan/tum/tum_file.hpp"

namespace handscan::calibrate {
namespace {

namespace fs = std::filesystem;
using C = SpinCorrection;

struct Replayed {
    tum::Trajectory trajectory;
    std::vector<MatchedSweepPose> matched;               // the trusted sweeps' matched poses
    std::vector<std::pair<double, double>> untrusted_s;  // sweeps not "ok" (rejected or lost)
    double ok_fraction = 0.0;
};

// The tracking monitor's verdicts: a sweep it did not trust leaves its span out.
Result<std::vector<std::pair<double, double>>> untrustedSpans(
    const std::string& stats_json, double* ok_fraction, std::vector<MatchedSweepPose>& matched) {
    std::ifstream is(stats_json);
    nlohmann::json j = nlohmann::json::parse(is, nullptr, false);
    if (j.is_discarded() || !j.contains("per_sweep"))
        return Status{StatusCode::kInvalidArgument,
                      stats_json + ": not the stats.json replay writes (no per_sweep)"};
    const auto& sweeps = j["per_sweep"];
    std::vector<std::pair<double, double>> out;
    std::size_t ok = 0;
    for (std::size_t i = 0; i < sweeps.size(); ++i) {
        const double t0 = sweeps[i].value("t_start_s", 0.0);
        const double t1 = i + 1 < sweeps.size() ? sweeps[i + 1].value("t_start_s", 0.0) : 1e18;
        if (sweeps[i].value("tracking", "") == "ok") {
            ++ok;
            const auto& pq = sweeps[i]["pose_xyz_qxyzw"];
            if (pq.is_array() && pq.size() == 7)
                matched.push_back({sweeps[i].value("index", std::uint64_t{0}), t0,
                                   Eigen::Quaterniond(pq[6].get<double>(), pq[3].get<double>(),
                                                      pq[4].get<double>(), pq[5].get<double>())
                                       .normalized()});
        } else
            out.emplace_back(t0, t1);
    }
    *ok_fraction =
        sweeps.empty() ? 0.0 : static_cast<double>(ok) / static_cast<double>(sweeps.size());
    return out;
}

Result<Replayed> replayWith(const SelfCalibrationOptions& o, const std::string& calibration_yaml,
                            const std::string& dir) {
    replay::ReplayOptions r;
    r.recording = o.recording;
    r.out_dir = dir;
    r.fast = true;
    r.calibration = calibration_yaml;
    r.device_config = o.device_config;
    r.colourise = false;
    r.write_journal = false;
    // The trajectory under the calibration being measured: clocks tracked online would already
    // have turned part of the encoder's error out of the sweeps.
    r.track_clocks = false;
    r.check_calibration = false;  // it is the calibration being measured
    auto report = replay::runReplay(r);
    if (!report.isOk()) return report.status();
    Replayed out;
    auto tr = tum::readTum(dir + "/trajectory.tum");
    if (!tr.isOk()) return tr.status();
    out.trajectory = std::move(*tr);
    auto spans = untrustedSpans(
        report->stats_json_path.empty() ? dir + "/stats.json" : report->stats_json_path,
        &out.ok_fraction, out.matched);
    if (!spans.isOk()) return spans.status();
    out.untrusted_s = std::move(*spans);
    return out;
}

double latencyMs(const std::optional<double>& calibrated, double device_default) {
    return calibrated ? *calibrated : device_default;
}

// The round's result: the model's geometry as solved, the time offsets only where determined.
Calibration applied(const SpinModel& m, const DeviceConfig& device, const SpinSolution& s,
                    std::vector<std::string>& notes) {
    Calibration out = m.base;
    auto shift = [&](std::optional<double>& field, double device_ms, double offset_s,
                     const char* what) {
        double ms = latencyMs(field, device_ms) + offset_s * 1e3;
        if (ms < 0.0) {
            notes.push_back(fmt::format("{}: found {:.3f} ms, below zero; written as 0", what, ms));
            ms = 0.0;
        }
        field = ms;
    };
    if (s.solved[C::kImuTime])
        shift(out.xsens_frame_latency_ms, device.xsens.frame_latency_ms, m.imu_time_s,
              "IMU latency");
    if (s.solved[C::kEncoderTime])
        shift(out.motor_tpdo_latency_ms, device.motor.tpdo_latency_ms, m.encoder_time_s,
              "encoder latency");
    return out;
}

Calibration resetRefused(const Calibration& current, const Calibration& start,
                         const SpinMask& refused) {
    Calibration out = current;
    Eigen::Vector3d phi =
        logSO3(current.T_shaft_laser.linear() * start.T_shaft_laser.linear().transpose());
    if (refused[C::kRollShaft]) phi.x() = 0.0;
    if (refused[C::kPitchShaft]) phi.y() = 0.0;
    out.T_shaft_laser.linear() = orthonormalize(expSO3(phi) * start.T_shaft_laser.linear());
    if (refused[C::kShiftX])
        out.T_shaft_laser.translation().x() = start.T_shaft_laser.translation().x();
    if (refused[C::kShiftY])
        out.T_shaft_laser.translation().y() = start.T_shaft_laser.translation().y();
    if (refused[C::kEncoderZero]) out.encoder_zero_offset_rad = start.encoder_zero_offset_rad;
    if (refused[C::kEncoderTime]) out.motor_tpdo_latency_ms = start.motor_tpdo_latency_ms;
    if (refused[C::kImuTime]) out.xsens_frame_latency_ms = start.xsens_frame_latency_ms;
    return out;
}

struct Consistency {
    double sigma_m = 0.0;
    std::size_t residuals = 0;
};

Consistency consistencyOf(std::span<const SpinObservation> obs, const SpinModel& model,
                          const AssociationOptions& opt) {
    const auto res = associateHalves(obs, model, C::Vector::Zero(), opt);
    std::vector<double> r;
    evaluateResiduals(obs, model, res, C::Vector::Zero(), r);
    for (double& v : r) v = std::abs(v);
    if (r.empty()) return {};
    auto mid = r.begin() + static_cast<std::ptrdiff_t>(r.size() / 2);
    std::nth_element(r.begin(), mid, r.end());
    return {1.4826 * *mid, res.size()};
}

// One round's solve on one replay: associate, solve, associate again at the solution, solve.
SpinSolution solveRound(std::span<const SpinObservation> obs, SpinModel& model,
                        const SpinMask& free, bool determine, const SelfCalibrationOptions& o) {
    SpinSolution total;
    Calibration base = model.base;
    constexpr int kAssociations = 2;
    for (int a = 0; a < kAssociations; ++a) {
        const auto res = associateHalves(obs, model, C::Vector::Zero(), o.association);
        SpinSolution s = determine ? solveDetermined(obs, model, res, free, o.solver)
                                   : solveSpin(obs, model, res, free, o.solver);
        if (o.log)
            o.log(fmt::format(
                "    association {}: {} half-to-half planes, sigma {:.2f} -> {:.2f} mm", a + 1,
                res.size(), s.robust_sigma_before_m * 1e3, s.robust_sigma_after_m * 1e3));
        // Fold the step into the model so the next association starts from it.
        model.base.T_shaft_laser.linear() =
            orthonormalize(expSO3(Eigen::Vector3d(s.x[C::kRollShaft], s.x[C::kPitchShaft], 0.0)) *
                           model.base.T_shaft_laser.linear());
        model.base.T_shaft_laser.translation() +=
            Eigen::Vector3d(s.x[C::kShiftX], s.x[C::kShiftY], 0.0);
        model.base.encoder_zero_offset_rad += s.x[C::kEncoderZero];
        model.encoder_time_s += s.x[C::kEncoderTime];
        model.imu_time_s += s.x[C::kImuTime];
        if (a == 0) total = s;
        total.std = s.std;
        total.covariance = s.covariance;
        total.solved = s.solved;
        total.refused = s.refused;
        total.robust_sigma_after_m = s.robust_sigma_after_m;
        total.residuals = s.residuals;
        if (a + 1 == kAssociations) total.notes = s.notes;
    }
    // The round's correction against its base, as one vector.
    total.x[C::kEncoderZero] = model.base.encoder_zero_offset_rad - base.encoder_zero_offset_rad;
    const Eigen::Vector3d phi =
        logSO3(model.base.T_shaft_laser.linear() * base.T_shaft_laser.linear().transpose());
    total.x[C::kRollShaft] = phi.x();
    total.x[C::kPitchShaft] = phi.y();
    const Eigen::Vector3d dt =
        model.base.T_shaft_laser.translation() - base.T_shaft_laser.translation();
    total.x[C::kShiftX] = dt.x();
    total.x[C::kShiftY] = dt.y();
    total.x[C::kEncoderTime] = model.encoder_time_s;
    total.x[C::kImuTime] = model.imu_time_s;
    return total;
}

std::string makeWorkDir(const std::string& requested, bool* temporary) {
    *temporary = requested.empty();
    if (!requested.empty()) {
        fs::create_directories(requested);
        return requested;
    }
    std::string tmpl = (fs::temp_directory_path() / "handscan-calibrate-XXXXXX").string();
    if (::mkdtemp(tmpl.data()) == nullptr)
        throw std::runtime_error("calibrate: cannot create a work folder in " +
                                 fs::temp_directory_path().string() + "; give --work-dir");
    return tmpl;
}

}  // namespace

Result<SelfCalibrationReport> selfCalibrate(const SelfCalibrationOptions& o) {
    const std::string config_dir = defaultConfigDir();
    const std::string start_yaml =
        o.start_calibration.empty() ? config_dir + "/calibration.yaml" : o.start_calibration;
    SelfCalibrationOptions opt = o;
    if (opt.device_config.empty()) opt.device_config = config_dir + "/device.yaml";
    const Calibration start = loadCalibration(start_yaml);
    const DeviceConfig device = loadDeviceConfig(opt.device_config);
    const std::string camchain = camchainPathOf(start_yaml);
    bool temporary = false;
    const std::string work = makeWorkDir(o.work_dir, &temporary);
    auto log = [&](const std::string& s) {
        if (o.log) o.log(s);
    };

    SelfCalibrationReport report;
    // The camchain against the recording, on a replay with `calibration` (its trajectory places the
    // laser's depth edges); a check that cannot run is a note, not a failure of calibrate.
    auto checkCameras = [&](const Calibration& calibration, const Replayed& replayed) {
        auto check =
            checkCamchain(o.recording, withCalibratedLatencies(device, calibration), calibration,
                          replayed.trajectory, replayed.untrusted_s, o.camchain);
        if (!check.isOk()) {
            report.camchain_note = "camchain not checked: " + check.status().message();
            return;
        }
        report.camchain = std::move(*check);
        if (report.camchain.cameras.empty())
            report.camchain_note = "camchain not checked: the recording has no camera frames";
        for (const CamchainCameraCheck& c : report.camchain.cameras) log(c.summary);
    };
    if (o.camchain_only) {
        auto replayed = replayWith(opt, start_yaml, work + "/camchain");
        if (!replayed.isOk()) return replayed.status();
        report.calibration = start;
        report.sweeps_ok_before = report.sweeps_ok_after = replayed->ok_fraction;
        checkCameras(start, *replayed);
        if (temporary) fs::remove_all(work);
        return report;
    }
    Calibration current = start;
    // The half-revolution consistency solves the laser on its shaft; the encoder zero and the
    // IMU clock come from the gyro alignment. The encoder's time offset is not solved: with the
    // shaft turning at a near constant speed it turns the sweep as the zero does (the speed ripple,
    // ~2 %, leaves a 1 ms error 0.007 deg to show), so the zero found stands for both.
    // A replay with `current` written to DIR/calibration.yaml, then the IMU and the half-revolution
    // observations on its trajectory: each round's input and the final "after" check.
    struct Observed {
        Replayed replayed;
        std::vector<ImuSample> imu;
        std::vector<SpinObservation> observations;
    };
    auto observe = [&](const std::string& dir) -> Result<Observed> {
        fs::create_directories(dir);
        const std::string yaml = dir + "/calibration.yaml";
        if (Status st = writeCalibrationYaml(yaml, current, camchain, {}); !st.isOk()) return st;
        auto replayed = replayWith(opt, yaml, dir);
        if (!replayed.isOk()) return replayed.status();
        const DeviceConfig clocks = withCalibratedLatencies(device, current);
        auto imu = loadImu(o.recording, clocks);
        if (!imu.isOk()) return imu.status();
        auto obs = loadObservations(o.recording, clocks, current, replayed->trajectory,
                                    replayed->untrusted_s, *imu, o.observations);
        if (!obs.isOk()) return obs.status();
        return Observed{std::move(*replayed), std::move(*imu), std::move(*obs)};
    };
    SpinMask geometry{};
    geometry[C::kRollShaft] = geometry[C::kPitchShaft] = true;
    geometry[C::kShiftX] = geometry[C::kShiftY] = true;
    SpinSolution last;
    std::vector<std::string> notes;
    for (int round = 0; round < o.max_rounds; ++round) {
        auto observed = observe(fmt::format("{}/round{}", work, round));
        if (!observed.isOk()) return observed.status();
        const Replayed* replayed = &observed->replayed;
        const std::vector<ImuSample>* imu = &observed->imu;
        const std::vector<SpinObservation>* obs = &observed->observations;
        SpinModel model{current};
        if (round == 0) {
            const Consistency c = consistencyOf(*obs, model, o.association);
            report.consistency_before_m = c.sigma_m;
            report.residuals_before = c.residuals;
            report.sweeps_ok_before = replayed->ok_fraction;
        }
        log(fmt::format("round {}: replayed, {:.0f} % of sweeps trusted, {} laser steps", round + 1,
                        100.0 * replayed->ok_fraction, obs->size()));
        // Trajectory and calibration improve together: each round moves the laser on its shaft
        // (half-revolution consistency) and the encoder zero and the IMU clock (gyro alignment);
        // what the data determine is decided once the rounds settle, on the last replay.
        const bool last_round = round + 1 == o.max_rounds;
        SpinModel trial = model;
        last = solveRound(*obs, trial, geometry, false, opt);
        log(fmt::format(
            "    laser on shaft: roll {:+.4f} pitch {:+.4f} deg, shift {:+.2f} {:+.2f} mm",
            last.x[C::kRollShaft] * 180 / M_PI, last.x[C::kPitchShaft] * 180 / M_PI,
            last.x[C::kShiftX] * 1e3, last.x[C::kShiftY] * 1e3));
        auto gyro = alignGyro(replayed->matched, *imu, current.T_camera_imu().linear(),
                              current.T_camera_shaftbase.linear() * Eigen::Vector3d::UnitZ());
        if (!gyro.isOk()) return gyro.status();
        log(fmt::format(
            "    gyro alignment: {} sweep pairs, rms {:.4f} -> {:.4f} deg; zero {:+.4f} "
            "+- {:.4f} deg, IMU time {:+.3f} +- {:.3f} ms",
            gyro->pairs, gyro->rms_before_rad * 180 / M_PI, gyro->rms_after_rad * 180 / M_PI,
            gyro->zero_rad * 180 / M_PI, gyro->zero_std_rad * 180 / M_PI, gyro->imu_time_s * 1e3,
            gyro->imu_time_std_s * 1e3));
        bool moved = std::abs(gyro->zero_rad) > gyro->zero_std_rad ||
                     std::abs(gyro->imu_time_s) > gyro->imu_time_std_s;
        for (int j = 0; j < C::kCount; ++j)
            if (last.solved[j] && std::abs(last.x[j]) > last.std[j]) moved = true;
        ++report.rounds;
        SpinModel* chosen = &trial;
        if (!moved || last_round) {
            log(fmt::format("round {}: {}; deciding what the recording determines", round + 1,
                            moved ? "last round" : "correction within noise"));
            last = solveRound(*obs, model, geometry, true, opt);
            chosen = &model;
        }
        // The gyro's two: written when determined (always applied between rounds).
        const bool deciding = chosen == &model;
        const double refuse = o.solver.refuse_fraction_of_prior;
        const bool zero_ok = gyro->zero_std_rad <= refuse * o.solver.prior_std[C::kEncoderZero];
        const bool imu_ok = gyro->imu_time_std_s <= refuse * o.solver.prior_std[C::kImuTime];
        last.x[C::kEncoderZero] = gyro->zero_rad;
        last.std[C::kEncoderZero] = gyro->zero_std_rad;
        last.x[C::kImuTime] = gyro->imu_time_s;
        last.std[C::kImuTime] = gyro->imu_time_std_s;
        last.solved[C::kEncoderZero] = !deciding || zero_ok;
        last.solved[C::kImuTime] = !deciding || imu_ok;
        last.refused[C::kEncoderZero] = deciding && !zero_ok;
        last.refused[C::kImuTime] = deciding && !imu_ok;
        if (deciding && !zero_ok)
            last.notes.push_back(fmt::format(
                "encoder zero: not determined by this recording (std {:.3g} deg > {:.3g})",
                gyro->zero_std_rad * 180 / M_PI,
                refuse * o.solver.prior_std[C::kEncoderZero] * 180 / M_PI));
        if (deciding && !imu_ok)
            last.notes.push_back(fmt::format(
                "IMU time offset: not determined by this recording (std {:.3g} ms > {:.3g})",
                gyro->imu_time_std_s * 1e3, refuse * o.solver.prior_std[C::kImuTime] * 1e3));
        if (last.solved[C::kEncoderZero]) chosen->base.encoder_zero_offset_rad += gyro->zero_rad;
        if (last.solved[C::kImuTime]) chosen->imu_time_s += gyro->imu_time_s;
        current = applied(*chosen, device, last, notes);
        if (deciding) break;
        log(fmt::format("round {}: calibration moved; replaying with it", round + 1));
    }
    // What the last round could not determine is written as START had it.
    for (const std::string& n : last.notes) notes.push_back(n);
    current = resetRefused(current, start, last.refused);

    // The "after" replay, with the calibration as it will be written.
    {
        auto observed = observe(work + "/final");
        if (!observed.isOk()) return observed.status();
        const Replayed* replayed = &observed->replayed;
        const std::vector<SpinObservation>* obs = &observed->observations;
        const Consistency c = consistencyOf(*obs, SpinModel{current}, o.association);
        report.consistency_after_m = c.sigma_m;
        report.residuals_after = c.residuals;
        report.sweeps_ok_after = replayed->ok_fraction;
        if (o.check_camchain) checkCameras(current, *replayed);
    }

    // What the data determined, against START.
    const Eigen::Vector3d phi =
        logSO3(current.T_shaft_laser.linear() * start.T_shaft_laser.linear().transpose());
    const Eigen::Vector3d shift =
        current.T_shaft_laser.translation() - start.T_shaft_laser.translation();
    const double imu0 = latencyMs(start.xsens_frame_latency_ms, device.xsens.frame_latency_ms);
    const double enc0 = latencyMs(start.motor_tpdo_latency_ms, device.motor.tpdo_latency_ms);
    const double values[C::kCount][2] = {
        {0.0, phi.x() * 180.0 / M_PI},
        {0.0, phi.y() * 180.0 / M_PI},
        {0.0, shift.x() * 1e3},
        {0.0, shift.y() * 1e3},
        {start.encoder_zero_offset_rad * 180.0 / M_PI,
         current.encoder_zero_offset_rad * 180.0 / M_PI},
        {enc0, latencyMs(current.motor_tpdo_latency_ms, device.motor.tpdo_latency_ms)},
        {imu0, latencyMs(current.xsens_frame_latency_ms, device.xsens.frame_latency_ms)}};
    for (int j = 0; j < C::kCount; ++j) {
        ParameterEstimate p;
        p.name = C::name(j);
        p.unit = C::unit(j);
        p.start = values[j][0];
        p.value = values[j][1];
        p.std = last.solved[j] ? last.std[j] * C::displayScale(j) : INFINITY;
        p.written = last.solved[j];
        if (p.written && last.std[j] > o.solver.target_std[j])
            notes.push_back(fmt::format(
                "{}: written, but its std {:.3g} {} is above the {:.3g} {} an instrument needs; "
                "calibrate on a longer walk with more turning",
                p.name, p.std, p.unit, o.solver.target_std[j] * C::displayScale(j), p.unit));
        report.parameters.push_back(p);
    }
    notes.push_back(
        "laser rotation about the shaft axis: the same as the encoder zero (one value, "
        "written as the zero)");
    notes.push_back(
        "encoder time offset: not separable from the encoder zero while the shaft turns "
        "at a near constant speed; kept as given, the zero found stands for both");
    notes.push_back(
        "laser shift along the shaft axis: a constant offset of every sweep, which the "
        "spin does not see; kept as given");
    report.notes = notes;
    report.calibration = current;

    std::vector<std::string> comments = {
        "Written by `handscan calibrate` from " + fs::path(o.recording).filename().string() +
            " (start: " + start_yaml + ")",
        fmt::format("half-revolution consistency (robust std): {:.2f} mm -> {:.2f} mm",
                    report.consistency_before_m * 1e3, report.consistency_after_m * 1e3)};
    for (const auto& p : report.parameters)
        comments.push_back(
            p.written ? fmt::format("{}: {:.4f} {} (std {:.4f})", p.name, p.value, p.unit, p.std)
                      : fmt::format("{}: {}, kept as given", p.name,
                                    std::string(p.name) == C::name(C::kEncoderTime)
                                        ? "not separable from the encoder zero"
                                        : "not determined"));
    if (Status st = writeCalibrationYaml(o.out, current, camchain, comments); !st.isOk()) return st;
    if (temporary) fs::remove_all(work);
    return report;
}

}  // namespace handscan::calibrate
