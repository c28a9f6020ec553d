#include "io/scene/reader.h"

#include <iterator>
#include <unistd.h>

#include <algorithm>
#include <memory>

#include "core/patterns.h"
#include "io/files.h"
#include "io/mesh_import.h"
#include "io/png.h"

namespace reel::io {

namespace {

// A PNG named by `key`, read into `path` and `image`; errors at the key's path.
void readTexture(Obj& o, const std::string& key, std::string& path, std::shared_ptr<const Image>& image) {
  auto tex = o.string(key);
  if (!tex) return;
  auto r = resolveAsset(o.diag().file(), *tex, {".png"}, kMaxTextureBytes);
  auto img = r.ok() ? readPng(r.value(), kMaxTexturePixels) : Result<Image>(r.error());
  if (img.ok()) {
    path = r.value();
    image = std::make_shared<const Image>(std::move(img.value()));
  } else if (r.ok()) {
    o.diag().error(childPath(o.path(), key), "\"" + *tex + "\": " + img.error().headline());
  } else
    o.diag().error(childPath(o.path(), key), r.error().headline());
}

}  // namespace

void readMaterial(Obj& o, Material& m) {
  m.color = o.vec3("color", m.color, kNonNeg);
  readTexture(o, "texture", m.texture, m.texture_image);
  if (o.has("pattern")) {
    const std::string pat = o.choice("pattern", "", {std::begin(kPatternNames), std::end(kPatternNames)});
    if (!m.texture.empty())
      o.diag().error(childPath(o.path(), "pattern"), "give texture or pattern, not both");
    else if (!pat.empty()) {
      m.texture = "pattern:" + pat;
      m.texture_image = std::make_shared<const Image>(makePattern(pat, 512));
    }
  }
  // Relief: at most 5 cm (a bump map stands in for detail finer than the mesh, not for shape).
  readTexture(o, "bump_texture", m.bump_texture, m.bump_image);
  m.bump = o.number("bump", m.bump, Range::closed(-0.05, 0.05));
  if (o.has("bump_texture") && !o.has("bump"))
    o.diag().error(childPath(o.path(), "bump"), "bump_texture needs bump, the relief's height in m");
  if (m.bump != 0 && !o.has("bump_texture") && !o.has("texture") && !o.has("pattern") && !m.texture_image)
    o.diag().error(childPath(o.path(), "bump"), "bump needs a map: give bump_texture, texture or pattern");
  m.specular = o.number("specular", m.specular, kUnit);
  m.shininess = o.number("shininess", m.shininess, kPos);
  if (o.has("roughness")) m.roughness = o.number("roughness", 0.5, kUnit);
  else if (o.has("shininess")) m.roughness.reset();  // a kind's default roughness yields to it
  m.metallic = o.number("metallic", m.metallic, kUnit);
  m.sheen = o.number("sheen", m.sheen, kUnit);
  m.transmission = o.number("transmission", m.transmission, kUnit);
  m.absorption_depth = o.number("absorption_depth", m.absorption_depth, kPos);
  if (o.has("roughness") && o.has("shininess"))
    o.diag().error(childPath(o.path(), "shininess"), "give roughness or shininess (the older key), not both");
  m.opacity = o.number("opacity", m.opacity, kUnit);
  if (o.has("back_color")) m.back_color = o.vec3("back_color", m.color, kNonNeg);
}

void readPins(Obj& o, const std::vector<long long>& dims, long long nodes, const NodeNames& names,
              std::vector<int>& out, const std::string& key, bool required) {
  const Json* j = o.raw(key);
  Diagnostics& d = o.diag();
  const std::string p = childPath(o.path(), key);
  if (!j) {
    if (required && o.ok()) d.error(p, "missing required key");
    return;
  }
  if (!j->is_array()) {
    d.error(p, "expected a list of nodes, got " + typeName(*j));
    return;
  }
  for (std::size_t k = 0; k < j->size(); ++k) {
    const Json& e = (*j)[k];
    const std::string ep = childPath(p, k);
    if (e.is_string()) {
      const std::string s = e.get<std::string>();
      auto it = std::find_if(names.begin(), names.end(), [&](auto& n) { return n.first == s; });
      if (it != names.end()) {
        for (long long n : it->second) out.push_back(static_cast<int>(n));
        continue;
      }
      std::vector<std::string> opts;
      for (auto& n : names) opts.push_back(n.first);
      const std::string near = nearest(s, opts);
      d.error(ep, "unknown node name \"" + s + "\"" + (near.empty() ? "" : "; did you mean \"" + near + "\"?"));
    } else if (e.is_array()) {
      if (e.size() != dims.size()) {
        d.error(ep, "expected " + std::to_string(dims.size()) + " grid indices, got " + typeName(e));
        continue;
      }
      long long idx = 0, stride = 1;
      bool good = true;
      for (std::size_t a = 0; a < dims.size(); ++a) {
        auto v = readInteger(e[a], childPath(ep, a), d, -dims[a], dims[a] - 1);
        if (!v) { good = false; continue; }
        idx += (*v < 0 ? *v + dims[a] : *v) * stride;
        stride *= dims[a];
      }
      if (good) out.push_back(static_cast<int>(idx));
    } else if (e.is_number()) {
      if (auto v = readInteger(e, ep, d, -nodes, nodes - 1))
        out.push_back(static_cast<int>(*v < 0 ? *v + nodes : *v));
      else if (e.is_number_integer())
        d.error(ep, "the body has " + std::to_string(nodes) + " nodes (indices 0.." +
                        std::to_string(nodes - 1) + ", or negative from the end)");
    } else {
      d.error(ep, "expected a node index, grid indices or a name, got " + typeName(e));
    }
  }
}

void checkNodeMass(Obj& o, double mass, long long nodes) {
  if (nodes > 0 && mass / static_cast<double>(nodes) < kMinNodeMass)
    o.diag().error(childPath(o.path(), "mass"), "gives each of the " + std::to_string(nodes) +
                                                    " nodes less than 1e-12 kg");
}

SpringParams readSpring(Obj& o, const std::string& stiff_key, const std::string& damp_key, const SpringParams* fallback) {
  SpringParams s;
  if (fallback) {
    s.stiffness = o.number(stiff_key, fallback->stiffness, kNonNeg);
    s.damping = o.number(damp_key, fallback->damping, kNonNeg);
  } else {
    s.stiffness = o.number(stiff_key, kNonNeg, true).value_or(0.0);
    s.damping = o.number(damp_key, 0.0, kNonNeg);
  }
  return s;
}

void readSheet(Obj& o, Vec3& position, Vec3& rotation_deg, std::array<double, 2>& size, std::array<int, 2>& resolution) {
  position = o.vec3("position", position);
  rotation_deg = o.vec3("rotation_deg", rotation_deg);
  if (auto s = o.numbers<2>("size", kPos)) size = *s;
  if (auto r = o.integers<2>("resolution", 2, 1 << 16)) resolution = {static_cast<int>((*r)[0]), static_cast<int>((*r)[1])};
  const long long n = static_cast<long long>(resolution[0]) * resolution[1];
  if (n > kMaxBodyNodes)
    o.diag().error(childPath(o.path(), "resolution"), std::to_string(n) + " nodes, more than the limit of " + std::to_string(kMaxBodyNodes));
}

NodeNames cornerNames(long long nx, long long ny) {
  return {{"corner_00", {0}}, {"corner_10", {nx - 1}}, {"corner_01", {(ny - 1) * nx}}, {"corner_11", {nx * ny - 1}}};
}

std::shared_ptr<const TriMesh> readMeshFile(Obj& o, const std::string& key, bool required, std::string* file) {
  auto f = o.string(key, required);
  if (!f) return nullptr;
  if (file) *file = *f;
  Diagnostics& d = o.diag();
  auto r = resolveAsset(d.file(), *f, {std::begin(kMeshExtensions), std::end(kMeshExtensions)}, kMaxMeshBytes);
  auto m = r.ok() ? importMesh(r.value(), assetRoots(d.file())) : Result<TriMesh>(r.error());
  if (m.ok()) return std::make_shared<const TriMesh>(std::move(m.value()));
  d.error(childPath(o.path(), key), r.ok() ? "\"" + *f + "\": " + m.error().headline() : m.error().headline());
  return nullptr;
}

std::optional<Vec3> readHeading(Obj& o, const std::string& key) {
  auto h = o.vec3(key);
  if (!h) return std::nullopt;
  if (!(h->norm() > 1e-12)) {
    o.diag().error(childPath(o.path(), key), "must not be the zero vector");
    return std::nullopt;
  }
  return h->normalized();
}

void readStart(Obj& o, StartRegion& start) {
  if (const Json* st = o.raw("start")) {
    Obj so(*st, childPath(o.path(), "start"), o.diag());
    start.sphere = !so.has("min") && !so.has("max");
    if (start.sphere) {
      start.center = so.vec3("center", start.center);
      start.radius = so.number("radius", start.radius, Range{0.0, 1e4, true, false});
    } else {
      start.min = so.vec3("min", Range::any(), true).value_or(start.min);
      start.max = so.vec3("max", Range::any(), true).value_or(start.max);
      if (!(start.min.array() < start.max.array()).all()) o.diag().error(childPath(so.path(), "max"), "must be above min on every axis");
    }
    so.finish();
  }
  start.heading = readHeading(o, "heading");
}

long long itemsInMemory(double fraction, long long item_bytes, long long lo, long long hi, long long fallback) {
  const long long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
  if (pages <= 0 || page <= 0) return fallback;
  const double n = fraction * static_cast<double>(pages) * static_cast<double>(page) / static_cast<double>(item_bytes);
  return std::clamp(static_cast<long long>(n), lo, hi);
}

}  // namespace reel::io
