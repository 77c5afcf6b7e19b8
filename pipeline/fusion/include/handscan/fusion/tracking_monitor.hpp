// TrackingMonitor: the pipeline watching itself. The paper's pipeline trusts every scan match;
// when the estimate runs away (a wrong calibration, the laser blinded, the scanner dropped) the
// map fills with garbage and nobody notices. After each sweep's match it checks the evidence a
// consistent estimate must show:
//   - the match found the map: enough correspondences, and most of the sweep's features have
//     one (a map that stops agreeing with new sweeps loses its correspondences first);
//   - the match fits: the robust rms feature-to-map distance stays near the laser's noise;
//   - the match agrees with the IMU prediction it started from (the prior of eq. 18): with
//     feedback the two differ by millimetres, a jump of decimetres is one of them failing;
//   - the motion between matched sweeps is one a hand-held device can make (speed, turn rate,
//     acceleration).
// A sweep that fails a check is inconsistent: it must not enter the map. `trip_after`
// inconsistent sweeps in a row (or one impossible motion) and tracking is lost, with the reason;
// nothing enters the map until `recover_after` consistent sweeps in a row, matched against the map
// built before the loss, say the operator is back in a place already scanned. Failures the
// pipeline sees without a match (a blinded laser, a silent IMU, a fall) lose tracking at once.
// Pure computation.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <vector>

#include "handscan/core/se3.hpp"
#include "handscan/core/time.hpp"

namespace handscan::fusion {

enum class LostReason : std::uint8_t {
    kNone = 0,
    kNoMatch = 1,              // too few correspondences: the laser sees nothing it knows
    kMapDisagrees = 2,         // most features found no map surface where the match put them
    kPoorFit = 3,              // the matched features lie far from their surfaces (rms)
    kPredictionDisagrees = 4,  // the match jumped away from the IMU prediction
    kImplausibleMotion = 5,    // speed, turn rate or acceleration no hand-held device makes
    // Failures seen outside a match, each conclusive on its own (TrackingMonitor::fail):
    kLaserBlind = 6,  // a whole sweep with (almost) no returns: the laser's window covered
    kImuSilent = 7,   // no IMU samples while the laser runs: nothing carries the prediction
    kDropped = 8,     // free fall: the scanner left the operator's hand
    // Set outside the monitor: the scan's calibration does not fit what the laser sees
    // (worker::CalibrationCheck); the whole scan stays out of the map.
    kCalibrationWrong = 9,
};
const char* lostReasonName(LostReason r);  // snake_case, for stats.json

struct TrackingMonitorConfig {
    bool enabled = true;
    // A matched sweep needs this share of its features associated with the map. Measured on
    // simulated office / house / courtyard walks: 0.55-0.95 per sweep; a sweep matched against a
    // map it does not belong to keeps a fraction of that.
    double min_match_fraction = 0.35;
    // Weighted rms feature-to-map distance of the final iteration; the laser's noise gives
    // 1-2 cm on the simulated walks (the bisquare kernel's scale is 10 cm).
    double max_rms_m = 0.045;
    // Distance of the match from its IMU prior (eq. 18) in the prior's standard deviations,
    // sqrt(e^T I e) with e = log(T_prior^-1 T_match) and I the prior's information: along
    // directions the last match solved the prediction is good to 5 mm / 0.3 deg (12 sigma:
    // 6 cm); along unsolved ones (a corridor's axis) it is the walker's guess, 20 cm, and a
    // weak direction the matcher confirms may jump back decimetres. On simulated house walks the
    // match lands at most 1.0 cm (2 sigma) from it; with the laser 1 deg off on its shaft (the
    // issue's wrong calibration) 11 cm within 40 s and 59 cm later, as the map bends.
    double max_prediction_sigmas = 12.0;
    // A hand-held scanner carried by a walker: 2 m/s is a brisk walk, 600 deg/s beyond the
    // aggressive motion the pipeline is specified for (370 deg/s).
    double max_speed_mps = 4.0;
    double max_rate_radps = 10.0;
    double max_accel_mps2 = 30.0;
    int trip_after = 2;  // inconsistent sweeps in a row before tracking is lost
    // ... or this many inconsistent ones among the last `trip_window` sweeps (4 s): a map that
    // fails every other sweep has stopped agreeing with them as surely as one that fails two in
    // a row. An office walk replayed with the encoder's and the IMU's clocks 3 ms off (s92) failed
    // every second sweep from 5.5 s and was 0.4 m off before two failed in a row at 11 s; the
    // rule flags it at 9 s. Clean office, house, courtyard, corridor, tunnel and field walks fail
    // none at all.
    int trip_window = 8;
    int trip_in_window = 3;
    int recover_after = 3;  // consistent sweeps in a row (against the old map) to recover
    // A loss the matches have not recovered within this many sweeps with correspondences (3 s;
    // given up at a failed one) is a lost pose: the prediction has drifted beyond the matcher's
    // reach, from where it converges to a wrong place as readily as to the right one (an office
    // walk after 5 s of blinded laser never came back). Recovery then waits for a relocalisation,
    // as after an IMU gap. 0: never.
    int relocalise_after = 6;
};

// What the matcher of one sweep reports (scan::SweepResult, kept free of the scan library).
struct SweepEvidence {
    TimeNs t = 0;                                                     // sweep start
    Eigen::Isometry3d T_world_prior = Eigen::Isometry3d::Identity();  // prediction at t
    Eigen::Isometry3d T_world_match = Eigen::Isometry3d::Identity();  // refined at t
    // Information of the prior's error in the body tangent (rot, trans), as the matcher used it.
    Matrix6d prior_information = Matrix6d::Zero();
    bool founds_map = false;  // the first sweep: nothing to match against, accepted as is
    bool enough_matches = false;
    std::size_t features = 0;  // edge + planar features extracted
    std::size_t matches = 0;   // of those, associated with the map in the last round
    double rms_m = 0.0;
};

struct TrackingVerdict {
    bool consistent = true;  // this sweep passed every check
    bool lost = false;       // the monitor's state after this sweep
    bool enters_map = true;  // consistent and not lost: the sweep may be merged and journaled
    // The match fits the map it was matched against (correspondences, rms), whatever the
    // prediction said and the motion it implies: a measurement the IMU predictor may take, so
    // that a wrong prediction is pulled back to the map instead of running away on the IMU.
    bool fits_map = true;
    LostReason reason = LostReason::kNone;  // why this sweep failed (or why tracking is lost)
    std::string detail;                     // the failed check with its figures
};

// One interval with tracking lost; t_end = 0 while it lasts.
struct LostInterval {
    TimeNs t_begin = 0;
    TimeNs t_end = 0;
    LostReason reason = LostReason::kNone;
    std::string detail;
    std::uint64_t sweeps = 0;  // sweeps held out of the map during it
    // When the pipeline knew: the failing sweep's start for a match's verdict (known once the
    // sweep is complete), the sample it was seen at for fail().
    TimeNs t_flagged = 0;
};

class TrackingMonitor {
public:
    explicit TrackingMonitor(const TrackingMonitorConfig& config = {}) : config_(config) {}

    // Judges one matched sweep (in time order) and advances the state.
    TrackingVerdict assess(const SweepEvidence& e);
    // A failure the pipeline saw outside a match at time t (the laser blinded, the IMU silent,
    // the scanner falling): no estimate made through it can be trusted, so tracking is lost at
    // once (no `trip_after`), and recovers as after any loss. Motion is not judged across it.
    // `pose_unknown`: the estimate cannot have survived it (the IMU silent) - see below.
    // `t_seen`: the sample time it was recognised at (t: when it began).
    TrackingVerdict fail(TimeNs t, TimeNs t_seen, LostReason reason, std::string detail,
                         bool pose_unknown);
    // After a failure with `pose_unknown` (the IMU silent: attitude and heading held across the
    // gap while the walker may have turned a corner) a match from the held pose may settle in
    // the wrong place and look consistent: recovery waits for a relocalisation (a search of the
    // old map, lio::Relocaliser). A blinded laser or a fall keep the IMU running: the matches
    // themselves recover, as after any loss - unless they have not within relocalise_after
    // sweeps.
    bool awaitingRelocalisation() const { return awaiting_relocalisation_; }
    // The relocaliser found the old map (`detail`: where); recovery counts from the next sweep.
    void relocalised(TimeNs t, const std::string& detail);

    bool lost() const { return lost_; }
    const std::vector<LostInterval>& intervals() const { return intervals_; }
    std::uint64_t rejectedSweeps() const { return rejected_; }
    const TrackingMonitorConfig& config() const { return config_; }

    // What the operator is told while tracking is lost.
    static constexpr const char* kLostMessage =
        "tracking lost \xe2\x80\x94 go back to a place already scanned";

private:
    // The first check `e` fails, with its figures; kNone when it passes every one.
    LostReason check(const SweepEvidence& e, std::string& detail) const;
    LostReason checkMotion(const SweepEvidence& e, std::string& detail) const;

    TrackingMonitorConfig config_;
    bool lost_ = false;
    int bad_run_ = 0;
    std::deque<bool> recent_;  // the last trip_window sweeps judged: inconsistent or not
    int good_run_ = 0;
    std::uint64_t rejected_ = 0;
    // The last two consistent matches (time, pose): speed and acceleration between sweeps.
    struct Stamped {
        TimeNs t;
        Eigen::Isometry3d T;
    };
    std::optional<Stamped> last_, before_last_;
    TimeNs last_failure_t_ = 0;  // the latest fail()
    bool awaiting_relocalisation_ = false;
    int unrecovered_ = 0;  // lost sweeps with correspondences since the loss or relocalisation
    std::vector<LostInterval> intervals_;
};

}  // namespace handscan::fusion
