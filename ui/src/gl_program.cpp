#include "handscan/ui/gl_program.hpp"

#include "gl_api.hpp"

namespace handscan::ui {
namespace {

Result<GLuint> compile(const std::string& name, GLenum type, const char* src) {
    const GLuint s = glCreateShader(type);
    glShaderSource(s, 1, &src, nullptr);
    glCompileShader(s);
    GLint ok = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[2048] = {};
        glGetShaderInfoLog(s, sizeof log, nullptr, log);
        glDeleteShader(s);
        return Status{StatusCode::kInvalidArgument,
                      name + (type == GL_VERTEX_SHADER ? " vertex" : " fragment") +
                          " shader does not compile: " + log};
    }
    return s;
}

}  // namespace

GlProgram::~GlProgram() {
    if (id_) glDeleteProgram(id_);
}

Status GlProgram::build(const std::string& name, const char* vertex_src, const char* fragment_src) {
    auto vs = compile(name, GL_VERTEX_SHADER, vertex_src);
    if (!vs) return vs.status();
    auto fs = compile(name, GL_FRAGMENT_SHADER, fragment_src);
    if (!fs) {
        glDeleteShader(*vs);
        return fs.status();
    }
    id_ = glCreateProgram();
    glAttachShader(id_, *vs);
    glAttachShader(id_, *fs);
    glLinkProgram(id_);
    glDeleteShader(*vs);
    glDeleteShader(*fs);
    GLint ok = 0;
    glGetProgramiv(id_, GL_LINK_STATUS, &ok);
    if (!ok) {
        char log[2048] = {};
        glGetProgramInfoLog(id_, sizeof log, nullptr, log);
        return {StatusCode::kInvalidArgument, name + " program does not link: " + log};
    }
    return Status::ok();
}

int GlProgram::uniform(const char* name) const { return glGetUniformLocation(id_, name); }

void describePositionColourVertices() {
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), nullptr);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float),
                          reinterpret_cast<void*>(3 * sizeof(float)));
}

}  // namespace handscan::ui
