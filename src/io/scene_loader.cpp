// The top-level scene loader: the format, the scene's own keys, render, camera, lights, objects,
// and each body through its kind's reader (io/scene/<kind>.cpp, chosen by `type`).
#include "io/scene_loader.h"

#include <algorithm>
#include <filesystem>
#include <map>
#include <set>

#include "io/environment_file.h"
#include "io/files.h"
#include "io/json_reader.h"
#include "io/scene/reader.h"
#include "io/scene/readers.h"

namespace reel::io {
namespace {

// render.environment: "sky" (the background's colours as a sky), or an object with one of `sky`
// (its colours) or `file`, and intensity, rotation_deg, background. Prefiltered here, once.
void readEnvironment(const Json& j, RenderDesc& r, Diagnostics& d) {
  EnvironmentDesc& e = r.environment;
  const std::string p = "/render/environment";
  e.zenith = r.background_top;
  e.horizon = r.background_bottom;
  e.ground = r.background_bottom * 0.35;
  RadianceMap map;
  if (j.is_string()) {
    if (j.get<std::string>() != "sky") {
      d.error(p, "expected \"sky\" or an object with `sky` or `file`, got \"" + j.get<std::string>() + "\"");
      return;
    }
    e.kind = EnvironmentDesc::Kind::Sky;
  } else {
    Obj o(j, p, d);
    if (!o.ok()) return;
    e.intensity = o.number("intensity", e.intensity, kNonNeg);
    e.rotation_deg = o.number("rotation_deg", e.rotation_deg, Range{-360.0, 360.0});
    e.background = o.boolean("background", e.background);
    const bool sky = o.has("sky"), file = o.has("file");
    if (sky == file) d.error(p, sky ? "give sky or file, not both" : "missing `sky` or `file`");
    if (sky) {
      e.kind = EnvironmentDesc::Kind::Sky;
      const Json* s = o.raw("sky");
      if (s->is_object()) {
        Obj so(*s, p + "/sky", d);
        e.zenith = so.vec3("zenith", e.zenith, kNonNeg);
        e.horizon = so.vec3("horizon", e.horizon, kNonNeg);
        e.ground = so.vec3("ground", e.ground, kNonNeg);
        so.finish();
      } else if (!s->is_boolean() || !s->get<bool>()) {
        d.error(p + "/sky", "expected true or an object with zenith, horizon, ground, got " + typeName(*s));
      }
    } else if (file) {
      e.kind = EnvironmentDesc::Kind::File;
      if (auto f = o.string("file")) {
        auto path = resolveAsset(d.file(), *f, {".hdr", ".exr", ".png"}, std::size_t{256} << 20);
        auto m = path.ok() ? readEnvironmentMap(path.value()) : Result<RadianceMap>(path.error());
        if (!m.ok()) {
          d.error(p + "/file", m.error().headline());
          return;
        }
        e.file = path.value();
        map = std::move(m.value());
      }
    }
    o.finish();
  }
  if (!d.empty()) return;
  if (e.kind == EnvironmentDesc::Kind::Sky) map = proceduralSky(e.zenith, e.horizon, e.ground);
  if (e.kind != EnvironmentDesc::Kind::None) {
    auto maps = prefilterEnvironment(map, e.intensity, e.rotation_deg);
    maps->background = e.background;
    e.maps = maps;
  }
}

void readRender(const Json& j, RenderDesc& r, Diagnostics& d) {
  Obj o(j, "/render", d);
  r.width = o.integer("width", r.width, 16, 16384);
  r.height = o.integer("height", r.height, 16, 16384);
  if (auto s = o.integer("samples", 1, 4)) {
    if (*s == 3)
      d.error("/render/samples", "must be 1, 2 or 4, got 3");
    else
      r.samples = static_cast<int>(*s);
  }
  if (const Json* bg = o.raw("background")) {
    if (bg->is_object()) {
      Obj g(*bg, "/render/background", d);
      r.background_top = g.vec3("top", r.background_top, kNonNeg);
      r.background_bottom = g.vec3("bottom", r.background_bottom, kNonNeg);
      if (const Json* gl = g.raw("glow")) {
        Obj w(*gl, "/render/background/glow", d);
        BackgroundGlow& b = r.background_glow;
        b.color = w.vec3("color", b.color, kNonNeg);
        b.x = w.number("x", b.x, Range{-1.0, 2.0});
        b.y = w.number("y", b.y, Range{-1.0, 2.0});
        b.radius = w.number("radius", b.radius, Range::closed(1e-3, 10.0));
        w.finish();
      }
      g.finish();
    } else if (auto c = readVec3(*bg, "/render/background", d, kNonNeg)) {
      r.background_top = r.background_bottom = *c;
    }
  }
  r.tonemap = o.choice("tonemap", r.tonemap, {"none", "aces"});
  r.exposure = o.number("exposure", r.exposure, Range{-16.0, 16.0});
  if (const Json* e = o.raw("environment")) readEnvironment(*e, r, d);
  // ao: true (0.5 m, strength 1), false, or {radius, strength}.
  if (const Json* a = o.raw("ao")) {
    if (a->is_boolean()) {
      r.ao_radius = a->get<bool>() ? 0.5 : 0.0;
    } else {
      Obj g(*a, "/render/ao", d);
      r.ao_radius = g.number("radius", 0.5, Range{0.0, 100.0});
      r.ao_strength = g.number("strength", r.ao_strength, Range{0.0, 8.0});
      g.finish();
    }
  }
  // motion_blur: true (a 180° shutter, 5 pictures), false, or {shutter_deg, samples}.
  if (const Json* m = o.raw("motion_blur")) {
    if (m->is_boolean()) {
      r.shutter_deg = m->get<bool>() ? 180.0 : 0.0;
    } else {
      Obj g(*m, "/render/motion_blur", d);
      r.shutter_deg = g.number("shutter_deg", 180.0, Range{0.0, 360.0});
      r.shutter_samples = g.integer("samples", r.shutter_samples, 2, 32);
      g.finish();
    }
  }
  if (const Json* f = o.raw("fog")) {
    Obj g(*f, "/render/fog", d);
    r.fog_color = g.vec3("color", r.fog_color, kNonNeg);
    r.fog_density = g.number("density", r.fog_density, kNonNeg);
    g.finish();
  }
  o.finish();
}

// `follow` or `frame`: a body's name, or {body, lag, mode (follow) or margin (frame)}.
void readCameraRig(Obj& o, CameraRigDesc& r, Diagnostics& d) {
  const bool follow = o.has("follow"), frame = o.has("frame");
  if (!follow && !frame) return;
  if (follow && frame) {
    d.error("/camera/frame", "give follow or frame, not both (frame follows the body it frames)");
    return;
  }
  const std::string key = follow ? "follow" : "frame", p = "/camera/" + key;
  const Json& j = *o.raw(key);
  r.mode = follow ? CameraRigDesc::Mode::Track : CameraRigDesc::Mode::Frame;
  r.path = p;
  if (j.is_string()) {
    r.body = j.get<std::string>();
  } else if (j.is_object()) {
    r.path = p + "/body";
    Obj ro(j, p, d);
    r.body = ro.string("body", true).value_or("");
    r.lag = ro.number("lag", r.lag, Range{0.0, 60.0});
    if (follow && ro.choice("mode", "track", {"track", "pan"}) == "pan") r.mode = CameraRigDesc::Mode::Pan;
    if (frame) r.margin = ro.number("margin", r.margin, Range{0.1, 100.0});
    ro.finish();
  } else {
    d.error(p, "expected a body's name or an object with `body`, got " + typeName(j));
  }
  if (r.body.empty()) {  // reported above, or an empty name: nothing to look up
    if (j.is_string()) d.error(p, "must name a body");
    r.path.clear();
  }
}

void readCamera(const Json& j, CameraDesc& c, Diagnostics& d) {
  Obj o(j, "/camera", d);
  readCameraRig(o, c.rig, d);
  if (const Json* f = o.raw("depth_of_field")) {
    Obj g(*f, "/camera/depth_of_field", d);
    c.aperture = g.number("aperture", kNonNeg, true).value_or(0.0);
    c.focus_distance = g.number("focus_distance", 0.0, kNonNeg);
    c.lens_samples = g.integer("samples", c.lens_samples, 2, 64);
    g.finish();
  }
  c.position = o.vec3("position", c.position);
  c.target = o.vec3("target", c.target);
  c.up = o.vec3("up", c.up);
  c.fov_deg = o.number("fov_deg", c.fov_deg, Range{0.0, 180.0, true, true});
  if (c.up.norm() == 0) d.error("/camera/up", "must not be the zero vector");
  if ((c.position - c.target).norm() == 0) d.error("/camera/target", "must differ from the camera position");
  if (const Json* keys = o.raw("keys")) {
    if (!keys->is_array()) {
      d.error("/camera/keys", "expected a list of keyframes, got " + typeName(*keys));
    } else {
      for (std::size_t i = 0; i < keys->size(); ++i) {
        const std::string p = childPath("/camera/keys", i);
        Obj k((*keys)[i], p, d);
        CameraKey key;
        key.time = k.number("time", kNonNeg, true).value_or(0.0);
        key.position = k.vec3("position", c.position);
        key.target = k.vec3("target", c.target);
        key.fov_deg = k.number("fov_deg", c.fov_deg, Range{0.0, 180.0, true, true});
        if ((key.position - key.target).norm() == 0) d.error(childPath(p, "target"), "must differ from the camera position");
        k.finish();
        if (!c.keys.empty() && key.time <= c.keys.back().time)
          d.error(childPath(p, "time"), "keyframe times must increase");
        c.keys.push_back(key);
      }
    }
  }
  o.finish();
}

void readLights(const Json& j, std::vector<LightDesc>& lights, Diagnostics& d) {
  if (!j.is_array()) {
    d.error("/lights", "expected a list of lights, got " + typeName(j));
    return;
  }
  if (j.size() > 8) d.error("/lights", "at most 8 lights, got " + std::to_string(j.size()));
  for (std::size_t i = 0; i < j.size(); ++i) {
    const std::string p = childPath("/lights", i);
    Obj o(j[i], p, d);
    LightDesc l;
    const std::string type = o.choice("type", "", {"directional", "point", "ambient"});
    if (!o.has("type") && o.ok()) d.error(childPath(p, "type"), "missing required key");
    l.color = o.vec3("color", l.color, kNonNeg);
    l.intensity = o.number("intensity", l.intensity, kNonNeg);
    if (type == "directional") {
      l.kind = LightKind::Directional;
      l.direction = o.vec3("direction", l.direction);
      if (l.direction.norm() == 0) d.error(childPath(p, "direction"), "must not be the zero vector");
      l.shadows = o.boolean("shadows", false);
      l.size = o.number("angle_deg", 0.0, Range{0.0, 30.0});
    } else if (type == "point") {
      l.kind = LightKind::Point;
      l.position = o.vec3("position", Range::any(), true).value_or(l.position);
      l.shadows = o.boolean("shadows", false);
      l.size = o.number("radius", 0.0, kNonNeg);
    } else if (type == "ambient") {
      l.kind = LightKind::Ambient;
    }
    if (!type.empty()) o.finish();
    lights.push_back(l);
  }
  if (std::count_if(lights.begin(), lights.end(), [](const LightDesc& l) { return l.shadows; }) > 2)
    d.error("/lights", "at most 2 lights may cast shadows");
}

// Reads `name` and `type` of an object or body; checks the name is unique.
std::pair<std::string, std::string> readIdentity(Obj& o, const std::vector<std::string>& types,
                                                 std::size_t index, std::set<std::string>& names) {
  std::string type = o.choice("type", "", types);
  if (o.ok() && !o.has("type")) o.diag().error(childPath(o.path(), "type"), "missing required key");
  std::string name = o.string("name").value_or((type.empty() ? "item" : type) + "_" + std::to_string(index));
  if (name.empty()) o.diag().error(childPath(o.path(), "name"), "must not be empty");
  else if (!names.insert(name).second)
    o.diag().error(childPath(o.path(), "name"), "duplicate name \"" + name + "\" (every object and body needs its own)");
  return {name, type};
}

// "line:col" (both from 1) of a byte offset.
std::string lineCol(const std::string& text, std::size_t at) {
  std::size_t line = 1, col = 1;
  for (std::size_t i = 0; i < at && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      col = 1;
    } else {
      ++col;
    }
  }
  return std::to_string(line) + ":" + std::to_string(col);
}

// Keys given twice in one object, which nlohmann would keep silently (the last wins); strict
// loaders refuse them, and so does reel: "file:line:col: /path: duplicate key "k" (first at
// line:col)". The text has parsed already, so the scan follows only strings, comments and nesting.
std::vector<std::string> duplicateKeys(const std::string& text, const std::string& file) {
  struct Frame {
    bool object;
    std::string path;
    std::map<std::string, std::size_t> keys;  // → offset of the first
    std::string key;                          // the last key read
    std::size_t index = 0;                    // of an array's current element
    bool expect_key = true;
  };
  std::vector<Frame> stack;
  std::vector<std::string> out;
  const std::size_t npos = std::string::npos;
  for (std::size_t i = 0; i < text.size();) {
    const char c = text[i];
    if (c == '\0') break;  // where the parser stops too
    if (c == '/' && i + 1 < text.size() && (text[i + 1] == '/' || text[i + 1] == '*')) {
      const bool line = text[i + 1] == '/';
      i = line ? text.find_first_of(std::string("\n\r\0", 3), i + 2) : text.find("*/", i + 2);
      if (i == npos) break;
      i += line ? 0 : 2;
      continue;
    }
    if (c == '"') {
      std::size_t j = i + 1;
      for (bool esc = false; j < text.size(); ++j) {
        if (esc) esc = false;
        else if (text[j] == '\\') esc = true;
        else if (text[j] == '"') break;
      }
      if (!stack.empty() && stack.back().object && stack.back().expect_key) {
        Frame& f = stack.back();
        const std::string raw = text.substr(i, j + 1 - i);
        const Json decoded = raw.find('\\') == npos ? Json() : Json::parse(raw, nullptr, false);
        f.key = decoded.is_string() ? decoded.get<std::string>() : raw.substr(1, raw.size() - 2);
        f.expect_key = false;
        const auto [first, fresh] = f.keys.emplace(f.key, i);
        if (!fresh && out.size() < 20)
          out.push_back(file + ":" + lineCol(text, i) + ": " + childPath(f.path, f.key) + ": duplicate key \"" + f.key +
                        "\" (first at " + lineCol(text, first->second) + ")");
      }
      i = j + 1;
      continue;
    }
    if (c == '{' || c == '[') {
      std::string path;
      if (!stack.empty()) path = stack.back().object ? childPath(stack.back().path, stack.back().key) : childPath(stack.back().path, stack.back().index);
      stack.push_back({c == '{', std::move(path), {}, {}, 0, true});
    } else if ((c == '}' || c == ']') && !stack.empty()) {
      stack.pop_back();
    } else if (c == ',' && !stack.empty()) {
      if (stack.back().object) stack.back().expect_key = true;
      else ++stack.back().index;
    }
    ++i;
  }
  return out;
}

}  // namespace

Result<Json> parseJson(const std::string& text, const std::string& file) {
  try {
    Json j = Json::parse(text, nullptr, /*allow_exceptions=*/true, /*ignore_comments=*/true);
    if (auto dup = duplicateKeys(text, file); !dup.empty()) return Error(ErrorKind::BadInput, std::move(dup));
    return j;
  } catch (const Json::parse_error& e) {
    // Position from the byte offset; the reason from nlohmann's message, cut short (it quotes
    // the whole failing token, which can be megabytes).
    const std::size_t at = std::min<std::size_t>(e.byte > 0 ? e.byte - 1 : 0, text.size());
    std::string what = e.what();
    const std::size_t colon = what.find(": ", what.find("parse error"));
    what = colon == std::string::npos ? what : what.substr(colon + 2);
    if (what.size() > 200) what = what.substr(0, 200) + "...";
    return Error(ErrorKind::BadInput, file + ":" + lineCol(text, at) + ": " + what);
  } catch (const Json::exception& e) {
    // Number overflow (1e999): nlohmann gives no position, so find the literal.
    const std::string what = e.what();
    const std::string key = "number overflow parsing '";
    const std::size_t k = what.find(key);
    if (k != std::string::npos) {
      const std::string lit = what.substr(k + key.size(), what.find('\'', k + key.size()) - k - key.size());
      const std::size_t at = text.find(lit);
      return Error(ErrorKind::BadInput, file + ":" + lineCol(text, at == std::string::npos ? 0 : at) + ": number " +
                                            lit.substr(0, 40) + " is too large (numbers must be finite)");
    }
    return Error(ErrorKind::BadInput, file + ": " + what.substr(0, 200));
  }
}

namespace {

// The scene's own keys: format, name, duration, rates, seed, gravity, wind, integrator.
void readSceneKeys(Obj& o, SceneDesc& s) {
  Diagnostics& d = o.diag();
  if (auto f = o.string("format", true); f && *f != "reel/1")
    d.error("/format", "unsupported format \"" + *f + "\" (this reel reads \"reel/1\")");
  s.name = o.string("name").value_or(std::filesystem::path(s.file).stem().string());
  s.duration = o.number("duration", Range{0.0, 1e6, true, false}, true).value_or(s.duration);
  s.fps = o.integer("fps", s.fps, 1, 1000);
  const bool substeps_given = o.has("substeps");
  s.substeps = o.integer("substeps", s.substeps, 1, 1000000);
  if (auto seed = o.integer("seed", 0, 9007199254740991ll)) s.seed = static_cast<std::uint64_t>(*seed);
  s.gravity = o.vec3("gravity", s.gravity);
  if (const Json* w = o.raw("wind")) {
    Obj wo(*w, "/wind", d);
    s.wind.velocity = wo.vec3("velocity", s.wind.velocity);
    s.wind.gust = wo.number("gust", 0.0, kNonNeg);
    s.wind.gust_period = wo.number("gust_period", s.wind.gust_period, kPos);
    wo.finish();
  }
  std::vector<std::string> integrators(kIntegratorNames.begin(), kIntegratorNames.end());
  s.integrator = *integratorFromName(o.choice("integrator", "symplectic_euler", integrators));
  s.auto_substeps = o.boolean("auto_substeps", false);
  // Implicit Euler and BDF2 need no small step for stability: by default they take Blender's
  // default quality, 5 steps a frame.
  if (!substeps_given && implicitIntegrator(s.integrator)) s.substeps = kImplicitSubsteps;
  if (const Json* im = o.raw("implicit")) {
    Obj io(*im, "/implicit", d);
    s.implicit.tolerance_given = io.has("cg_tolerance");
    s.implicit.cg_tolerance = io.number("cg_tolerance", s.implicit.cg_tolerance, Range{0.0, 1.0, true, true});
    s.implicit.cg_max_iterations = io.integer("cg_max_iterations", s.implicit.cg_max_iterations, 1, 100000);
    const std::string solver = io.choice("solver", "auto", {"auto", "cg", "direct"});
    s.implicit.solver = solver == "cg" ? LinearSolver::Cg : solver == "direct" ? LinearSolver::Direct : LinearSolver::Auto;
    io.finish();
  }
  if (s.frameCount() < 1) d.error("/duration", "too short for one frame at this fps");

}

// `water`: density and currents; sources and sinks name objects (read after the objects).
void readWater(Obj& o, SceneDesc& s) {
  const Json* w = o.raw("water");
  if (!w) return;
  Obj wo(*w, "/water", o.diag());
  s.water.density = wo.number("density", s.water.density, Range::closed(0.0, 1e5));
  readList(wo, "currents", [&](Obj& c) {
    CurrentDesc cd;
    const std::string type = c.choice("type", "uniform", {"uniform", "source", "sink"});
    if (type == "uniform") {
      cd.velocity = c.vec3("velocity", cd.velocity, Range::closed(-1000.0, 1000.0));
      cd.amplitude = c.vec3("amplitude", cd.amplitude, Range::closed(-1000.0, 1000.0));
      cd.period = c.number("period", cd.period, Range{0.0, 1e6, true, false});
    } else {
      cd.kind = type == "source" ? CurrentDesc::Kind::Source : CurrentDesc::Kind::Sink;
      cd.object = c.string("object", true).value_or("");
      cd.collider = objectIndex(s, cd.object);
      if (cd.collider < 0 && !cd.object.empty())
        c.diag().error(childPath(c.path(), "object"), "names no object of the scene: \"" + cd.object + "\"");
      cd.rate = c.number("rate", Range{0.0, 1e6, true, false}, true).value_or(0.0);
      cd.core = c.number("core", cd.core, Range{0.0, 1e4, true, false});
    }
    s.water.currents.push_back(cd);
  });
  wo.finish();
}

void readObjects(Obj& o, SceneDesc& s, std::set<std::string>& names) {
  Diagnostics& d = o.diag();
  if (const Json* objs = o.raw("objects")) {
    if (!objs->is_array()) {
      d.error("/objects", "expected a list of objects, got " + typeName(*objs));
    } else {
      for (std::size_t i = 0; i < objs->size(); ++i) {
        Obj ob(objs->at(i), childPath("/objects", i), d);
        ObjectDesc od;
        od.path = ob.path();
        auto [name, type] = readIdentity(ob, kObjectTypes, i, names);
        od.name = name;
        if (type.empty()) continue;  // unknown type: its keys cannot be checked
        readObject(ob, od, type);
        ob.finish();
        if (od.kind() == ObjectKind::Mesh && !od.as<MeshObjectShape>().mesh) continue;  // its error is reported
        s.objects.push_back(std::move(od));
      }
    }
  }
}

// Each body: the keys every body has here, the rest through its kind's reader.
void readBodies(Obj& o, SceneDesc& s, std::set<std::string>& names, std::span<const BodyReaderRow> kinds) {
  Diagnostics& d = o.diag();
  std::vector<std::string> body_types;
  for (const BodyReaderRow& k : kinds) body_types.push_back(k.type);
  if (const Json* bodies = o.raw("bodies")) {
    if (!bodies->is_array()) {
      d.error("/bodies", "expected a list of bodies, got " + typeName(*bodies));
    } else {
      for (std::size_t i = 0; i < bodies->size(); ++i) {
        Obj bo(bodies->at(i), childPath("/bodies", i), d);
        BodyDesc bd;
        bd.path = bo.path();
        auto [name, type] = readIdentity(bo, body_types, i, names);
        bd.name = name;
        bd.type = type;
        if (type.empty()) continue;
        const auto kind = std::find_if(kinds.begin(), kinds.end(), [&](const BodyReaderRow& k) { return bd.type == k.type; });
        bd.params = kind->read(bo, bd, s);
        readMaterial(bo, bd.material);
        bd.node_radius = bo.number("node_radius", bd.node_radius, kPos);
        bo.finish();
        s.bodies.push_back(std::move(bd));
      }
    }
  }
}

// Totals over all bodies, so that no scene can exhaust the machine's memory; per-species
// surfaces must name a species of some body.
void checkBodies(const SceneDesc& s, Diagnostics& d) {
  long long nodes = 0, springs = 0;
  std::vector<std::string> species;
  for (const BodyDesc& b : s.bodies) {
    const auto [bn, bs] = b.params->nodesAndSprings();
    nodes += bn;
    springs += bs;
    for (std::string& sp : b.params->speciesNames()) species.push_back(std::move(sp));
  }
  auto checkSpecies = [&](const SpeciesSurfaces& per, const std::string& path) {
    for (const auto& [name, sf] : per)
      if (std::find(species.begin(), species.end(), name) == species.end()) {
        const std::string near = nearest(name, species);
        d.error(childPath(childPath(childPath(path, "surface"), "species"), name),
                "unknown species \"" + name + "\"" + (near.empty() ? "" : " (did you mean \"" + near + "\"?)"));
      }
  };
  for (const ObjectDesc& ob : s.objects) checkSpecies(ob.species_surface, ob.path);
  for (const BodyDesc& b : s.bodies) {
    // The objects rigid bodies are (their first copy: the same keys), and bodies' own surfaces.
    if (!b.params->ownObjects().empty()) checkSpecies(b.params->ownObjects().front().species_surface, b.params->ownObjects().front().path);
    if (const SpeciesSurfaces* per = b.params->speciesSurfaces()) checkSpecies(*per, b.path);
  }
  if (nodes > kMaxSceneNodes)
    d.error("/bodies", std::to_string(nodes) + " nodes in all, more than the limit of " + std::to_string(kMaxSceneNodes));
  if (springs > kMaxSceneSprings)
    d.error("/bodies", std::to_string(springs) + " springs in all, more than the limit of " + std::to_string(kMaxSceneSprings));
}

}  // namespace

Result<SceneDesc> parseScene(const std::string& text, const std::string& file, std::span<const BodyReaderRow> kinds) {
  auto root = parseJson(text, file);
  if (!root.ok()) return root.error();
  Diagnostics d(file);
  SceneDesc s;
  s.file = file;
  Obj o(root.value(), "", d);
  if (!o.ok()) return Error(ErrorKind::BadInput, d.lines());
  readSceneKeys(o, s);
  if (const Json* r = o.raw("render")) readRender(*r, s.render, d);
  if (const Json* c = o.raw("camera")) readCamera(*c, s.camera, d);
  if (const Json* l = o.raw("lights")) {
    s.has_lights = true;
    readLights(*l, s.lights, d);
  }
  std::set<std::string> names;  // of objects and bodies: each unique
  readObjects(o, s, names);
  readWater(o, s);
  readBodies(o, s, names, kinds);
  // Each dynamic object moves as a rigid body of its own, after the scene's bodies.
  for (std::size_t k = 0; k < s.objects.size(); ++k) {
    const ObjectDesc& ob = s.objects[k];
    if (!ob.free_body) continue;
    BodyDesc bd;
    bd.name = ob.name;
    bd.type = "rigid";
    bd.path = ob.path;
    bd.material = ob.material;
    bd.params = rigidFromObject(ob, k, d);
    s.bodies.push_back(std::move(bd));
  }
  checkBodies(s, d);
  if (const CameraRigDesc& rig = s.camera.rig; rig.mode != CameraRigDesc::Mode::None && !rig.path.empty() &&
      std::none_of(s.bodies.begin(), s.bodies.end(), [&](const BodyDesc& b) { return b.name == rig.body; })) {
    std::vector<std::string> body_names;
    for (const BodyDesc& b : s.bodies) body_names.push_back(b.name);
    const std::string near = nearest(rig.body, body_names);
    d.error(rig.path, "no body named '" + rig.body + "'" + (near.empty() ? "" : "; did you mean \"" + near + "\"?") +
                          " (a camera follows or frames a body or a dynamic object)");
  }
  o.finish();
  if (!d.empty()) return Error(ErrorKind::BadInput, d.lines());
  return s;
}

Result<SceneDesc> loadScene(const std::string& path, std::span<const BodyReaderRow> kinds) {
  clearResolvedAssets();
  auto text = readFile(path, kMaxSceneBytes);
  if (!text.ok()) return text.error();
  return parseScene(text.value(), path, kinds);
}

}  // namespace reel::io
