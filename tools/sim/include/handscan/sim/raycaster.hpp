// Ray casting against the world with Embree 3: single rays and batches (Embree ray streams, used
// by the laser and the cameras). Hits report the distance along the unit direction and the
// triangle index (material, normal and texture come from the World).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>

#include "handscan/sim/world.hpp"

namespace handscan::sim {

struct RayHit {
    float t = std::numeric_limits<float>::infinity();  // metres along the unit direction
    std::uint32_t triangle = kNoHit;
    static constexpr std::uint32_t kNoHit = 0xFFFFFFFFu;
    bool hit() const { return triangle != kNoHit; }
};

struct Ray {
    Eigen::Vector3f origin;
    Eigen::Vector3f dir;  // unit
    float tmax = std::numeric_limits<float>::infinity();
};

class Raycaster {
public:
    // Builds the acceleration structure (single-threaded: deterministic and one core).
    explicit Raycaster(const World& world);
    ~Raycaster();
    Raycaster(const Raycaster&) = delete;
    Raycaster& operator=(const Raycaster&) = delete;

    const World& world() const { return world_; }
    RayHit cast(const Ray& ray) const;
    // Casts many rays at once (Embree stream); `coherent` when neighbouring rays are similar
    // (camera pixels), which lets Embree trace them as packets.
    void castBatch(std::span<const Ray> rays, std::span<RayHit> hits, bool coherent = false) const;

private:
    struct Impl;
    const World& world_;
    std::unique_ptr<Impl> impl_;
};

}  // namespace handscan::sim
