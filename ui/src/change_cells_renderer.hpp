// Draws a continued scan's change cells (shm::ChangeReport: where something appeared since the
// earlier scan, or vanished) over the map: each cell a cube of the report's cell size, faces
// translucent and edges solid in its kind's colour, drawn over everything (a moved cupboard in
// the next room shows through the wall between). At most shm::kMaxChangeCells cells, uploaded
// once per report (0.5 Hz), not per frame. Needs a current OpenGL 3.3 core context.
#pragma once

#include <Eigen/Core>
#include <cstdint>

#include "handscan/core/status.hpp"
#include "handscan/shm/layout.hpp"
#include "handscan/ui/gl_program.hpp"

namespace handscan::ui {

struct Rgb8 {
    std::uint8_t r = 0, g = 0, b = 0;
};
// Neither is a colour the map's points, its path (magenta) or the device (white) use for long.
inline constexpr Rgb8 kAppearedColour{255, 140, 0};  // orange: something is here now
inline constexpr Rgb8 kVanishedColour{0, 190, 255};  // light blue: something was here
Rgb8 changeColour(shm::ChangeKind kind);

class ChangeCellsRenderer {
public:
    ChangeCellsRenderer() = default;
    ~ChangeCellsRenderer();
    ChangeCellsRenderer(const ChangeCellsRenderer&) = delete;
    ChangeCellsRenderer& operator=(const ChangeCellsRenderer&) = delete;

    [[nodiscard]] Status init();
    // The cells of `report` (its first `count`); an empty report clears them.
    void set(const shm::ChangeReport& report);
    void draw(const Eigen::Matrix4f& view_proj);
    std::size_t cells() const { return cells_; }

private:
    GlProgram program_;
    unsigned vao_ = 0, vbo_ = 0;
    std::size_t cells_ = 0;
    int face_vertices_ = 0, edge_vertices_ = 0;  // faces first in the buffer, then edges
};

}  // namespace handscan::ui
