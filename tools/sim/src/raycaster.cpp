#include "handscan/sim/raycaster.hpp"

#include <embree3/rtcore.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace handscan::sim {

struct Raycaster::Impl {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    ~Impl() {
        if (scene) rtcReleaseScene(scene);
        if (device) rtcReleaseDevice(device);
    }
};

Raycaster::Raycaster(const World& world) : world_(world), impl_(std::make_unique<Impl>()) {
    impl_->device = rtcNewDevice("threads=1,verbose=0");
    if (!impl_->device) {
        throw std::runtime_error("Embree: cannot create a device (error " +
                                 std::to_string(static_cast<int>(rtcGetDeviceError(nullptr))) +
                                 ")");
    }
    impl_->scene = rtcNewScene(impl_->device);
    rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_HIGH);
    RTCGeometry geom = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0,
                                                          RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                                          world.vertices.size()));
    for (std::size_t i = 0; i < world.vertices.size(); ++i) {
        v[3 * i] = world.vertices[i].x();
        v[3 * i + 1] = world.vertices[i].y();
        v[3 * i + 2] = world.vertices[i].z();
    }
    auto* idx = static_cast<unsigned*>(
        rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                3 * sizeof(unsigned), world.triangles.size()));
    for (std::size_t i = 0; i < world.triangles.size(); ++i) {
        for (int k = 0; k < 3; ++k) idx[3 * i + k] = world.triangles[i][k];
    }
    rtcCommitGeometry(geom);
    rtcAttachGeometry(impl_->scene, geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(impl_->scene);
    if (rtcGetDeviceError(impl_->device) != RTC_ERROR_NONE) {
        throw std::runtime_error("Embree: building the scene of '" + world.name + "' failed");
    }
}

Raycaster::~Raycaster() = default;

namespace {

void fill(RTCRayHit& rh, const Ray& r) {
    rh.ray.org_x = r.origin.x();
    rh.ray.org_y = r.origin.y();
    rh.ray.org_z = r.origin.z();
    rh.ray.dir_x = r.dir.x();
    rh.ray.dir_y = r.dir.y();
    rh.ray.dir_z = r.dir.z();
    rh.ray.tnear = 0.0f;
    rh.ray.tfar = r.tmax;
    rh.ray.time = 0.0f;
    rh.ray.mask = 0xFFFFFFFFu;
    rh.ray.id = 0;
    rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
}

RayHit result(const RTCRayHit& rh) {
    RayHit h;
    if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) {
        h.t = rh.ray.tfar;
        h.triangle = rh.hit.primID;
    }
    return h;
}

}  // namespace

RayHit Raycaster::cast(const Ray& ray) const {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRayHit rh;
    fill(rh, ray);
    rtcIntersect1(impl_->scene, &ctx, &rh);
    return result(rh);
}

void Raycaster::castBatch(std::span<const Ray> rays, std::span<RayHit> hits, bool coherent) const {
    if (hits.size() < rays.size())
        throw std::invalid_argument("Raycaster::castBatch: hits shorter than rays");
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    ctx.flags =
        coherent ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
    thread_local std::vector<RTCRayHit> buf;
    buf.resize(rays.size());
    for (std::size_t i = 0; i < rays.size(); ++i) fill(buf[i], rays[i]);
    rtcIntersect1M(impl_->scene, &ctx, buf.data(), static_cast<unsigned>(buf.size()),
                   sizeof(RTCRayHit));
    for (std::size_t i = 0; i < rays.size(); ++i) hits[i] = result(buf[i]);
}

}  // namespace handscan::sim
