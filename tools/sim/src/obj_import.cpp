// OBJ import through tinyobjloader (Debian libtinyobjloader-dev).
#include <tiny_obj_loader.h>

#include <algorithm>
#include <filesystem>
#include <stdexcept>

#include "handscan/sim/mesh_builder.hpp"
#include "handscan/sim/scenes.hpp"

namespace handscan::sim {
namespace {

// A texture file name says little about its look: pick the procedural texture by keywords.
TextureId textureFromName(const std::string& name) {
    std::string n = name;
    std::transform(n.begin(), n.end(), n.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (n.empty()) return TextureId::kPlaster;
    if (n.find("brick") != std::string::npos) return TextureId::kBrick;
    if (n.find("wood") != std::string::npos) return TextureId::kWood;
    if (n.find("grass") != std::string::npos) return TextureId::kGrass;
    if (n.find("leaf") != std::string::npos || n.find("foliage") != std::string::npos)
        return TextureId::kFoliage;
    if (n.find("concrete") != std::string::npos || n.find("stone") != std::string::npos)
        return TextureId::kConcrete;
    if (n.find("carpet") != std::string::npos) return TextureId::kCarpet;
    if (n.find("check") != std::string::npos || n.find("tile") != std::string::npos)
        return TextureId::kChecker;
    return TextureId::kPosters;
}

}  // namespace

Scene importObj(const std::string& path) {
    tinyobj::ObjReaderConfig config;
    config.triangulate = true;
    config.mtl_search_path = std::filesystem::path(path).parent_path().string();
    tinyobj::ObjReader reader;
    if (!reader.ParseFromFile(path, config)) {
        throw std::runtime_error(path + ": cannot import OBJ: " + reader.Error());
    }
    Scene scene;
    scene.world.name = std::filesystem::path(path).stem().string();
    scene.world.description = "imported from " + path;
    MeshBuilder b(scene.world);
    const auto& attrib = reader.GetAttrib();
    const auto& materials = reader.GetMaterials();
    for (const auto& m : materials) {
        Material mm;
        mm.name = m.name;
        mm.colour = {static_cast<float>(m.diffuse[0]), static_cast<float>(m.diffuse[1]),
                     static_cast<float>(m.diffuse[2])};
        mm.reflectivity =
            std::clamp((mm.colour[0] + mm.colour[1] + mm.colour[2]) / 3.0f, 0.02f, 0.95f);
        mm.texture = textureFromName(m.diffuse_texname);
        mm.texture_scale_m = 1.0f;
        (void)b.addMaterial(mm);
    }
    const std::uint16_t fallback =
        b.addMaterial(Material{"default", 0.6f, {0.7f, 0.7f, 0.7f}, TextureId::kPlaster, 1.0f});
    auto vtx = [&](const tinyobj::index_t& i) {
        const std::size_t k = 3 * static_cast<std::size_t>(i.vertex_index);
        return Eigen::Vector3d(attrib.vertices[k], attrib.vertices[k + 1], attrib.vertices[k + 2]);
    };
    for (const auto& shape : reader.GetShapes()) {
        const auto& mesh = shape.mesh;
        for (std::size_t f = 0; f < mesh.num_face_vertices.size(); ++f) {
            if (mesh.num_face_vertices[f] != 3)
                continue;  // triangulated above; skip degenerate faces
            const int mid = mesh.material_ids.empty() ? -1 : mesh.material_ids[f];
            const std::uint16_t m = mid >= 0 && static_cast<std::size_t>(mid) < materials.size()
                                        ? static_cast<std::uint16_t>(mid)
                                        : fallback;
            b.addTriangle(vtx(mesh.indices[3 * f]), vtx(mesh.indices[3 * f + 1]),
                          vtx(mesh.indices[3 * f + 2]), m);
        }
    }
    if (scene.world.triangles.empty()) throw std::runtime_error(path + ": OBJ holds no triangles");
    return scene;
}

}  // namespace handscan::sim
