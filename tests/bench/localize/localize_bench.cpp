// Cost of the localizer's matches to a prior map (section 9), per call, on the synthetic room of
// the localizer's tests (10 x 7 x 3 m, four pieces of furniture): the lock search from a hint 1 m
// and 15 deg off (the grid of ~1500 poses around it, then the best seeds refined), its grid
// score of one pose (400 points: exactly by the k-d trees, or by the prior's NearCells), and one
// 0.5 Hz tracking match once locked. The paper's budget: 10.7 % of a thread at 0.5 Hz, i.e.
// 214 ms per 2 s.
#include <benchmark/benchmark.h>

#include <memory>

#include "handscan/localize/prior_match.hpp"
#include "synthetic_room.hpp"

namespace {

using namespace handscan;
using localize::test::pose;

struct Room {
    localize::PriorMap prior{
        localize::test::roomWorld(0.2, 0.0, Eigen::Vector3d::Zero(),
                                  {{2.5, 2.0, 1.3}, {7.5, 2.0, 1.3}, {3.5, 5.5, 1.3}}),
        pose(5, 3.5, 1.3, 0)};
    Eigen::Isometry3d truth = pose(3.2, 2.4, 1.3, 40);
    Eigen::Isometry3d hint = pose(3.2 + 0.8, 2.4 + 0.6, 1.3, 55);
    scan::FeatureCloud stack = localize::test::sweepAt(truth);
};

const Room& room() {
    static const Room r;
    return r;
}

void BM_LockSearch(benchmark::State& state) {
    const Room& r = room();
    const localize::LocalizerConfig config;
    for (auto _ : state) {
        const localize::PriorMatchOutcome o =
            localize::searchLock(config, r.prior, r.stack, r.hint);
        if (!o.accepted || localize::separation(o.T_prior_new, r.truth).first > 0.05)
            state.SkipWithError("the search did not lock on the truth");
        benchmark::DoNotOptimize(o);
    }
}
BENCHMARK(BM_LockSearch)->Unit(benchmark::kMillisecond);

void BM_GridPoseExact(benchmark::State& state) {
    const Room& r = room();
    const localize::LocalizerConfig config;
    const std::vector<Eigen::Vector3d> pts = localize::samplePoints(r.stack, config.search_points);
    for (auto _ : state)
        benchmark::DoNotOptimize(localize::shareOnMap(config, r.prior, pts, r.hint));
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(pts.size()));
}
BENCHMARK(BM_GridPoseExact)->Unit(benchmark::kMicrosecond);

void BM_GridPoseNearCells(benchmark::State& state) {
    const Room& r = room();
    const localize::LocalizerConfig config;
    const std::vector<Eigen::Vector3d> pts = localize::samplePoints(r.stack, config.search_points);
    for (auto _ : state)
        benchmark::DoNotOptimize(localize::gridShare(config, r.prior, pts, r.hint));
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(pts.size()));
}
BENCHMARK(BM_GridPoseNearCells)->Unit(benchmark::kMicrosecond);

void BM_TrackingMatch(benchmark::State& state) {
    const Room& r = room();
    const localize::LocalizerConfig config;
    const Eigen::Isometry3d start = pose(3.25, 2.43, 1.3, 41);
    for (auto _ : state)
        benchmark::DoNotOptimize(localize::trackPrior(config, r.prior, r.stack, start));
}
BENCHMARK(BM_TrackingMatch)->Unit(benchmark::kMillisecond);

}  // namespace
