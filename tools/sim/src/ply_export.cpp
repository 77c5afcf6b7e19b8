#include "handscan/sim/ply_export.hpp"

#include <cstring>
#include <fstream>

namespace handscan::sim {
namespace {

template <typename T>
void put(std::ofstream& out, T v) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));  // x86/ARM targets are little-endian, as the header says
    out.write(b, sizeof(T));
}

std::uint8_t toByte(float c) {
    return static_cast<std::uint8_t>(std::clamp(c, 0.0f, 1.0f) * 255.0f + 0.5f);
}

}  // namespace

Status writePly(const World& world, const std::string& path, bool binary) {
    std::ofstream out(path, std::ios::binary);
    if (!out)
        return {StatusCode::kIoError,
                path + ": cannot open for writing (check the directory exists and is writable)"};
    out << "ply\nformat " << (binary ? "binary_little_endian" : "ascii") << " 1.0\n"
        << "comment handscan sim scene '" << world.name << "' in world coordinates (metres, z up)\n"
        << "element vertex " << world.vertices.size()
        << "\nproperty float x\nproperty float y\nproperty float z\n"
        << "element face " << world.triangles.size()
        << "\nproperty list uchar int vertex_indices\nproperty ushort material\n"
        << "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n";
    for (const auto& v : world.vertices) {
        if (binary) {
            put(out, v.x());
            put(out, v.y());
            put(out, v.z());
        } else {
            out << v.x() << ' ' << v.y() << ' ' << v.z() << '\n';
        }
    }
    for (std::size_t i = 0; i < world.triangles.size(); ++i) {
        const auto& t = world.triangles[i];
        const std::uint16_t m = world.triangle_material[i];
        const auto& c = world.materials[m].colour;
        if (binary) {
            put<std::uint8_t>(out, 3);
            for (std::uint32_t k : t) put<std::int32_t>(out, static_cast<std::int32_t>(k));
            put(out, m);
            put(out, toByte(c[0]));
            put(out, toByte(c[1]));
            put(out, toByte(c[2]));
        } else {
            out << "3 " << t[0] << ' ' << t[1] << ' ' << t[2] << ' ' << m << ' '
                << int(toByte(c[0])) << ' ' << int(toByte(c[1])) << ' ' << int(toByte(c[2]))
                << '\n';
        }
    }
    out.flush();
    if (!out) return {StatusCode::kIoError, path + ": write failed (disk full?)"};
    return Status::ok();
}

}  // namespace handscan::sim
