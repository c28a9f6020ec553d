// reel's head's hair drawn as strands over the cap its skin paints (head::hairCover): thin ribbons
// rooted in the hair, combed away from the crown's whorl, along the head with a little lift,
// so the hair's outline is soft and its surface catches light strand by strand (a painted
// cap alone reads as a helmet). Drawn, not simulated: they turn with the skull (face_draw.cpp).
// After the shell-and-strand idea of real-time fur (Lengyel, Praun, Finkelstein & Hoppe 2001),
// with the strands as geometry since the renderer has no cut-out textures.
#include <algorithm>
#include <cmath>

#include "core/math.h"
#include "core/mesh.h"
#include "core/random.h"
#include "sim/face/head.h"
#include "sim/face/head_shape.h"

namespace reel {

std::shared_ptr<const TriMesh> makeHair(const FaceSurface& s) {
  auto m = std::make_shared<TriMesh>();
  if (!s.generated) return m;
  const double k = s.scale;
  // The whorl, where the hair parts from: over the back of the crown (at 0.24 m).
  const Vec3 whorl(0.0, 0.1, -0.045);
  // Strands per square metre of scalp: one every 8 mm² (real hair is some 200 per cm², each
  // ribbon here a lock).
  constexpr double kDensity = 1.0 / 8e-6;
  constexpr int kSegments = 3;
  const std::vector<Vec3> normals = areaNormals(s.skin, s.tris);
  std::uint64_t serial = 0;
  for (std::size_t t = 0; t + 2 < s.tris.size(); t += 3) {
    const Vec3 a = s.skin[s.tris[t]], b = s.skin[s.tris[t + 1]], c = s.skin[s.tris[t + 2]];
    const double area = 0.5 * (b - a).cross(c - a).norm() / (k * k);
    const Vec3 mid = (a + b + c) / (3.0 * k);
    if (mid.y() < -0.09) continue;  // the neck's rings
    const Vec3 d = mid.normalized();
    if (head::hairCover(mid, d, 0.004) < 0.05) continue;
    // How many strands this triangle roots: its share of the density, the fraction drawn by lot.
    const double expected = area * kDensity;
    const int count = static_cast<int>(expected) + (uniformAt(7, 0, t) < expected - std::floor(expected) ? 1 : 0);
    for (int q = 0; q < count; ++q, ++serial) {
      auto rnd = [&](int stream) { return uniformAt(7, static_cast<std::uint64_t>(stream + 1), serial); };
      double u = rnd(0), v = rnd(1);
      if (u + v > 1) u = 1 - u, v = 1 - v;
      const Vec3 root = (a + u * (b - a) + v * (c - a)) / k;
      const Vec3 dir = root.normalized();
      // Fewer strands toward the hairline (they thin out over the skin, as painted).
      const double cover = head::hairCover(root, dir, 0.004);
      // (None where the hair has all but thinned out: at the sideburn's steep front edge a root
      // there, its ribbon a quarter of a millimetre to either side, lay on bare skin.)
      if (rnd(2) > cover || cover < 0.15) continue;
      const Vec3 n = unitOr(normals[s.tris[t]] + normals[s.tris[t + 1]] + normals[s.tris[t + 2]], dir);
      // Combed away from the whorl along the head, a little wayward; over the forehead, up and
      // back from the hairline (combed forward, the strands hung over the brow as a fringe).
      const double front = smoothstep(0.25, 0.6, dir.z()) * smoothstep(0.02, 0.05, root.y());
      Vec3 flow = (root - whorl).normalized() + front * (Vec3(0, 0.6, -1.0) - (root - whorl).normalized());
      flow -= flow.dot(n) * n;
      const Vec3 side = unitOr(n.cross(flow), Vec3::UnitX());
      flow = unitOr(flow, side.cross(n));
      flow = (flow + 0.35 * (rnd(3) - 0.5) * side).normalized();
      // 12 to 22 mm long, shorter at the hairline; rising from under the cap's surface at an
      // angle that flattens along the strand, and bending round the head as combed hair lies
      // (a 7.5 cm sphere's sag), its tip within about a millimetre of the cap's surface (a little
      // under it where the cap is flatter than that sphere). (Straight strands 7 to
      // 13 mm long with tips up to 2 mm off drew the outline as a fringe of spikes, "stubble"
      // round a helmet, viewers said; up to 4 mm off, as fuzz standing out all round.)
      double length = (0.012 + 0.01 * rnd(4)) * (0.35 + 0.65 * cover);
      const double lift = 0.1 + 0.08 * rnd(5);
      // No tip over bare skin: a strand combed past the hairline (forward over a temple, down past
      // a sideburn) is cut back until its tip lies in the hair (they hung in the air off the
      // sideburns, 10 mm out over the skin).
      const Vec3 start = root - 0.0015 * cover * n;  // (under the cap, never under the scalp)
      auto along = [&](double f) {
        const double sag = head::sq(length * f) / (2 * 0.075);
        return Vec3(start + length * f * flow + (length * (lift * f * (1.0 - 0.6 * f) + 0.05 * f) - sag) * n);
      };
      bool inside = false;
      for (int cut = 0; cut < 4 && !inside; ++cut) {
        const Vec3 tip = along(1.0);  // (where the strand drawn ends, lifted and bent round the head)
        inside = head::hairCover(tip, tip.normalized(), 0.004) > 0.97;
        if (!inside) length *= 0.6;
      }
      if (!inside) continue;  // (a root at the hair's edge combed straight out of it)
      const double width = 0.0005;
      const Vec3 hair = head::hairColor(root, dir, s.look) * (0.75 + 0.5 * rnd(6));
      addStrand(*m, kSegments + 2, width, side, n, k, along,
                [&](double f) { return Vec3(hair * (0.85 + 0.3 * f)); });  // lighter toward the tips
    }
  }
  return m;
}

}  // namespace reel
