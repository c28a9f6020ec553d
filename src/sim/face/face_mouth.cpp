// The lips' thickness where they part (FaceBody::addLipRims): the strip from the skin drawn
// in to the mouth's lining along the parting's open edges.
#include <algorithm>
#include <cmath>

#include "core/math.h"
#include "sim/face/face_body.h"

namespace reel {

// Along each open edge of the parted skin (an edge of one triangle only), a wet red strip from
// just under the skin drawn in to the mouth's lining, turning from the skin's outward direction
// to face the opening and darkening inward (without it the
// opening's edge was a line, the lips rubber sheets and the mouth a flat black hole). Each edge
// in three, on Catmull–Rom curves through its vertices and their neighbours along the opening:
// straight from vertex to vertex, 4-7 mm apart, the rims were a polygon's facets round a
// puppet's mouth. Its vertices after the lining's, in the lining's mesh.
void FaceBody::addLipRims(TriMesh& inside, const std::vector<Vec3>& relaxed) const {
  const std::size_t n = surface_.size();
  if (!surface_.generated || inside.vertexCount() < n) return;
  const auto open = openEdgeNeighbours(surface_.tris, relaxed.size());
  // Dimmer as the lips close, as the teeth are (FaceBody::mouthLight), but from a narrower opening
  // (the rims lie at the lips, the teeth 8.5 mm behind them): in a slit little light reaches
  // them (lit in full, where the skin drawn between the vertices bared them they showed in the
  // slit of lips not quite closed as a dotted line of bright flecks).
  const Vec3 rim = mouthLight(0.25, 0.001, 0.005) * kLipRim;
  const double near = 0.015 * surface_.scale;
  auto lining = [&](std::uint32_t v) {
    return Vec3(inside.positions[3 * v], inside.positions[3 * v + 1], inside.positions[3 * v + 2]);
  };
  // Each vertex of the parting's open edges: its rim's outer end (just under the skin drawn: 0.3 mm
  // below where it dips deepest under the simulated skin), its inner end (the lining) and the
  // skin's outward direction there.
  struct End {
    bool lip = false;  // on the parting's open edges
    Vec3 outer, inner, normal;
  };
  std::vector<End> ends(n);
  for (std::uint32_t v = 0; v < n; ++v) {
    if (open[v].empty() || std::abs(surface_.skin[v].y() - surface_.mouth.y()) > near) continue;
    const Vec3 nv = (relaxed[v] - lining(v)).normalized();
    ends[v] = {true, relaxed[v] - (detail_.dip[v] + 0.0003 * surface_.scale) * nv, lining(v), nv};
  }
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;  // in the mesh's order
  for (std::uint32_t v = 0; v < n; ++v)
    for (std::uint32_t u : open[v])
      if (v < u && ends[v].lip && ends[u].lip) edges.emplace_back(v, u);
  if (edges.empty()) return;
  Vec3 centre = Vec3::Zero();
  for (const auto& [a, b] : edges) centre += ends[a].outer + ends[b].outer;
  centre /= 2.0 * static_cast<double>(edges.size());  // the opening's middle
  // Each outer end tucked 0.8 mm under the lip, away from the opening along the skin (at the
  // skin's edge, the mouth's dark inside showed between the skin drawn, curving between the
  // vertices, and the rim, as a dark outline round the lips).
  for (End& e : ends)
    if (e.lip) {
      const Vec3 away = e.outer - centre;
      e.outer += 0.0008 * surface_.scale * unitOr(away - away.dot(e.normal) * e.normal, Vec3::Zero());
    }
  // Along the opening a → b, the neighbour of a that is not b (a itself at a chain's end).
  auto beyond = [&](std::uint32_t a, std::uint32_t b) {
    for (std::uint32_t c : open[a])
      if (c != b && ends[c].lip) return c;
    return a;
  };
  for (const auto& [a, b] : edges) {
    const End &E0 = ends[beyond(a, b)], &E1 = ends[a], &E2 = ends[b], &E3 = ends[beyond(b, a)];
    auto outerAt = [&](double t) { return t <= 0 ? E1.outer : t >= 1 ? E2.outer : catmullRom(E0.outer, E1.outer, E2.outer, E3.outer, t); };
    auto innerAt = [&](double t) { return t <= 0 ? E1.inner : t >= 1 ? E2.inner : catmullRom(E0.inner, E1.inner, E2.inner, E3.inner, t); };
    // Its normals at t along the edge: facing the opening's middle, across the curve's tangent
    // and the skin's outward direction there (the vertices' blended), so they run on smoothly
    // from piece to piece and edge to edge (a normal per flat piece shaded the pieces in turn
    // light and dark: lips not quite closed showed a dotted line of bright flecks in the slit).
    // The skin's outward direction at t, the two vertices' blended.
    auto sideAt = [&](double t) { return Vec3((1 - t) * E1.normal + t * E2.normal); };
    auto facingAt = [&](double t) {
      const Vec3 tangent = catmullRom(E0.outer, E1.outer, E2.outer, E3.outer, std::min(t + 0.02, 1.0)) -
                           catmullRom(E0.outer, E1.outer, E2.outer, E3.outer, std::max(t - 0.02, 0.0));
      Vec3 facing = unitOr(tangent.cross(sideAt(t)), Vec3::UnitY());
      if (facing.dot(centre - outerAt(t)) < 0) facing = -facing;
      return facing;
    };
    constexpr int kPieces = 3;
    for (int q = 0; q < kPieces; ++q) {
      const double t0 = static_cast<double>(q) / kPieces, t1 = static_cast<double>(q + 1) / kPieces;
      // (The ends exactly the vertices' points, so that neighbouring edges' rims meet.)
      const Vec3 oa = outerAt(t0), ob = outerAt(t1), ia = innerAt(t0), ib = innerAt(t1);
      const Vec3 fa = facingAt(t0), fb = facingAt(t1);
      // One quad a piece, wound to face the opening.
      const bool flip = (ob - oa).cross(ib - oa).dot(fa + fb) < 0;
      // Rounded and wet: at its outer end it faces out with the skin and turns to face the
      // opening going in, and darkens toward the mouth's dark inside (flat and of one colour, the
      // strip read as a pink rubber seal round the opening).
      auto rolled = [&](const Vec3& facing, double t) { return unitOr(facing + 1.5 * sideAt(t).normalized(), facing); };
      const auto base = static_cast<std::uint32_t>(inside.vertexCount());
      for (int c = 0; c < 4; ++c) {
        const bool outer = c < 2;
        const Vec3 normal = c == 0 ? rolled(fa, t0) : c == 1 ? rolled(fb, t1) : c == 2 ? fb : fa;
        inside.addVertex(c == 0 ? oa : c == 1 ? ob : c == 2 ? ib : ia, normal);
        const Vec3 col = outer ? rim : Vec3(0.65 * rim);  // (at 0.3, seen from in front the strip read as a dark outline round the lips)
        for (int k = 0; k < 3; ++k) inside.colors.push_back(static_cast<float>(col[k]));
      }
      if (!flip) inside.indices.insert(inside.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
      else inside.indices.insert(inside.indices.end(), {base, base + 2, base + 1, base, base + 3, base + 2});
    }
  }
  inside.uvs.clear();
}

}  // namespace reel
