#include "handscan/scan/surface_offset.hpp"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <functional>
#include <optional>
#include <random>
#include <vector>

namespace handscan::scan {
namespace {

// A planar match as the scan matcher forms it: the best-fit plane of the nearest `plane_k` points
// and the query's distance to it, plain and moved onto the surface by surfaceOffsetAt (fitted to
// all the points). Distances are signed along +z whichever way the plane's normal came out.
struct PlaneMatch {
    double plain_m = 0.0;               // n . (q - c)
    std::optional<double> corrected_m;  // n . (q - c) - offset
};

PlaneMatch matchQuery(const std::vector<Eigen::Vector3d>& pts, std::size_t plane_k,
                      const Eigen::Vector3d& q) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i < plane_k; ++i) c += pts[i];
    c /= static_cast<double>(plane_k);
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (std::size_t i = 0; i < plane_k; ++i) cov += (pts[i] - c) * (pts[i] - c).transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
    es.computeDirect(cov);
    const Eigen::Vector3d n = es.eigenvectors().col(0);
    const double sign = n.z() > 0.0 ? 1.0 : -1.0;
    PlaneMatch m;
    m.plain_m = sign * n.dot(q - c);
    const auto off = surfaceOffsetAt(pts.data(), static_cast<int>(pts.size()), c, n,
                                     es.eigenvectors().col(2), es.eigenvectors().col(1), q);
    if (off) m.corrected_m = m.plain_m - sign * *off;
    return m;
}

// Clusters of 16 map points ~0.2 m apart (the map's planar leaf) around a query point, all on a
// surface z = f(x, y) with 7 mm noise; the query's true distance to the surface is 0.
struct ClusterStats {
    double mean_plain_m = 0.0;
    double mean_corrected_m = 0.0;
    int corrected = 0;
    int trials = 0;
};

ClusterStats clusters(const std::function<double(double, double)>& f, int trials, unsigned seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> noise(0.0, 0.007);
    std::uniform_real_distribution<double> jitter(-0.08, 0.08);
    ClusterStats s;
    for (int t = 0; t < trials; ++t) {
        const double qx = jitter(rng);
        const double qy = jitter(rng);
        const Eigen::Vector3d q(qx, qy, f(qx, qy) + noise(rng));
        std::vector<Eigen::Vector3d> pts;
        // 4 x 4 grid 0.2 m apart, closest to the query first (as a k-d tree returns them).
        for (int i = 0; i < 4; ++i) {
            for (int j = 0; j < 4; ++j) {
                const double x = -0.3 + 0.2 * i + jitter(rng) * 0.5;
                const double y = -0.3 + 0.2 * j + jitter(rng) * 0.5;
                pts.emplace_back(x, y, f(x, y) + noise(rng));
            }
        }
        std::sort(pts.begin(), pts.end(),
                  [&](const auto& a, const auto& b) { return (a - q).norm() < (b - q).norm(); });
        const PlaneMatch m = matchQuery(pts, 8, q);
        s.mean_plain_m += m.plain_m;
        if (m.corrected_m) {
            s.mean_corrected_m += *m.corrected_m;
            ++s.corrected;
        }
        ++s.trials;
    }
    s.mean_plain_m /= s.trials;
    if (s.corrected > 0) s.mean_corrected_m /= s.corrected;
    return s;
}

TEST(SurfaceOffset, ACurvedVaultNoLongerBiasesThePointToPlaneDistance) {
    // A tunnel vault of 3 m radius seen from inside: the surface curves up (+z, towards the axis)
    // away from the query. The best-fit plane of 8 points 0.2 m apart sits on the axis side by
    // kappa var(u) / 2, so the query seems outside (below) it by millimetres, every time.
    const double R = 3.0;
    const auto vault = [R](double x, double) { return R - std::sqrt(R * R - x * x); };
    const ClusterStats s = clusters(vault, 2000, 11);
    std::printf("vault R=3 m: plain plane %.2f mm, surface offset %.2f mm (%d of %d corrected)\n",
                1e3 * s.mean_plain_m, 1e3 * s.mean_corrected_m, s.corrected, s.trials);
    EXPECT_LT(s.mean_plain_m,
              -0.003);  // measured -3.9 mm: the bias the matcher turned into a pitch
    EXPECT_NEAR(s.mean_corrected_m, 0.0, 0.0008);
    EXPECT_GT(s.corrected, s.trials * 8 / 10);
}

TEST(SurfaceOffset, AFlatSurfaceStaysUnbiased) {
    const ClusterStats s = clusters([](double, double) { return 0.0; }, 2000, 12);
    EXPECT_NEAR(s.mean_plain_m, 0.0, 0.0006);
    EXPECT_NEAR(s.mean_corrected_m, 0.0, 0.0008);
    EXPECT_GT(s.corrected, s.trials * 8 / 10);
}

TEST(SurfaceOffset, ACornerOrALineIsNoSurfaceToFit) {
    // Points on two walls meeting at 90 degrees: no quadric fits them within the laser's noise.
    std::vector<Eigen::Vector3d> corner;
    for (int i = 0; i < 8; ++i) corner.emplace_back(0.05 * i, 0.1 * (i % 4), 0.0);
    for (int i = 0; i < 8; ++i) corner.emplace_back(0.0, 0.1 * (i % 4), 0.05 + 0.05 * i);
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (const auto& p : corner) c += p;
    c /= static_cast<double>(corner.size());
    const Eigen::Vector3d n = Eigen::Vector3d(1, 0, 1).normalized();
    EXPECT_FALSE(surfaceOffsetAt(corner.data(), 16, c, n, Eigen::Vector3d(1, 0, -1).normalized(),
                                 Eigen::Vector3d::UnitY(), Eigen::Vector3d(0.1, 0.1, 0.1))
                     .has_value());
    // Points along one line: nothing tells the curvature across it.
    std::vector<Eigen::Vector3d> line;
    for (int i = 0; i < 10; ++i) line.emplace_back(0.1 * i, 0.0, 0.0);
    EXPECT_FALSE(surfaceOffsetAt(line.data(), 10, Eigen::Vector3d(0.45, 0, 0),
                                 Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitX(),
                                 Eigen::Vector3d::UnitY(), Eigen::Vector3d(0.4, 0, 0))
                     .has_value());
    // Too few points for a quadric with any redundancy.
    EXPECT_FALSE(surfaceOffsetAt(corner.data(), 6, c, n, Eigen::Vector3d(1, 0, -1).normalized(),
                                 Eigen::Vector3d::UnitY(), c)
                     .has_value());
}

}  // namespace
}  // namespace handscan::scan
