#include "render/gl/program.h"

#include <fstream>
#include <sstream>

namespace reel::gl {

namespace {

bool readText(const std::string& path, std::string& out) {
  std::ifstream in(path);
  if (!in) return false;
  std::stringstream ss;
  ss << in.rdbuf();
  out = ss.str();
  return true;
}

Result<Shader> compile(const GlApi& gl, GLenum type, const std::string& src, const std::string& name) {
  Shader sh = makeShader(gl, type);
  const char* p = src.c_str();
  gl.ShaderSource(sh.id(), 1, &p, nullptr);
  gl.CompileShader(sh.id());
  GLint ok = 0;
  gl.GetShaderiv(sh.id(), GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[4096];
    gl.GetShaderInfoLog(sh.id(), sizeof log, nullptr, log);
    return Error(ErrorKind::Internal, "shader " + name + " does not compile: " + log);
  }
  return sh;
}

}  // namespace

Result<Program> buildProgram(const GlApi& gl, const std::string& dir, const std::string& vs,
                             const std::string& fs, bool with_geometry, const std::string& defines) {
  std::string vsrc, fsrc, geo, color;
  if (!readText(dir + "/" + vs, vsrc) || !readText(dir + "/" + fs, fsrc) || !readText(dir + "/color.glsl", color) ||
      (with_geometry && !readText(dir + "/geometry.glsl", geo)))
    return Error(ErrorKind::Internal, "shaders not found in " + dir + " (set REEL_SHADERS)");
  const std::string head = "#version 330 core\n";
  auto v = compile(gl, GL_VERTEX_SHADER, head + defines + geo + vsrc, vs);
  if (!v.ok()) return v.error();
  auto f = compile(gl, GL_FRAGMENT_SHADER, head + defines + color + fsrc, fs);
  if (!f.ok()) return f.error();
  // The shaders are deleted on return; attached, they live on in the program.
  Program p = makeProgram(gl);
  gl.AttachShader(p.id(), v.value().id());
  gl.AttachShader(p.id(), f.value().id());
  gl.LinkProgram(p.id());
  GLint ok = 0;
  gl.GetProgramiv(p.id(), GL_LINK_STATUS, &ok);  // (attribute 5 is a_color in every program)
  if (!ok) {
    char log[4096];
    gl.GetProgramInfoLog(p.id(), sizeof log, nullptr, log);
    return Error(ErrorKind::Internal, "shaders " + vs + " + " + fs + " do not link: " + log);
  }
  return p;
}

GLint UniformCache::get(const GlApi& gl, GLuint program, const char* name) {
  const std::string key = std::to_string(program) + ":" + name;
  auto it = locations_.find(key);
  if (it != locations_.end()) return it->second;
  const GLint l = gl.GetUniformLocation(program, name);
  locations_[key] = l;
  return l;
}

}  // namespace reel::gl
