// The face tests' scene: one face at a test resolution, `extra` keys added to it.
#pragma once

#include <string>

#include "sim/face/face_body.h"
#include "sim/world.h"

namespace reel::test {

inline std::string faceSceneText(const std::string& extra, double duration, const std::string& resolution,
                                 const std::string& cg_tolerance) {
  return R"({"format": "reel/1", "duration": )" + std::to_string(duration) +
         R"(, "fps": 30, "substeps": 2, "integrator": "implicit_euler", "implicit": {"cg_tolerance": )" + cg_tolerance +
         R"(}, "bodies": [{"type": "face", "name": "f", "resolution": )" + resolution + extra + "}]}";
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
