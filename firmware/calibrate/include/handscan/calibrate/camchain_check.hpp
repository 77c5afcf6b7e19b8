// The camchain checked against the recording (issue 13: "calibrate checks the camchain against the
// recording (reprojection of laser points on image edges) and reports when it looks wrong"). The
// cameras' intrinsics and their pose on the rig come from Kalibr, not from calibrate; a knock, a
// refocus or the wrong camchain file shows as laser points landing beside what the image shows.
//
// The laser's depth edges (a return much nearer than its neighbour on the same scan line: the
// silhouette of a door frame, a pillar, a desk) are placed in the world with the replayed
// trajectory and projected into camera frames taken while tracking was ok; there they should lie
// on the image's intensity edges (Levinson & Thrun, "Automatic online calibration of cameras and
// lasers", RSS 2013: the score is the edge strength under the projected depth edges, weighted by
// the depth jump). The score is searched over small turns of the camera about its centre: a
// camchain that is right scores best near no turn; one that is off scores best at the turn that
// undoes it. A pure turn stands for the error here: a few degrees of rotation or a wrong principal
// point move the projection alike, while a centimetre of translation moves points at 3 m by a
// third of that (0.2 deg).
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "handscan/core/config.hpp"
#include "handscan/core/status.hpp"
#include "handscan/tum/tum_file.hpp"

namespace handscan::calibrate {

struct CamchainCheckOptions {
    int frames = 24;        // camera frames per camera, spread over the trusted walk
    double window_s = 0.3;  // laser steps within this of a frame are projected into it
    double min_depth_jump_m =
        0.3;                    // a depth edge: the neighbour on the scan line this much farther
    double max_range_m = 12.0;  // farther edges are a few pixels wide and blurred
    double search_deg = 2.0;    // the turns searched, each axis
    // A camchain looks wrong when the best turn is at least this far from none and farther than
    // 3 standard deviations (its scatter over groups of frames).
    double min_turn_deg = 0.3;
    int groups = 4;
};

struct CamchainCameraCheck {
    std::string camera;  // "tracking" (cam0) or "colour" (cam1)
    std::size_t frames = 0;
    std::size_t edge_points = 0;  // projected depth edges over all frames
    // The turn of the camera (about its x right, y down, z forward axes, deg) whose projection
    // fits the image edges best: p_cam' = R(turn) p_cam. Zero for a right camchain.
    Eigen::Vector3d best_turn_deg = Eigen::Vector3d::Zero();
    Eigen::Vector3d turn_std_deg = Eigen::Vector3d::Zero();  // over groups of frames
    double score_given = 0.0;  // mean edge strength under the depth edges, camchain as is
    double score_best = 0.0;
    bool checked = false;  // enough frames and edges to say anything
    bool looks_wrong = false;
    std::string summary;  // one line for the operator
};

struct CamchainCheck {
    std::vector<CamchainCameraCheck> cameras;  // the cameras the recording has frames of
};

// `trajectory`: the walk replayed with `calibration` (trajectory.tum, body = tracking camera);
// `untrusted_s`: spans the tracking monitor did not trust (no frame is taken there).
Result<CamchainCheck> checkCamchain(const std::string& recording, const DeviceConfig& device,
                                    const Calibration& calibration,
                                    const tum::Trajectory& trajectory,
                                    const std::vector<std::pair<double, double>>& untrusted_s,
                                    const CamchainCheckOptions& options = {});

}  // namespace handscan::calibrate
