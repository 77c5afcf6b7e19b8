// `handscan merge A B ... --out DIR`: scan sessions already in one frame (each later one replayed
// or scanned with --prior-map on an earlier one, which its journal's metadata records) as one
// map and one trajectory per session: DIR/map.ply (with a `session` property, 1 = A, 2 = B, ...),
// DIR/map.las (the session as each point's point source ID), DIR/trajectory_<n>.tum and
// DIR/sessions.json (the sessions, their point counts, whether each was localized on an earlier
// one, and how well each agrees with the first where they overlap).
#pragma once

#include <string>
#include <vector>

#include "handscan/core/status.hpp"
#include "handscan/merge/overlap_consistency.hpp"

namespace handscan::merge {

struct SessionSummary {
    std::string dir;
    std::uint64_t points = 0;
    std::uint64_t poses = 0;
    std::string prior_map;      // the earlier scan it was localized on ("" for the first)
    bool in_frame = true;       // the first, or localized on one of the sessions before it
    Consistency against_first;  // for the later sessions
};

struct MergeReport {
    std::vector<SessionSummary> sessions;
    std::uint64_t points = 0;
    std::string sessions_json;
};

Result<MergeReport> mergeSessions(const std::vector<std::string>& dirs, const std::string& out_dir);

}  // namespace handscan::merge
