// Triangle meshes from files through assimp: OBJ, PLY, STL, glTF (.gltf, .glb).
#pragma once

#include <string>

#include "core/error.h"
#include "core/mesh.h"

namespace reel::io {

inline constexpr std::size_t kMaxMeshTriangles = 2'000'000;
inline const char* const kMeshExtensions[] = {".obj", ".ply", ".stl", ".gltf", ".glb"};

// All meshes of the file in one, triangulated, with smooth normals where the file has none,
// node transforms applied, per-vertex colours kept. Importer failures, empty files and meshes
// over kMaxMeshTriangles are BadInput errors naming the path.
Result<TriMesh> importMesh(const std::string& path);

}  // namespace reel::io
