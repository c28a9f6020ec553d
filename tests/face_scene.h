// The face tests' scene: one face at a test resolution, `extra` keys added to it.
#pragma once

#include <string>

namespace reel::test {

inline std::string faceSceneText(const std::string& extra, double duration, const std::string& resolution,
                                 const std::string& cg_tolerance) {
  return R"({"format": "reel/1", "duration": )" + std::to_string(duration) +
         R"(, "fps": 30, "substeps": 2, "integrator": "implicit_euler", "implicit": {"cg_tolerance": )" + cg_tolerance +
         R"(}, "bodies": [{"type": "face", "name": "f", "resolution": )" + resolution + extra + "}]}";
}

}  // namespace reel::test
