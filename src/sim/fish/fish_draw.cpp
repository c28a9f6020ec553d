// What a fish body gives the renderer. Skinned (Tu 1996, §3.4 binds a NURBS skin to the
// biomechanical model's faces; here a swept surface does the same): a smooth body whose
// cross-sections follow the rings of nodes, interpolated along a Catmull–Rom spine, textured with
// the species' pattern; a forked tail fin between the tail nodes, a dorsal fin, pectoral fins at
// the fins' pitch, and eyes. Or, `"draw": "wireframe"`, the model itself: nodes, units and the
// muscles tinted by their contraction, as in the first shot of "Go Fish!".
#include <cmath>

#include "core/math.h"
#include "core/patterns.h"
#include "sim/draw_material.h"
#include "sim/fish/fish_body.h"

namespace reel {
namespace {

constexpr int kAround = 16;   // vertices around a section
constexpr int kPerSpan = 4;   // sections between consecutive spine points

struct Section {
  Vec3 c, up, left;
  double w = 0, h = 0;  // half width, half height
};

// The spine: nose, the five rings, the tail's root (its nodes' midpoint pulled in).
std::array<Section, 7> spine(const Vec3* x, const FishFrame& f) {
  std::array<Section, 7> s;
  s[0].c = x[0], s[0].up = f.up, s[0].left = f.left;
  for (int r = 0; r < 5; ++r) {
    const Vec3 &ul = x[1 + 4 * r], &ur = x[2 + 4 * r], &lr = x[3 + 4 * r], &ll = x[4 + 4 * r];
    Section& q = s[static_cast<std::size_t>(r + 1)];
    q.c = 0.25 * (ul + ur + lr + ll);
    const Vec3 up = 0.5 * ((ul + ur) - (lr + ll)), left = 0.5 * ((ul + ll) - (ur + lr));
    q.h = 0.5 * up.norm(), q.w = 0.5 * left.norm();
    q.up = unitOr(up, f.up), q.left = unitOr(left - left.dot(q.up) * q.up, f.left);
  }
  // The nose: a small section just ahead of ring 1 so the head is rounded.
  s[0].w = 0.15 * s[1].w, s[0].h = 0.15 * s[1].h;
  Section& t = s[6];
  t.c = 0.5 * (x[21] + x[22]);
  t.c = s[5].c + 0.45 * (t.c - s[5].c);
  t.up = s[5].up, t.left = s[5].left, t.w = 0.5 * s[5].w, t.h = 0.5 * s[5].h;
  return s;
}

// The body: sections along the spine (ellipses), the nose closed by a tip vertex and the tail root
// by a cap. u runs nose to tail, v around from the back over the left flank.
void addBody(TriMesh& m, const std::array<Section, 7>& s) {
  const int spans = 6, rings = spans * kPerSpan + 1;
  const auto first = static_cast<std::uint32_t>(m.vertexCount());
  for (int k = 0; k < rings; ++k) {
    const int span = std::min(k / kPerSpan, spans - 1);
    const double t = static_cast<double>(k - span * kPerSpan) / kPerSpan;
    auto at = [&](int j) { return s[static_cast<std::size_t>(std::clamp(j, 0, 6))]; };
    const Section &a = at(span), &b = at(span + 1);
    const Vec3 c = catmullRom(at(span - 1).c, a.c, b.c, at(span + 2).c, t);
    const Vec3 up = unitOr((1 - t) * a.up + t * b.up, a.up), left = unitOr((1 - t) * a.left + t * b.left, a.left);
    // Radii: smooth between sections, the head rounded.
    const double e = 0.5 - 0.5 * std::cos(kPi * t);
    double w = (1 - e) * a.w + e * b.w, h = (1 - e) * a.h + e * b.h;
    if (span == 0) {
      const double r = std::sqrt(std::max(0.0, 1 - (1 - t) * (1 - t)));
      w = r * b.w, h = r * b.h;
    }
    const double u = static_cast<double>(k) / (rings - 1);
    for (int j = 0; j <= kAround; ++j) {
      const double th = 2 * kPi * j / kAround;
      const Vec3 p = c + std::cos(th) * h * up + std::sin(th) * w * left;
      const Vec3 n = unitOr(std::cos(th) / std::max(h, 1e-9) * up + std::sin(th) / std::max(w, 1e-9) * left, up);
      m.addVertex(p, n, u, static_cast<double>(j) / kAround);
    }
  }
  const std::uint32_t row = kAround + 1;
  for (int k = 0; k + 1 < rings; ++k)
    for (std::uint32_t j = 0; j < static_cast<std::uint32_t>(kAround); ++j) {
      const std::uint32_t a = first + static_cast<std::uint32_t>(k) * row + j, b = a + row;
      // Counter-clockwise from outside: v runs from the back over the left (+x) flank.
      m.indices.insert(m.indices.end(), {a, a + 1, b + 1, a, b + 1, b});
    }
}

// A fin as a double-sided fan of triangles (two faces with opposite normals).
void addFin(TriMesh& m, const std::vector<Vec3>& pts, const std::vector<std::array<int, 3>>& tris, double u) {
  for (int side = 0; side < 2; ++side) {
    const auto base = static_cast<std::uint32_t>(m.vertexCount());
    const Vec3 n0 = unitOr((pts[1] - pts[0]).cross(pts[2] - pts[0]), Vec3::UnitX());
    const Vec3 n = side == 0 ? n0 : Vec3(-n0);
    for (const Vec3& p : pts) m.addVertex(p, n, u, 0.02);  // the back's colour
    for (const auto& t : tris)
      if (side == 0) m.indices.insert(m.indices.end(), {base + t[0], base + t[1], base + t[2]});
      else m.indices.insert(m.indices.end(), {base + t[0], base + t[2], base + t[1]});
  }
}

}  // namespace

void FishBody::draw(DrawList& out) const {
  const auto& x = net_.state.x;
  if (desc_.wireframe) {
    // Nodes, the passive units, and the muscles in four shades from relaxed to fully contracted.
    DrawSpheres nodes;
    nodes.radius = static_cast<float>(0.012 * desc_.length);
    nodes.material.color = Vec3(0.9, 0.9, 0.85);
    appendPoints(nodes.centers, x);
    DrawTubes passive;
    passive.radius = static_cast<float>(0.004 * desc_.length);
    passive.material.color = Vec3(0.6, 0.75, 0.9);
    std::array<DrawTubes, 4> muscles;
    for (int b = 0; b < 4; ++b) {
      muscles[static_cast<std::size_t>(b)].radius = static_cast<float>(0.008 * desc_.length);
      const double c = b / 3.0;
      muscles[static_cast<std::size_t>(b)].material.color = Vec3(0.9, 0.85 - 0.7 * c, 0.3 - 0.25 * c);
    }
    const Springs& sp = net_.model.springs;
    auto put = [&](DrawTubes& t, std::size_t s) {
      for (int end = 0; end < 2; ++end) {
        const Vec3& p = x[static_cast<std::size_t>(end ? sp.b[s] : sp.a[s])];
        for (int k = 0; k < 3; ++k) t.ends.push_back(static_cast<float>(p[k]));
      }
    };
    std::array<int, kFishSprings> muscle_of;
    muscle_of.fill(-1);
    for (int k = 0; k < kFishMuscles; ++k) muscle_of[static_cast<std::size_t>(tmpl_.muscle[static_cast<std::size_t>(k)])] = k;
    for (std::size_t s = 0; s < sp.size(); ++s) {
      const std::size_t fish = s / kFishSprings;
      const int k = muscle_of[s % kFishSprings];
      if (k < 0) put(passive, s);
      else put(muscles[static_cast<std::size_t>(std::lround(3.0 * motor_[fish].contraction[static_cast<std::size_t>(k)]))], s);
    }
    out.spheres.push_back(std::move(nodes));
    out.tubes.push_back(std::move(passive));
    for (auto& t : muscles)
      if (!t.ends.empty()) out.tubes.push_back(std::move(t));
    return;
  }
  auto mesh = std::make_shared<TriMesh>();
  DrawSpheres eyes;
  eyes.radius = static_cast<float>(0.022 * desc_.length);
  eyes.material.color = Vec3(0.02, 0.02, 0.03);
  eyes.material.specular = 0.8, eyes.material.shininess = 90;
  for (std::size_t i = 0; i < count(); ++i) {
    const Vec3* p = &x[kFishNodes * i];
    const FishFrame f = frame(i);
    const auto s = spine(p, f);
    addBody(*mesh, s);
    // Tail fin: from the tail root to the two tips, notched at the middle.
    const Vec3 root_top = s[6].c + 0.8 * s[5].h * s[6].up, root_bottom = s[6].c - 0.8 * s[5].h * s[6].up;
    const Vec3 notch = 0.5 * (p[21] + p[22]) + 0.25 * (s[6].c - 0.5 * (p[21] + p[22]));
    addFin(*mesh, {root_top, p[21], notch, p[22], root_bottom}, {{0, 1, 2}, {0, 2, 4}, {4, 2, 3}}, 0.95);
    // Dorsal fin on the back between rings 2 and 4.
    const Vec3 d0 = s[2].c + s[2].h * s[2].up, d1 = s[4].c + s[4].h * s[4].up;
    const Vec3 tip = 0.4 * d0 + 0.6 * d1 + 1.1 * s[3].h * s[3].up - 0.15 * desc_.length * f.forward;
    addFin(*mesh, {d0, d1, tip}, {{0, 2, 1}}, 0.4);
    // Pectoral fins behind the head, pitched as the fins are.
    const double pitch = motor_[i].pitch;
    const Vec3 chord = desc_.length * 0.09 * (std::cos(pitch) * -f.forward + std::sin(pitch) * -f.up);
    for (int side : {1, -1}) {
      const Vec3 root = s[2].c + 0.9 * side * s[2].w * f.left - 0.3 * s[2].h * f.up;
      const Vec3 tip_out = root + 0.09 * desc_.length * side * f.left - 0.03 * desc_.length * f.up;
      addFin(*mesh, {root, root + chord, tip_out + 0.6 * chord}, {{0, 1, 2}}, 0.3);
    }
    // Eyes on the head's flanks.
    for (int side : {1, -1}) {
      const Vec3 e = 0.45 * s[0].c + 0.55 * s[1].c + 0.85 * side * s[1].w * s[1].left + 0.25 * s[1].h * s[1].up;
      for (int k = 0; k < 3; ++k) eyes.centers.push_back(static_cast<float>(e[k]));
    }
  }
  DrawMesh dm;
  dm.mesh = std::move(mesh);
  dm.per_frame = true;
  dm.material = drawMaterial(material_);
  dm.material.color = Vec3(1, 1, 1);  // the skin texture carries the colours
  dm.material.texture = skin_;
  // Its own skin replaces the scene's texture, which is then no bump map either (a bump_texture is).
  if (!material_.bump_image) dm.material.bump = nullptr;
  dm.material.double_sided = true;  // the fins are thin
  out.meshes.push_back(std::move(dm));
  out.spheres.push_back(std::move(eyes));
}

}  // namespace reel
