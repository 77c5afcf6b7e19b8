// StartPlacement: the operator's "I stand here, facing there" on an earlier scan's map before
// continuing it (section 9's start hint, as `--initial-pose` gives it to replay): a tap on the
// map is the position, a drag from it (or a second tap) the heading. Screen points become map
// points by casting the tap's ray through the view camera (the matrices the GPU draws with) onto
// a horizontal plane; the height is that of the earlier scan's path nearest the tap (the device
// is carried at about the height it was carried then, on that floor). Pure math, unit-tested.
#pragma once

#include <Eigen/Geometry>
#include <optional>
#include <span>
#include <string>

#include "handscan/shm/layout.hpp"

namespace handscan::ui {

// Where the ray through window pixel (px, py) meets the plane z = plane_z, in map coordinates.
// `view_proj`: projection * view of the 3D view; (vx, vy, vw, vh): the view's rectangle in
// window pixels from the top-left. None when the ray runs parallel to the plane or meets it
// behind the eye.
std::optional<Eigen::Vector3f> screenToMap(const Eigen::Matrix4f& view_proj, float vx, float vy,
                                           float vw, float vh, float px, float py, float plane_z);

// The height of the path point nearest (x, y) horizontally; none for an empty path.
std::optional<float> pathHeightNear(std::span<const shm::TrackPoint> path, float x, float y);

class StartPlacement {
public:
    // A touch lands on the map: the position (a new placement keeps the heading given before).
    void press(const Eigen::Vector3f& at_map);
    // The finger moved to `at_map` while down: the heading points there, once 0.2 m away.
    void drag(const Eigen::Vector3f& at_map);
    void clear() { *this = StartPlacement(); }

    bool placed() const { return position_.has_value(); }
    const std::optional<Eigen::Vector3f>& position() const { return position_; }
    float headingRad() const { return heading_rad_; }
    // The body pose it means: at the position, level, its x axis along the heading.
    Eigen::Isometry3d pose() const;
    // "x,y,z,qx,qy,qz,qw" (TUM order), the continue command's pose= value.
    std::string poseText() const;

private:
    std::optional<Eigen::Vector3f> position_;
    float heading_rad_ = 0.0f;
};

}  // namespace handscan::ui
