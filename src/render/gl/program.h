// Shader loading: GLSL files from reel's shader folder compiled and linked into a gl::Program,
// and a cache of uniform locations.
#pragma once

#include <map>
#include <string>

#include "core/error.h"
#include "render/gl/objects.h"

namespace reel::gl {

// Links `vs` + `fs` from the folder `dir` under "#version 330 core". With `with_geometry` the
// shared vertex placement (geometry.glsl) goes before the vertex shader; `defines` goes before
// both, and the shared colour functions (color.glsl) before the fragment shader.
Result<Program> buildProgram(const GlApi& gl, const std::string& dir, const std::string& vs,
                             const std::string& fs, bool with_geometry, const std::string& defines = "");

// Uniform locations by program and name, each asked of GL once.
class UniformCache {
 public:
  GLint get(const GlApi& gl, GLuint program, const char* name);

 private:
  std::map<std::string, GLint> locations_;  // "program:name" → location
};

}  // namespace reel::gl
