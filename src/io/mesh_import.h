// Triangle meshes from files through assimp: OBJ, PLY, STL, glTF (.gltf, .glb).
#pragma once

#include <string>
#include <vector>

#include "core/error.h"
#include "core/mesh.h"
#include "io/mesh_scan.h"

namespace reel::io {

inline const char* const kMeshExtensions[] = {".obj", ".ply", ".stl", ".gltf", ".glb"};
// Wall-clock budget of one import, after the scan (a backstop: the scan bounds the work).
inline constexpr double kMeshImportSeconds = 60.0;

// All meshes of the file in one, triangulated, with smooth normals where the file has none,
// node transforms applied, per-vertex colours kept. The file is scanned first (io/mesh_scan.h).
// Every file the importer opens (the mesh, and what it refers to: an OBJ's mtllib, a glTF's
// buffers) must lie inside `roots` (default: the mesh's own folder) and be at most kMaxMeshBytes;
// a reference elsewhere is an error naming it. Importer failures, empty files, meshes over
// kMaxMeshTriangles and imports over `budget_s` seconds are BadInput errors naming the path.
Result<TriMesh> importMesh(const std::string& path, const std::vector<std::string>& roots = {},
                           double budget_s = kMeshImportSeconds);

}  // namespace reel::io
