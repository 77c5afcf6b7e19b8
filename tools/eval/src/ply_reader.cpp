#include "handscan/eval/ply_reader.hpp"

#include <fmt/format.h>

#include <cstring>
#include <fstream>
#include <sstream>

namespace handscan::eval {
namespace {

enum class Scalar { kI8, kU8, kI16, kU16, kI32, kU32, kF32, kF64 };

bool scalarFromName(const std::string& s, Scalar& out) {
    static const std::pair<const char*, Scalar> kNames[] = {
        {"char", Scalar::kI8},    {"int8", Scalar::kI8},     {"uchar", Scalar::kU8},
        {"uint8", Scalar::kU8},   {"short", Scalar::kI16},   {"int16", Scalar::kI16},
        {"ushort", Scalar::kU16}, {"uint16", Scalar::kU16},  {"int", Scalar::kI32},
        {"int32", Scalar::kI32},  {"uint", Scalar::kU32},    {"uint32", Scalar::kU32},
        {"float", Scalar::kF32},  {"float32", Scalar::kF32}, {"double", Scalar::kF64},
        {"float64", Scalar::kF64}};
    for (const auto& [name, type] : kNames) {
        if (s == name) {
            out = type;
            return true;
        }
    }
    return false;
}

std::size_t scalarSize(Scalar s) {
    switch (s) {
        case Scalar::kI8:
        case Scalar::kU8:
            return 1;
        case Scalar::kI16:
        case Scalar::kU16:
            return 2;
        case Scalar::kI32:
        case Scalar::kU32:
        case Scalar::kF32:
            return 4;
        case Scalar::kF64:
            return 8;
    }
    return 0;
}

struct Property {
    std::string name;
    bool is_list = false;
    Scalar count_type = Scalar::kU8;
    Scalar type = Scalar::kF32;
};

struct Element {
    std::string name;
    std::size_t count = 0;
    std::vector<Property> properties;
};

// Reads values one at a time from either encoding.
class ValueReader {
public:
    ValueReader(const std::string& bytes, std::size_t pos, bool binary)
        : b_(bytes), pos_(pos), binary_(binary) {}
    bool read(Scalar t, double& v) {
        if (!binary_) {
            while (pos_ < b_.size() && std::isspace(static_cast<unsigned char>(b_[pos_]))) ++pos_;
            if (pos_ >= b_.size()) return false;
            const char* begin = b_.data() + pos_;
            char* end = nullptr;
            v = std::strtod(begin, &end);
            if (end == begin) return false;
            pos_ += static_cast<std::size_t>(end - begin);
            return true;
        }
        const std::size_t n = scalarSize(t);
        if (pos_ + n > b_.size()) return false;
        const char* p = b_.data() + pos_;
        pos_ += n;
        switch (t) {
            case Scalar::kI8: {
                std::int8_t x;
                std::memcpy(&x, p, 1);
                v = x;
                break;
            }
            case Scalar::kU8: {
                std::uint8_t x;
                std::memcpy(&x, p, 1);
                v = x;
                break;
            }
            case Scalar::kI16: {
                std::int16_t x;
                std::memcpy(&x, p, 2);
                v = x;
                break;
            }
            case Scalar::kU16: {
                std::uint16_t x;
                std::memcpy(&x, p, 2);
                v = x;
                break;
            }
            case Scalar::kI32: {
                std::int32_t x;
                std::memcpy(&x, p, 4);
                v = x;
                break;
            }
            case Scalar::kU32: {
                std::uint32_t x;
                std::memcpy(&x, p, 4);
                v = x;
                break;
            }
            case Scalar::kF32: {
                float x;
                std::memcpy(&x, p, 4);
                v = x;
                break;
            }
            case Scalar::kF64: {
                double x;
                std::memcpy(&x, p, 8);
                v = x;
                break;
            }
        }
        return true;
    }

private:
    const std::string& b_;
    std::size_t pos_;
    bool binary_;
};

}  // namespace

Result<PlyGeometry> parsePly(const std::string& bytes, const std::string& name) {
    auto error = [&](const std::string& what) {
        return Status(StatusCode::kInvalidArgument, fmt::format("{}: {}", name, what));
    };
    const std::size_t header_end = bytes.find("end_header");
    if (bytes.rfind("ply", 0) != 0 || header_end == std::string::npos) {
        return error("not a PLY file (no 'ply' magic or no 'end_header')");
    }
    std::size_t data_pos = bytes.find('\n', header_end);
    if (data_pos == std::string::npos) return error("header not terminated by a newline");
    ++data_pos;

    std::istringstream header(bytes.substr(0, header_end));
    std::string line;
    bool binary = false;
    std::vector<Element> elements;
    int line_no = 0;
    while (std::getline(header, line)) {
        ++line_no;
        std::istringstream ls(line);
        std::string key;
        ls >> key;
        if (key == "format") {
            std::string fmt_name;
            ls >> fmt_name;
            if (fmt_name == "ascii") {
                binary = false;
            } else if (fmt_name == "binary_little_endian") {
                binary = true;
            } else {
                return error(
                    fmt::format("header line {}: format '{}' not supported (ascii or "
                                "binary_little_endian)",
                                line_no, fmt_name));
            }
        } else if (key == "element") {
            Element e;
            ls >> e.name >> e.count;
            if (!ls)
                return error(fmt::format("header line {}: malformed element '{}'", line_no, line));
            elements.push_back(e);
        } else if (key == "property") {
            if (elements.empty())
                return error(fmt::format("header line {}: property before any element", line_no));
            Property p;
            std::string type;
            ls >> type;
            if (type == "list") {
                std::string ct, vt;
                ls >> ct >> vt >> p.name;
                p.is_list = true;
                if (!scalarFromName(ct, p.count_type) || !scalarFromName(vt, p.type)) {
                    return error(
                        fmt::format("header line {}: unknown list types in '{}'", line_no, line));
                }
            } else {
                ls >> p.name;
                if (!scalarFromName(type, p.type)) {
                    return error(
                        fmt::format("header line {}: unknown property type '{}'", line_no, type));
                }
            }
            elements.back().properties.push_back(p);
        }
    }

    PlyGeometry out;
    ValueReader reader(bytes, data_pos, binary);
    for (const Element& e : elements) {
        const bool is_vertex = e.name == "vertex";
        const bool is_face = e.name == "face";
        int ix = -1, iy = -1, iz = -1;
        for (std::size_t i = 0; i < e.properties.size(); ++i) {
            if (e.properties[i].name == "x") ix = static_cast<int>(i);
            if (e.properties[i].name == "y") iy = static_cast<int>(i);
            if (e.properties[i].name == "z") iz = static_cast<int>(i);
        }
        if (is_vertex && (ix < 0 || iy < 0 || iz < 0))
            return error("vertex element lacks x, y or z");
        if (is_vertex) out.vertices.reserve(e.count);
        std::vector<double> list;
        for (std::size_t r = 0; r < e.count; ++r) {
            Eigen::Vector3d v = Eigen::Vector3d::Zero();
            for (std::size_t pi = 0; pi < e.properties.size(); ++pi) {
                const Property& p = e.properties[pi];
                double value = 0.0;
                if (!p.is_list) {
                    if (!reader.read(p.type, value)) {
                        return error(
                            fmt::format("truncated: {} {} of {} ends early", e.name, r, e.count));
                    }
                    if (static_cast<int>(pi) == ix) v.x() = value;
                    if (static_cast<int>(pi) == iy) v.y() = value;
                    if (static_cast<int>(pi) == iz) v.z() = value;
                    continue;
                }
                double count = 0.0;
                if (!reader.read(p.count_type, count) || count < 0) {
                    return error(
                        fmt::format("truncated: {} {} of {} ends early", e.name, r, e.count));
                }
                list.resize(static_cast<std::size_t>(count));
                for (double& x : list) {
                    if (!reader.read(p.type, x)) {
                        return error(
                            fmt::format("truncated: {} {} of {} ends early", e.name, r, e.count));
                    }
                }
                if (is_face && (p.name == "vertex_indices" || p.name == "vertex_index")) {
                    for (std::size_t k = 2; k < list.size(); ++k) {  // fan triangulation
                        out.triangles.push_back({static_cast<std::uint32_t>(list[0]),
                                                 static_cast<std::uint32_t>(list[k - 1]),
                                                 static_cast<std::uint32_t>(list[k])});
                    }
                }
            }
            if (is_vertex) out.vertices.push_back(v);
        }
    }
    for (const auto& t : out.triangles) {
        for (std::uint32_t i : t) {
            if (i >= out.vertices.size()) {
                return error(fmt::format("face refers to vertex {} but there are only {}", i,
                                         out.vertices.size()));
            }
        }
    }
    return out;
}

Result<PlyGeometry> readPly(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    if (!f) return Status(StatusCode::kNotFound, fmt::format("{}: cannot open PLY file", path));
    std::stringstream ss;
    ss << f.rdbuf();
    return parsePly(ss.str(), path);
}

}  // namespace handscan::eval
