#include "handscan/eval/mesh_distance.hpp"

#include <embree3/rtcore.h>

#include <algorithm>
#include <limits>

namespace handscan::eval {

Eigen::Vector3d closestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                       const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
    const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
    const double d1 = ab.dot(ap), d2 = ac.dot(ap);
    if (d1 <= 0.0 && d2 <= 0.0) return a;  // vertex region A
    const Eigen::Vector3d bp = p - b;
    const double d3 = ab.dot(bp), d4 = ac.dot(bp);
    if (d3 >= 0.0 && d4 <= d3) return b;  // vertex region B
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return a + d1 / (d1 - d3) * ab;  // edge AB
    const Eigen::Vector3d cp = p - c;
    const double d5 = ab.dot(cp), d6 = ac.dot(cp);
    if (d6 >= 0.0 && d5 <= d6) return c;  // vertex region C
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return a + d2 / (d2 - d6) * ac;  // edge AC
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
        return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);  // edge BC
    }
    const double denom = va + vb + vc;
    if (denom <= 0.0) {  // degenerate (zero-area) triangle: nearest of its edges
        const Eigen::Vector3d e[3] = {closestPointOnTriangle(p, a, b, b),
                                      closestPointOnTriangle(p, b, c, c),
                                      closestPointOnTriangle(p, a, c, c)};
        return *std::min_element(std::begin(e), std::end(e), [&](const auto& x, const auto& y) {
            return (x - p).squaredNorm() < (y - p).squaredNorm();
        });
    }
    const double v = vb / denom, w = vc / denom;  // face region
    return a + ab * v + ac * w;
}

double pointTriangleDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                             const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
    return (closestPointOnTriangle(p, a, b, c) - p).norm();
}

struct MeshDistance::Bvh {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    ~Bvh() {
        if (scene) rtcReleaseScene(scene);
        if (device) rtcReleaseDevice(device);
    }
};

namespace {

struct QueryState {
    const PlyGeometry* mesh;
    Eigen::Vector3d p;
    double best_sq;
};

bool closestTriangleCallback(RTCPointQueryFunctionArguments* args) {
    auto* q = static_cast<QueryState*>(args->userPtr);
    const auto& t = q->mesh->triangles[args->primID];
    const double d_sq = (closestPointOnTriangle(q->p, q->mesh->vertices[t[0]],
                                                q->mesh->vertices[t[1]], q->mesh->vertices[t[2]]) -
                         q->p)
                            .squaredNorm();
    if (d_sq < q->best_sq) {
        q->best_sq = d_sq;
        // Shrink the search sphere (slightly padded for the BVH's float bounds).
        args->query->radius = static_cast<float>(std::sqrt(d_sq) * (1.0 + 1e-6) + 1e-6);
        return true;
    }
    return false;
}

}  // namespace

MeshDistance::MeshDistance(PlyGeometry mesh, std::unique_ptr<Bvh> bvh)
    : mesh_(std::move(mesh)), bvh_(std::move(bvh)) {}

Result<std::unique_ptr<MeshDistance>> MeshDistance::build(PlyGeometry mesh) {
    if (mesh.triangles.empty()) {
        return Status(StatusCode::kInvalidArgument,
                      "mesh distance: the mesh has no triangles (faces)");
    }
    auto bvh = std::make_unique<Bvh>();
    bvh->device = rtcNewDevice("threads=1");
    if (!bvh->device)
        return Status(StatusCode::kDeviceError, "mesh distance: Embree device creation failed");
    bvh->scene = rtcNewScene(bvh->device);
    std::unique_ptr<MeshDistance> out(new MeshDistance(std::move(mesh), std::move(bvh)));
    const PlyGeometry& mesh_ = out->mesh_;
    RTCGeometry geom = rtcNewGeometry(out->bvh_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0,
                                                          RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                                          mesh_.vertices.size()));
    for (std::size_t i = 0; i < mesh_.vertices.size(); ++i) {
        for (int k = 0; k < 3; ++k)
            v[3 * i + static_cast<std::size_t>(k)] = static_cast<float>(mesh_.vertices[i][k]);
    }
    auto* idx = static_cast<unsigned*>(
        rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                3 * sizeof(unsigned), mesh_.triangles.size()));
    for (std::size_t i = 0; i < mesh_.triangles.size(); ++i) {
        for (int k = 0; k < 3; ++k)
            idx[3 * i + static_cast<std::size_t>(k)] =
                mesh_.triangles[i][static_cast<std::size_t>(k)];
    }
    rtcCommitGeometry(geom);
    rtcAttachGeometry(out->bvh_->scene, geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(out->bvh_->scene);
    return out;
}

MeshDistance::~MeshDistance() = default;

double MeshDistance::distance(const Eigen::Vector3d& p) const {
    QueryState state{&mesh_, p, std::numeric_limits<double>::infinity()};
    RTCPointQuery query;
    query.x = static_cast<float>(p.x());
    query.y = static_cast<float>(p.y());
    query.z = static_cast<float>(p.z());
    query.time = 0.0f;
    query.radius = std::numeric_limits<float>::infinity();
    RTCPointQueryContext context;
    rtcInitPointQueryContext(&context);
    rtcPointQuery(bvh_->scene, &query, &context, closestTriangleCallback, &state);
    return std::sqrt(state.best_sq);
}

MapErrorResult computeMapError(const std::vector<Eigen::Vector3d>& map_points,
                               const MeshDistance& mesh) {
    MapErrorResult r;
    std::vector<double> d;
    d.reserve(map_points.size());
    double sum = 0.0;
    for (const auto& p : map_points) {
        d.push_back(mesh.distance(p));
        sum += d.back();
    }
    r.points = d.size();
    if (d.empty()) return r;
    std::sort(d.begin(), d.end());
    auto pct = [&](double q) {
        return d[std::min(d.size() - 1,
                          static_cast<std::size_t>(q * static_cast<double>(d.size())))];
    };
    r.median_m = pct(0.5);
    r.p90_m = pct(0.9);
    r.p99_m = pct(0.99);
    r.mean_m = sum / static_cast<double>(d.size());
    r.max_m = d.back();
    return r;
}

}  // namespace handscan::eval
