#include "handscan/ui/map_renderer.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "gl_api.hpp"

namespace handscan::ui {
namespace {

const char* kPointVs = R"(#version 330 core
layout(location = 0) in vec3 a_pos;
layout(location = 1) in vec4 a_rgbi;   // red, green, blue, intensity: normalised bytes
uniform mat4 u_view_proj;
uniform int u_mode;                    // 0 rgb, 1 height, 2 intensity
uniform vec2 u_z_range;
uniform float u_point_size;
out vec3 v_colour;
vec3 ramp(float t) {                   // blue - cyan - green - yellow - red
    t = clamp(t, 0.0, 1.0);
    return clamp(vec3(1.5 - abs(4.0 * t - 3.0), 1.5 - abs(4.0 * t - 2.0), 1.5 - abs(4.0 * t - 1.0)), 0.0, 1.0);
}
void main() {
    gl_Position = u_view_proj * vec4(a_pos, 1.0);
    gl_PointSize = u_point_size;
    if (u_mode == 1) v_colour = ramp((a_pos.z - u_z_range.x) / max(u_z_range.y - u_z_range.x, 1e-3));
    else if (u_mode == 2) v_colour = vec3(a_rgbi.a);
    else v_colour = a_rgbi.rgb;
}
)";

const char* kPointFs = R"(#version 330 core
in vec3 v_colour;
out vec4 frag;
void main() { frag = vec4(v_colour, 1.0); }
)";

const char* kLineVs = R"(#version 330 core
layout(location = 0) in vec3 a_pos;
layout(location = 1) in vec3 a_colour;
uniform mat4 u_view_proj;
uniform float u_point_size;
out vec3 v_colour;
void main() { gl_Position = u_view_proj * vec4(a_pos, 1.0); gl_PointSize = u_point_size; v_colour = a_colour; }
)";

const char* kLineFs = R"(#version 330 core
in vec3 v_colour;
out vec4 frag;
void main() { frag = vec4(v_colour, 1.0); }
)";

}  // namespace

const char* toString(ColourMode mode) {
    switch (mode) {
        case ColourMode::kRgb:
            return "rgb";
        case ColourMode::kHeight:
            return "height";
        case ColourMode::kIntensity:
            return "intensity";
    }
    return "?";
}

GrowingVertexBuffer::GrowingVertexBuffer(std::size_t record_bytes, std::size_t initial_records)
    : record_bytes_(record_bytes), initial_(initial_records) {}

GrowingVertexBuffer::~GrowingVertexBuffer() {
    if (vbo_) glDeleteBuffers(1, &vbo_);
}

void GrowingVertexBuffer::reserve(std::size_t records) {
    if (records <= capacity_ && vbo_) return;
    const std::size_t cap = std::max({records, capacity_ * 2, initial_});
    GLuint next = 0;
    glGenBuffers(1, &next);
    glBindBuffer(GL_COPY_WRITE_BUFFER, next);
    glBufferData(GL_COPY_WRITE_BUFFER, static_cast<GLsizeiptr>(cap * record_bytes_), nullptr,
                 GL_DYNAMIC_DRAW);
    if (vbo_ && count_ > 0) {
        // Keep what is on the GPU: copy there instead of uploading everything again.
        glBindBuffer(GL_COPY_READ_BUFFER, vbo_);
        glCopyBufferSubData(GL_COPY_READ_BUFFER, GL_COPY_WRITE_BUFFER, 0, 0,
                            static_cast<GLsizeiptr>(count_ * record_bytes_));
    }
    if (vbo_) glDeleteBuffers(1, &vbo_);
    vbo_ = next;
    capacity_ = cap;
    ++generation_;
}

void GrowingVertexBuffer::append(const void* records, std::size_t n) {
    if (n == 0) return;
    reserve(count_ + n);
    glBindBuffer(GL_ARRAY_BUFFER, vbo_);
    glBufferSubData(GL_ARRAY_BUFFER, static_cast<GLintptr>(count_ * record_bytes_),
                    static_cast<GLsizeiptr>(n * record_bytes_), records);
    count_ += n;
    bytes_uploaded_ += n * record_bytes_;
}

MapRenderer::MapRenderer()
    : points_(sizeof(shm::DisplayPoint), 1u << 20), track_(sizeof(shm::TrackPoint), 4096) {}

MapRenderer::~MapRenderer() {
    const GLuint vaos[] = {points_vao_, track_vao_, device_vao_};
    glDeleteVertexArrays(3, vaos);
    if (device_vbo_) glDeleteBuffers(1, &device_vbo_);
}

Status MapRenderer::init() {
    if (Status s = point_program_.build("map points", kPointVs, kPointFs); !s) return s;
    if (Status s = line_program_.build("trajectory", kLineVs, kLineFs); !s) return s;
    glGenVertexArrays(1, &points_vao_);
    glGenVertexArrays(1, &track_vao_);
    glGenVertexArrays(1, &device_vao_);
    glGenBuffers(1, &device_vbo_);
    glBindVertexArray(device_vao_);
    glBindBuffer(GL_ARRAY_BUFFER, device_vbo_);
    glBufferData(GL_ARRAY_BUFFER, 64 * 6 * sizeof(float), nullptr, GL_DYNAMIC_DRAW);
    describePositionColourVertices();
    glBindVertexArray(0);
    return Status::ok();
}

void MapRenderer::reset() {
    points_.clear();
    track_.clear();
    have_z_ = false;
    min_z_ = 0.0f;
    max_z_ = 3.0f;
}

void MapRenderer::appendPoints(std::span<const shm::DisplayPoint> pts) {
    for (const shm::DisplayPoint& p : pts) {
        if (!std::isfinite(p.z_m)) continue;
        if (!have_z_) {
            min_z_ = max_z_ = p.z_m;
            have_z_ = true;
        }
        min_z_ = std::min(min_z_, p.z_m);
        max_z_ = std::max(max_z_, p.z_m);
    }
    points_.append(pts.data(), pts.size());
}

void MapRenderer::appendTrack(std::span<const shm::TrackPoint> track) {
    track_.append(track.data(), track.size());
}

void MapRenderer::bindVertexArrays(std::size_t stride) {
    if ((points_gen_ != points_.generation() || stride_ != stride) && points_.buffer()) {
        const auto bytes = static_cast<GLsizei>(stride * sizeof(shm::DisplayPoint));
        glBindVertexArray(points_vao_);
        glBindBuffer(GL_ARRAY_BUFFER, points_.buffer());
        glEnableVertexAttribArray(0);
        glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, bytes, nullptr);
        glEnableVertexAttribArray(1);
        glVertexAttribPointer(1, 4, GL_UNSIGNED_BYTE, GL_TRUE, bytes,
                              reinterpret_cast<void*>(offsetof(shm::DisplayPoint, r)));
        points_gen_ = points_.generation();
        stride_ = stride;
    }
    if (track_gen_ != track_.generation() && track_.buffer()) {
        glBindVertexArray(track_vao_);
        glBindBuffer(GL_ARRAY_BUFFER, track_.buffer());
        glEnableVertexAttribArray(0);
        glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(shm::TrackPoint),
                              reinterpret_cast<void*>(offsetof(shm::TrackPoint, x_m)));
        glDisableVertexAttribArray(1);  // constant colour, set per draw
        track_gen_ = track_.generation();
    }
    glBindVertexArray(0);
}

void MapRenderer::draw(const Eigen::Matrix4f& view_proj, ColourMode mode, float point_size_px,
                       std::size_t max_points) {
    const std::size_t n = points_.count();
    const std::size_t stride =
        max_points > 0 && n > max_points ? (n + max_points - 1) / max_points : 1;
    bindVertexArrays(stride);
    last_drawn_ = n / stride;
    glEnable(GL_DEPTH_TEST);
    glEnable(GL_PROGRAM_POINT_SIZE);
    if (points_.count() > 0) {
        glUseProgram(point_program_.id());
        glUniformMatrix4fv(point_program_.uniform("u_view_proj"), 1, GL_FALSE, view_proj.data());
        glUniform1i(point_program_.uniform("u_mode"), static_cast<int>(mode));
        glUniform2f(point_program_.uniform("u_z_range"), min_z_, max_z_);
        glUniform1f(point_program_.uniform("u_point_size"), point_size_px);
        glBindVertexArray(points_vao_);
        glDrawArrays(GL_POINTS, 0, static_cast<GLsizei>(last_drawn_));
    }
    glUseProgram(line_program_.id());
    glUniformMatrix4fv(line_program_.uniform("u_view_proj"), 1, GL_FALSE, view_proj.data());
    glUniform1f(line_program_.uniform("u_point_size"), 14.0f);
    if (track_.count() > 1) {
        glBindVertexArray(track_vao_);
        glVertexAttrib3f(1, 1.0f, 0.2f, 0.9f);  // magenta: stands out against scanned colours
        glDrawArrays(GL_LINE_STRIP, 0, static_cast<GLsizei>(track_.count()));
    }
    if (device_) {
        // The device: a big white dot and its body axes (x red, y green, z blue), 0.6 m long.
        const Eigen::Vector3f p(static_cast<float>(device_->position_m[0]),
                                static_cast<float>(device_->position_m[1]),
                                static_cast<float>(device_->position_m[2]));
        const Eigen::Quaternionf q(static_cast<float>(device_->orientation_xyzw[3]),
                                   static_cast<float>(device_->orientation_xyzw[0]),
                                   static_cast<float>(device_->orientation_xyzw[1]),
                                   static_cast<float>(device_->orientation_xyzw[2]));
        const Eigen::Matrix3f R = q.normalized().toRotationMatrix();
        float v[7 * 6];
        const auto put = [&v](int i, const Eigen::Vector3f& pos, const Eigen::Vector3f& c) {
            for (int k = 0; k < 3; ++k) v[i * 6 + k] = pos[k], v[i * 6 + 3 + k] = c[k];
        };
        put(0, p, Eigen::Vector3f(1, 1, 1));
        for (int a = 0; a < 3; ++a) {
            const Eigen::Vector3f c = Eigen::Vector3f::Unit(a);
            put(1 + 2 * a, p, c);
            put(2 + 2 * a, p + 0.6f * R.col(a), c);
        }
        glBindBuffer(GL_ARRAY_BUFFER, device_vbo_);
        glBufferSubData(GL_ARRAY_BUFFER, 0, sizeof v, v);
        glBindVertexArray(device_vao_);
        glDisable(GL_DEPTH_TEST);  // always visible, even inside walls
        glDrawArrays(GL_POINTS, 0, 1);
        glDrawArrays(GL_LINES, 1, 6);
        glEnable(GL_DEPTH_TEST);
    }
    glBindVertexArray(0);
    glUseProgram(0);
}

}  // namespace handscan::ui
