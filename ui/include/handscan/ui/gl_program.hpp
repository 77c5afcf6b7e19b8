// A linked GLSL program (OpenGL 3.3 core) with compile and link errors turned into messages that
// name the shader and the driver's log.
#pragma once

#include <string>

#include "handscan/core/status.hpp"

namespace handscan::ui {

class GlProgram {
public:
    GlProgram() = default;
    ~GlProgram();
    GlProgram(const GlProgram&) = delete;
    GlProgram& operator=(const GlProgram&) = delete;

    [[nodiscard]] Status build(const std::string& name, const char* vertex_src,
                               const char* fragment_src);
    unsigned id() const { return id_; }
    int uniform(const char* name) const;

private:
    unsigned id_ = 0;
};

// For the bound vertex array and GL_ARRAY_BUFFER: vertices of six floats, attribute 0 the
// position (x, y, z), attribute 1 the colour (r, g, b in 0..1).
void describePositionColourVertices();

}  // namespace handscan::ui
