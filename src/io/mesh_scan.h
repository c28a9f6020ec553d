// A look at a mesh file before assimp reads it. Assimp's readers trust what a file declares: a
// PLY header that never ends makes its reader loop forever, a 190-byte PLY that declares 10^8
// faces makes it allocate gigabytes, and an OBJ is read whole before its size is known. The scan
// reads the header (PLY, binary STL, glTF/GLB) or counts the lines (OBJ, ASCII STL), and refuses
// a file whose counts pass reel's caps or need more bytes than the file has, so that what assimp
// then allocates is bounded by the caps and by the file's size.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/error.h"

namespace reel::io {

inline constexpr std::size_t kMaxMeshTriangles = 2'000'000;
inline constexpr std::size_t kMaxMeshVertices = 3 * kMaxMeshTriangles;  // a triangle soup
inline constexpr std::size_t kMaxMeshBytes = 256u << 20;                 // a mesh file, or a file it refers to

// Checks the file at PATH (its extension picks the format: .obj .ply .stl .gltf .glb). `roots`:
// the folders a glTF's buffers may come from. The error (BadInput) names the file, the line or
// field where that helps, and the limit.
Status scanMesh(const std::string& path, const std::vector<std::string>& roots);

// A binary PLY whose data begins with a whitespace byte (0x09, 0x0A, 0x0D or 0x20: the first byte
// of about one binary PLY in sixty) is misread by Debian 12's assimp (5.2), which skips those bytes
// as the header's and reads the whole body shifted. For such a file (already scanned) this is the
// same mesh as an ASCII PLY, for assimp to read from memory; nullopt for any other file.
std::optional<std::string> plyForAssimp(const std::string& path);

}  // namespace reel::io
