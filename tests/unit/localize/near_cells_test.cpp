// The lock search's grid score (NearCells): a cell is near when its centre lies within the
// radius of a point, so a query agrees with the exact distance except within half a cell's
// diagonal of the radius; far away, across brick borders and at negative coordinates too.
#include "handscan/localize/near_cells.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace handscan::localize {
namespace {

TEST(NearCellsTest, AgreesWithTheExactDistanceOutsideHalfACellOfTheRadius) {
    std::vector<Eigen::Vector3f> edges{{-3.21f, 0.4f, 1.0f}}, planars;
    for (float x = -2.0f; x < 2.0f; x += 0.2f) planars.push_back({x, -0.75f, 0.33f});
    const NearCells near(edges, planars, 0.2, 0.1);
    const double half_diagonal = 0.1 * std::sqrt(3.0) / 2.0;
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-4.0, 4.0);
    int checked = 0;
    for (int i = 0; i < 20000; ++i) {
        const Eigen::Vector3d q(u(rng), u(rng) * 0.3 - 0.75, u(rng) * 0.2 + 0.5);
        double d = std::numeric_limits<double>::infinity();
        for (const auto* set : {&edges, &planars})
            for (const Eigen::Vector3f& p : *set) d = std::min(d, (p.cast<double>() - q).norm());
        if (std::abs(d - 0.2) <= half_diagonal) continue;
        EXPECT_EQ(near.near(q), d < 0.2) << q.transpose() << " at " << d;
        ++checked;
    }
    EXPECT_GT(checked, 10000);
    EXPECT_FALSE(near.near(Eigen::Vector3d(1e12, 0, 0)));
    EXPECT_FALSE(near.near(Eigen::Vector3d::Constant(std::nan(""))));
    EXPECT_FALSE(NearCells().near(Eigen::Vector3d::Zero()));
}

}  // namespace
}  // namespace handscan::localize
