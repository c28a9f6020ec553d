#include "io/mesh_import.h"

#include <assimp/Importer.hpp>
#include <cmath>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

namespace reel::io {

Result<TriMesh> importMesh(const std::string& path) {
  Assimp::Importer importer;
  // Points and lines are dropped; everything else becomes triangles in world space.
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  const aiScene* scene = nullptr;
  try {
    scene = importer.ReadFile(path, aiProcess_Triangulate | aiProcess_GenSmoothNormals |
                                        aiProcess_JoinIdenticalVertices | aiProcess_PreTransformVertices |
                                        aiProcess_SortByPType | aiProcess_ValidateDataStructure);
  } catch (const std::exception& e) {
    return Error(ErrorKind::BadInput, path + ": cannot import: " + e.what());
  }
  if (!scene || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) || !scene->mRootNode)
    return Error(ErrorKind::BadInput, path + ": cannot import: " + importer.GetErrorString());
  std::size_t tris = 0;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) tris += scene->mMeshes[m]->mNumFaces;
  if (tris == 0) return Error(ErrorKind::BadInput, path + ": holds no triangles");
  if (tris > kMaxMeshTriangles)
    return Error(ErrorKind::BadInput, path + ": " + std::to_string(tris) + " triangles, more than the limit of " +
                                          std::to_string(kMaxMeshTriangles));
  TriMesh out;
  bool any_colour = false;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) any_colour = any_colour || scene->mMeshes[m]->HasVertexColors(0);
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* mesh = scene->mMeshes[m];
    if (!(mesh->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
    const auto base = static_cast<std::uint32_t>(out.vertexCount());
    for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
      const aiVector3D& p = mesh->mVertices[v];
      const aiVector3D n = mesh->HasNormals() ? mesh->mNormals[v] : aiVector3D(0, 1, 0);
      const aiVector3D uv = mesh->HasTextureCoords(0) ? mesh->mTextureCoords[0][v] : aiVector3D(0, 0, 0);
      // glTF and OBJ put v = 0 at the image's bottom; reel's textures start at the top row.
      out.addVertex(Vec3(p.x, p.y, p.z), Vec3(n.x, n.y, n.z), uv.x, 1.0 - uv.y);
      if (any_colour) {
        const aiColor4D c = mesh->HasVertexColors(0) ? mesh->mColors[0][v] : aiColor4D(1, 1, 1, 1);
        out.colors.insert(out.colors.end(), {c.r, c.g, c.b});
      }
    }
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      if (face.mNumIndices != 3) continue;
      out.indices.insert(out.indices.end(), {base + face.mIndices[0], base + face.mIndices[1], base + face.mIndices[2]});
    }
  }
  for (float x : out.positions)
    if (!std::isfinite(x)) return Error(ErrorKind::BadInput, path + ": holds non-finite coordinates");
  if (out.indices.empty()) return Error(ErrorKind::BadInput, path + ": holds no triangles");
  return out;
}

}  // namespace reel::io
