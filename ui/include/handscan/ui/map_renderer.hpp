// Draws the live map: millions of display points, the walked trajectory and the device. Points
// live in a GPU buffer that grows by doubling (with a GPU-side copy of what is there), and each
// frame uploads only the points that are new since the last frame, so the cost of a frame is the
// draw, not the transfer. Needs a current OpenGL 3.3 core context.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>

#include "handscan/core/status.hpp"
#include "handscan/shm/layout.hpp"
#include "handscan/ui/gl_program.hpp"

namespace handscan::ui {

enum class ColourMode { kRgb = 0, kHeight = 1, kIntensity = 2 };
const char* toString(ColourMode mode);

// A vertex buffer that is appended to and grows by doubling; the VAO describing it is rebuilt by
// the owner after a reallocation (see generation()).
class GrowingVertexBuffer {
public:
    GrowingVertexBuffer(std::size_t record_bytes, std::size_t initial_records);
    ~GrowingVertexBuffer();
    GrowingVertexBuffer(const GrowingVertexBuffer&) = delete;
    GrowingVertexBuffer& operator=(const GrowingVertexBuffer&) = delete;

    void append(const void* records, std::size_t n);
    void clear() { count_ = 0; }
    std::size_t count() const { return count_; }
    std::size_t capacity() const { return capacity_; }
    unsigned buffer() const { return vbo_; }
    std::uint64_t generation() const { return generation_; }  // bumps when the buffer is replaced
    std::uint64_t bytesUploaded() const { return bytes_uploaded_; }

private:
    void reserve(std::size_t records);
    std::size_t record_bytes_;
    std::size_t initial_;
    std::size_t capacity_ = 0;
    std::size_t count_ = 0;
    unsigned vbo_ = 0;
    std::uint64_t generation_ = 0;
    std::uint64_t bytes_uploaded_ = 0;
};

class MapRenderer {
public:
    MapRenderer();
    ~MapRenderer();
    MapRenderer(const MapRenderer&) = delete;
    MapRenderer& operator=(const MapRenderer&) = delete;

    [[nodiscard]] Status init();
    void reset();  // a new scan or a new pipeline: drop everything
    void appendPoints(std::span<const shm::DisplayPoint> points);
    void appendTrack(std::span<const shm::TrackPoint> track);
    void setDevice(const std::optional<shm::PoseRecord>& pose) { device_ = pose; }

    // Draws into the current viewport. `view_proj` = projection * view. With more points than
    // `max_points` (0 = no limit), every k-th point is drawn so that a slow (software) renderer
    // stays interactive; the decimation is uniform because it strides through append order.
    void draw(const Eigen::Matrix4f& view_proj, ColourMode mode, float point_size_px,
              std::size_t max_points = 0);
    std::size_t lastDrawnPoints() const { return last_drawn_; }

    std::size_t pointCount() const { return points_.count(); }
    std::size_t pointCapacity() const { return points_.capacity(); }
    std::size_t trackCount() const { return track_.count(); }
    std::uint64_t bytesUploaded() const { return points_.bytesUploaded() + track_.bytesUploaded(); }
    float minZ() const { return min_z_; }
    float maxZ() const { return max_z_; }

private:
    void bindVertexArrays(std::size_t stride);
    GrowingVertexBuffer points_;
    GrowingVertexBuffer track_;
    GlProgram point_program_;
    GlProgram line_program_;
    unsigned points_vao_ = 0, track_vao_ = 0, device_vao_ = 0, device_vbo_ = 0;
    std::uint64_t points_gen_ = ~0ull, track_gen_ = ~0ull;
    std::size_t stride_ = 1;  // points per drawn point in points_vao_
    std::size_t last_drawn_ = 0;
    std::optional<shm::PoseRecord> device_;
    float min_z_ = 0.0f, max_z_ = 3.0f;
    bool have_z_ = false;
};

}  // namespace handscan::ui
