// `handscan merge A B ... --out DIR`: scan sessions in one frame as one map (PLY/LAS with a
// session id per point) and one trajectory per session.
#include <iostream>

#include "command_registry.hpp"
#include "handscan/core/log.hpp"
#include "handscan/merge/session_merge.hpp"

namespace handscan::cli {
namespace {

const RegisterCommand kMerge{
    "merge",
    "Merge scan sessions localized on each other (replay --prior-map) into one map and frame",
    [](CLI::App& sub) {
        auto dirs = std::make_shared<std::vector<std::string>>();
        auto out = std::make_shared<std::string>();
        sub.add_option("SCANS", *dirs,
                       "scan directories (journal.hsj), the first one's frame is the merged "
                       "map's; each later one localized on an earlier one")
            ->required()
            ->check(CLI::ExistingDirectory);
        sub.add_option("--out", *out, "output directory")->required();
        return std::function<int()>([dirs, out] {
            auto r = merge::mergeSessions(*dirs, *out);
            if (!r.isOk()) {
                log().error("{}", r.status().message());
                return 1;
            }
            for (std::size_t i = 0; i < r->sessions.size(); ++i) {
                const merge::SessionSummary& s = r->sessions[i];
                std::cout << "session " << i + 1 << ": " << s.dir << ", " << s.points << " points, "
                          << s.poses << " poses";
                if (i > 0) {
                    std::cout << (s.in_frame ? ", localized on " + s.prior_map
                                             : ", NOT localized on an earlier session (its own "
                                               "frame: replay it with --prior-map)");
                    const merge::Consistency& c = s.against_first;
                    std::cout << "; against session 1 over " << c.overlap_points
                              << " overlapping points: median " << c.median_m * 1e3 << " mm, p90 "
                              << c.p90_m * 1e3 << " mm";
                }
                std::cout << "\n";
                if (i > 0 && !s.in_frame)
                    log().warn("merge: {} was not localized on an earlier session given", s.dir);
            }
            std::cout << r->points << " points -> " << *out << "/map.ply, map.las, "
                      << "trajectory_<n>.tum, sessions.json\n";
            return 0;
        });
    }};

}  // namespace
}  // namespace handscan::cli
