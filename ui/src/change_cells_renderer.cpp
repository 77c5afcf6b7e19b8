#include "change_cells_renderer.hpp"

#include <array>
#include <vector>

#include "gl_api.hpp"

namespace handscan::ui {
namespace {

const char* kVs = R"(#version 330 core
layout(location = 0) in vec3 a_pos;
layout(location = 1) in vec3 a_colour;
uniform mat4 u_view_proj;
out vec3 v_colour;
void main() { gl_Position = u_view_proj * vec4(a_pos, 1.0); v_colour = a_colour; }
)";

const char* kFs = R"(#version 330 core
in vec3 v_colour;
uniform float u_alpha;
out vec4 frag;
void main() { frag = vec4(v_colour, u_alpha); }
)";

constexpr float kFaceAlpha = 0.35f;  // the map stays readable through a cell

// The cube's corner i: bit 0 x, bit 1 y, bit 2 z (0: low side, 1: high side).
Eigen::Vector3f corner(const Eigen::Vector3f& c, float half, int i) {
    return c +
           half * Eigen::Vector3f(i & 1 ? 1.0f : -1.0f, i & 2 ? 1.0f : -1.0f, i & 4 ? 1.0f : -1.0f);
}

// Two triangles per face (corners as above), and the 12 edges.
constexpr std::array<int, 36> kFaces = {0, 1, 3, 0, 3, 2, 4, 6, 7, 4, 7, 5, 0, 4, 5, 0, 5, 1,
                                        2, 3, 7, 2, 7, 6, 0, 2, 6, 0, 6, 4, 1, 5, 7, 1, 7, 3};
constexpr std::array<int, 24> kEdges = {0, 1, 2, 3, 4, 5, 6, 7, 0, 2, 1, 3,
                                        4, 6, 5, 7, 0, 4, 1, 5, 2, 6, 3, 7};

void put(std::vector<float>& v, const Eigen::Vector3f& p, const Rgb8& c) {
    v.insert(v.end(), {p.x(), p.y(), p.z(), c.r / 255.0f, c.g / 255.0f, c.b / 255.0f});
}

}  // namespace

Rgb8 changeColour(shm::ChangeKind kind) {
    return kind == shm::ChangeKind::kVanished ? kVanishedColour : kAppearedColour;
}

ChangeCellsRenderer::~ChangeCellsRenderer() {
    if (vao_) glDeleteVertexArrays(1, &vao_);
    if (vbo_) glDeleteBuffers(1, &vbo_);
}

Status ChangeCellsRenderer::init() {
    if (Status s = program_.build("change cells", kVs, kFs); !s) return s;
    glGenVertexArrays(1, &vao_);
    glGenBuffers(1, &vbo_);
    glBindVertexArray(vao_);
    glBindBuffer(GL_ARRAY_BUFFER, vbo_);
    describePositionColourVertices();
    glBindVertexArray(0);
    return Status::ok();
}

void ChangeCellsRenderer::set(const shm::ChangeReport& report) {
    const std::size_t n = std::min<std::size_t>(report.count, shm::kMaxChangeCells);
    const float half = 0.5f * report.cell_m;
    std::vector<float> faces, edges;
    faces.reserve(n * kFaces.size() * 6);
    edges.reserve(n * kEdges.size() * 6);
    cells_ = 0;
    for (std::size_t k = 0; k < n; ++k) {
        const shm::ChangeCellRecord& c = report.cells[k];
        const Eigen::Vector3f centre(c.x_m, c.y_m, c.z_m);
        if (!centre.allFinite() || !(half > 0.0f)) continue;
        const Rgb8 colour = changeColour(static_cast<shm::ChangeKind>(c.kind));
        for (int i : kFaces) put(faces, corner(centre, half, i), colour);
        for (int i : kEdges) put(edges, corner(centre, half, i), colour);
        ++cells_;
    }
    face_vertices_ = static_cast<int>(faces.size() / 6);
    edge_vertices_ = static_cast<int>(edges.size() / 6);
    faces.insert(faces.end(), edges.begin(), edges.end());
    glBindBuffer(GL_ARRAY_BUFFER, vbo_);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(faces.size() * sizeof(float)),
                 faces.empty() ? nullptr : faces.data(), GL_DYNAMIC_DRAW);
}

void ChangeCellsRenderer::draw(const Eigen::Matrix4f& view_proj) {
    if (cells_ == 0) return;
    glUseProgram(program_.id());
    glUniformMatrix4fv(program_.uniform("u_view_proj"), 1, GL_FALSE, view_proj.data());
    glBindVertexArray(vao_);
    glDisable(GL_DEPTH_TEST);  // over the map, also behind walls
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glUniform1f(program_.uniform("u_alpha"), kFaceAlpha);
    glDrawArrays(GL_TRIANGLES, 0, face_vertices_);
    glUniform1f(program_.uniform("u_alpha"), 1.0f);
    glDrawArrays(GL_LINES, face_vertices_, edge_vertices_);
    glDisable(GL_BLEND);
    glEnable(GL_DEPTH_TEST);
    glBindVertexArray(0);
    glUseProgram(0);
}

}  // namespace handscan::ui
