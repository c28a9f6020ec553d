// The face tests' scene: one face at a test resolution, `extra` keys added to it.
#pragma once

#include <fstream>
#include <string>

#include "core/mesh.h"

#include "sim/face/face_body.h"
#include "sim/world.h"

namespace reel::test {

inline std::string faceSceneText(const std::string& extra, double duration, const std::string& resolution,
                                 const std::string& cg_tolerance) {
  return R"({"format": "reel/1", "duration": )" + std::to_string(duration) +
         R"(, "fps": 30, "substeps": 2, "integrator": "implicit_euler", "implicit": {"cg_tolerance": )" + cg_tolerance +
         R"(}, "bodies": [{"type": "face", "name": "f", "resolution": )" + resolution + extra + "}]}";
}

// A user's face mesh for the tests: a ball of radius 0.1 m as an OBJ file at `path` (its seam and
// poles welded by the reader).
inline void writeBallObj(const std::string& path) {
  const TriMesh ball = makeUvSphere(0.1, 32, 24);
  std::ofstream obj(path);
  for (std::size_t v = 0; v < ball.vertexCount(); ++v)
    obj << "v " << ball.positions[3 * v] << " " << ball.positions[3 * v + 1] << " " << ball.positions[3 * v + 2] << "\n";
  for (std::size_t t = 0; t < ball.triangleCount(); ++t)
    obj << "f " << ball.indices[3 * t] + 1 << " " << ball.indices[3 * t + 1] + 1 << " " << ball.indices[3 * t + 2] + 1 << "\n";
}

// The World's (first) face.
inline const FaceBody& face(const World& w) { return *w.first<FaceBody>(); }

// The vertex whose rest position is nearest p (in the head frame).
inline std::size_t vertexNear(const FaceBody& f, const Vec3& p) {
  std::size_t best = 0;
  for (std::size_t k = 0; k < f.surface().size(); ++k)
    if ((f.surface().skin[k] - p).squaredNorm() < (f.surface().skin[best] - p).squaredNorm()) best = k;
  return best;
}

}  // namespace reel::test
