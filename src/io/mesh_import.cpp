#include "io/mesh_import.h"

#include <assimp/DefaultIOSystem.h>
#include <assimp/Importer.hpp>
#include <assimp/ProgressHandler.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <cctype>
#include <chrono>
#include <cstring>
#include <cmath>
#include <filesystem>
#include <regex>

#include "io/files.h"

namespace reel::io {

namespace {

namespace fs = std::filesystem;

// The files assimp opens, the mesh's own references included, pass the same checks as a scene's
// asset paths: inside the allowed folders, a regular file, within the size cap.
class GuardedIO : public Assimp::DefaultIOSystem {
 public:
  explicit GuardedIO(std::vector<std::string> roots) : roots_(std::move(roots)) {}
  bool Exists(const char* file) const override { return allowed(file) && DefaultIOSystem::Exists(file); }
  Assimp::IOStream* Open(const char* file, const char* mode) override {
    if (std::string(mode).find_first_of("wa+") != std::string::npos) return refuse(file, "opened for writing");
    if (!allowed(file)) return nullptr;
    return DefaultIOSystem::Open(file, mode);
  }
  const std::string& refused() const { return refused_; }

 private:
  bool allowed(const char* file) const {
    std::error_code ec;
    if (!insideRoots(file, roots_)) return refuse(file, "lies outside the allowed folders"), false;
    if (fs::exists(file, ec) && !fs::is_regular_file(file, ec)) return refuse(file, "is not a regular file"), false;
    if (fs::exists(file, ec) && fs::file_size(file, ec) > kMaxMeshBytes)
      return refuse(file, "is larger than the limit of " + std::to_string(kMaxMeshBytes) + " bytes"), false;
    return true;
  }
  Assimp::IOStream* refuse(const char* file, const std::string& why) const {
    if (refused_.empty()) refused_ = std::string("refers to \"") + file + "\", which " + why;
    return nullptr;
  }
  std::vector<std::string> roots_;
  mutable std::string refused_;  // the first refusal
};

// Cancels an import that runs past its budget (assimp asks between reading and each step).
class Budget : public Assimp::ProgressHandler {
 public:
  explicit Budget(double seconds) : seconds_(seconds) {}
  bool Update(float) override {
    const std::chrono::duration<double> t = std::chrono::steady_clock::now() - start_;
    over_ = over_ || t.count() > seconds_;
    return !over_;
  }
  bool over() const { return over_; }

 private:
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  double seconds_;
  bool over_ = false;
};

// Assimp's own wording, as a sentence about the file.
std::string explain(std::string what) {
  std::smatch m;
  // (assimp 5.2 fails a glTF scene without nodes, and some empty files, without a word)
  if (what.find_first_not_of(" \t\r\n") == std::string::npos) return "holds nothing to draw (no meshes in its scene)";
  if (std::regex_search(what, m, std::regex(R"(aiMesh::mFaces\[(\d+)\] is a (LINE|POINT))")))
    return "face " + m[1].str() + " has " + (m[2] == "LINE" ? "2 corners" : "1 corner") + "; a face needs 3 or more";
  if (std::regex_search(what, m, std::regex(R"(aiMesh::mFaces\[(\d+)\]::mIndices\[(\d+)\] is out of range)")))
    return "face " + m[1].str() + " refers to a vertex that does not exist";
  if (what.find("No meshes remaining") != std::string::npos) return "holds no triangles (its faces are points or lines)";
  for (const char* prefix : {"Validation failed: ", "Mesh is invalid: "})
    if (what.rfind(prefix, 0) == 0) what = what.substr(std::strlen(prefix));
  if (what.size() > 200) what = what.substr(0, 200) + "...";
  // A reader's "STL: Invalid number of vertices" or "Invalid .ply file: Vertices should ..." as
  // "not a valid STL file: invalid number of vertices".
  if (std::regex_search(what, m, std::regex(R"(^(?:([A-Za-z0-9]{2,8}) ?(?:\(\w+\))?|Invalid \.?([A-Za-z0-9]{2,8}) file): (.+)$)"))) {
    std::string format = m[1].matched ? m[1].str() : m[2].str(), rest = m[3].str();
    for (char& c : format) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    rest[0] = static_cast<char>(std::tolower(static_cast<unsigned char>(rest[0])));
    return "not a valid " + format + " file: " + rest;
  }
  return "cannot import: " + what;
}

}  // namespace

Result<TriMesh> importMesh(const std::string& path, const std::vector<std::string>& roots_in, double budget_s) {
  std::error_code ec;
  const std::vector<std::string> roots =
      roots_in.empty() ? std::vector<std::string>{fs::weakly_canonical(fs::absolute(path, ec), ec).parent_path().string()} : roots_in;
  if (Status st = scanMesh(path, roots); !st) return st.error();
  Assimp::Importer importer;
  auto* io = new GuardedIO(roots);  // the importer owns both
  auto* budget = new Budget(budget_s);
  importer.SetIOHandler(io);
  importer.SetProgressHandler(budget);
  // Points and lines are dropped; everything else becomes triangles in world space.
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  const aiScene* scene = nullptr;
  std::string failure;
  const unsigned flags = aiProcess_Triangulate | aiProcess_GenSmoothNormals | aiProcess_JoinIdenticalVertices |
                         aiProcess_PreTransformVertices | aiProcess_SortByPType | aiProcess_ValidateDataStructure;
  // (a binary PLY that this assimp would misread goes in as the same mesh in ASCII)
  const std::optional<std::string> ply = plyForAssimp(path);
  try {
    scene = ply ? importer.ReadFileFromMemory(ply->data(), ply->size(), flags, "ply") : importer.ReadFile(path, flags);
  } catch (const std::bad_alloc&) {
    failure = "out of memory while importing";
  } catch (const std::exception& e) {
    failure = e.what();
  }
  if (!io->refused().empty()) return Error(ErrorKind::BadInput, path + ": " + io->refused());
  if (budget->over())
    return Error(ErrorKind::BadInput, path + ": import took longer than the budget of " + std::to_string(static_cast<int>(budget_s)) + " s");
  if (!failure.empty()) return Error(ErrorKind::BadInput, path + ": " + explain(failure));
  if (!scene || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) || !scene->mRootNode)
    return Error(ErrorKind::BadInput, path + ": " + explain(importer.GetErrorString()));
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
