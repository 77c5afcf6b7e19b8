// Reads the geometry of a PLY file: vertex x/y/z (any scalar type) and, when present, faces
// (vertex_indices / vertex_index lists, polygons fan-triangulated). ASCII and binary little-endian;
// other elements and properties are skipped. Errors name the file and what is wrong.
#pragma once

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "handscan/core/status.hpp"

namespace handscan::eval {

struct PlyGeometry {
    std::vector<Eigen::Vector3d> vertices;
    std::vector<std::array<std::uint32_t, 3>> triangles;
};

Result<PlyGeometry> readPly(const std::string& path);
Result<PlyGeometry> parsePly(const std::string& bytes, const std::string& name = "<bytes>");

}  // namespace handscan::eval
