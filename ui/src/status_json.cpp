#include "status_json.hpp"

#include <cstdio>
#include <fstream>
#include <sstream>

namespace handscan::ui {
namespace {

std::string quote(const std::string& s) {
    std::string out = "\"";
    for (const char c : s) {
        switch (c) {
            case '"':
                out += "\\\"";
                break;
            case '\\':
                out += "\\\\";
                break;
            case '\n':
                out += "\\n";
                break;
            case '\t':
                out += "\\t";
                break;
            default:
                if (static_cast<unsigned char>(c) < 0x20) {
                    char buf[8];
                    std::snprintf(buf, sizeof buf, "\\u%04x", c);
                    out += buf;
                } else {
                    out += c;
                }
        }
    }
    return out + "\"";
}

std::string line(const Line& l) {
    return "{\"text\": " + quote(l.text) + ", \"health\": " + quote(toString(l.health)) + "}";
}

std::string lines(const std::vector<Line>& ls) {
    std::string out = "[";
    for (std::size_t i = 0; i < ls.size(); ++i) out += (i ? ", " : "") + line(ls[i]);
    return out + "]";
}

}  // namespace

std::string statusJson(const StatusTexts& t, const FrameFacts& f) {
    std::ostringstream o;
    o << "{\n  \"connection\": " << line(t.connection)
      << ",\n  \"scan_state\": " << quote(t.scan_state) << ",\n  \"elapsed\": " << quote(t.elapsed)
      << ",\n  \"distance\": " << quote(t.distance) << ",\n  \"points\": " << quote(t.points)
      << ",\n  \"storage\": " << line(t.storage) << ",\n  \"sensors\": " << lines(t.sensors)
      << ",\n  \"modules\": " << lines(t.modules) << ",\n  \"warnings\": " << lines(t.warnings)
      << ",\n  \"export\": " << line(t.export_line) << ",\n  \"message\": " << quote(t.message)
      << ",\n  \"dof\": [";
    for (int i = 0; t.dof_valid && i < shm::kDofCount; ++i)
        o << (i ? ", " : "") << quote(toString(t.dof[i]));
    o << "],\n  \"view\": {\"camera\": " << quote(toString(f.camera))
      << ", \"colour\": " << quote(toString(f.colour))
      << ", \"coverage\": " << (f.coverage ? "true" : "false") << ", \"framebuffer\": ["
      << f.framebuffer_w << ", " << f.framebuffer_h << "], \"viewport\": [" << f.view_px.x << ", "
      << f.view_px.y << ", " << f.view_px.w << ", " << f.view_px.h
      << "], \"view_proj_col_major\": [";
    for (int i = 0; i < 16; ++i) o << (i ? ", " : "") << f.view_proj.data()[i];
    o << "]},\n  \"map\": {\"points_drawn\": " << f.points_drawn
      << ", \"track_points\": " << f.track_points << ", \"epoch\": " << f.epoch << "}\n}\n";
    return o.str();
}

Status writeTextFile(const std::string& path, const std::string& text) {
    std::ofstream out(path, std::ios::trunc);
    out << text;
    out.close();
    if (!out) return {StatusCode::kIoError, path + ": cannot write (does the directory exist?)"};
    return Status::ok();
}

}  // namespace handscan::ui
