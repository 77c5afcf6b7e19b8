// The localizer's settings (section 9): the sweep stack, the 0.5 Hz match period, the lock
// search around the hint, the lock and tracking acceptance, the change report.
#pragma once

#include "handscan/localize/sweep_stack.hpp"
#include "handscan/scan/scan_matcher.hpp"

namespace handscan::localize {

enum class MatchApply { kWhenReady, kAtNextSweep };

struct LocalizerConfig {
    SweepStackConfig stack;
    double period_s = 2.0;  // one match to the prior map per this (0.5 Hz)
    // The initial search around the hint: positions within this radius on this grid, headings
    // within +-yaw on this step.
    double search_radius_m = 3.0;
    double search_step_m = 0.5;
    double search_yaw_deg = 30.0;
    double search_yaw_step_deg = 5.0;
    // Headings turn about the place of the session's first sweep (the hint's), not about the
    // newest sweep: where the hint's error is a heading lost there (a relocalisation after an
    // IMU gap: the heading the IMU held), it moves the newest sweep by the turn times the
    // distance walked since, which no search radius covers for long.
    bool search_turns_about_first = false;
    int search_points = 400;  // stacked points scored per candidate (evenly picked)
    int refine_candidates = 6;
    // A refined candidate that moved farther from its grid seed than this many grid steps (in
    // position or heading) is dropped: the seed lay in no basin of its own, and the matcher ran
    // off to a place the grid did not offer (a 4-fold symmetric courtyard's turned copy, 109 deg
    // from the hint with the grid reaching 90). 0: kept.
    double refine_max_steps = 0.0;
    // A stacked point is "on the prior map" when a prior point lies this close: the prior's
    // planar density is one point per 0.2 m cell, so a point on a mapped surface has one within
    // ~0.15 m.
    double on_map_m = 0.2;
    // Lock: at least this share of the stacked points on the prior map, and every other refined
    // candidate farther than distinct_m / distinct_deg from it this much lower.
    double lock_min_on_map = 0.6;
    double lock_margin = 0.1;
    // The share on the map is taken among the stacked points with a prior point within
    // covered_m (the rest is new ground: a scanner relocalising on its own map while the
    // operator walks on into rooms not scanned yet), counting at least this share of all the
    // points as covered, so that a pose putting the stack beside the map scores nothing;
    // 0: among all the points (a new session starting where the earlier one did).
    double score_min_covered = 0.0;
    double covered_m = 1.5;
    double distinct_m = 0.5;
    double distinct_deg = 10.0;
    // Or: two successive searches (other stacks, other views) put the odometry's world at the
    // same place (within distinct_m / distinct_deg), each best with at least lock_min_on_map and
    // this margin. An aliased place (a corridor's repeated bays) can win one view by a few %, but
    // not the next at the same place, while the true one keeps winning. 0: off.
    double confirm_margin = 0.0;
    // Every lock confirmed so (none on one search alone, whatever its margin).
    bool confirm_always = false;
    // After the lock a match is used when this share is on the map and it moves the estimate
    // less than this (the odometry drifts millimetres per period; more is a wrong match).
    double track_min_on_map = 0.5;
    double max_correction_m = 0.3;
    double max_correction_deg = 3.0;
    // Changes (judged on planar points, which carry the laser centre that saw them): a point of
    // this session farther than change_m from every prior point, where the earlier session saw
    // through empty space (PriorMap::seenSpace), has appeared; a prior point where this session
    // sees through empty space has vanished. Space the earlier session never looked at is new
    // ground, not a change.
    double change_m = 0.3;
    double change_cell_m = 0.5;
    int change_cell_min_points = 3;  // a cell is reported from this many points up
    // ... an appeared cell seen by this many matches (stacks 2 s apart, other viewpoints): what
    // one view alone finds (vegetation's unrepeatable returns, a grazing ray) is noise.
    int change_cell_min_matches = 2;
    scan::ScanMatcherConfig matcher;
    // When a match (run on the localizer's own thread) takes effect: as soon as it is done
    // (the daemon, paced replay), or at the next sweep, waited for if need be (replay --fast:
    // the same bytes run after run, whatever the thread scheduling).
    MatchApply apply = MatchApply::kWhenReady;
};

}  // namespace handscan::localize
