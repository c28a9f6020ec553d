// The brows' hairs (FaceBody::addBrowHairs): over the brows painted into the skin's texture,
// hairs one by one, each rooted at a point of the skin drawn and lying along it, so the brows
// move with the frontalis and the corrugator and their edges break up into hairs (painted alone,
// viewers saw blurry stamped decals).
#include <algorithm>
#include <cmath>

#include "core/math.h"
#include "core/random.h"
#include "sim/face/face_body.h"
#include "sim/face/head_shape.h"

namespace reel {

// Where the brows' hairs root (points of the skin drawn, reel's head only) and how each lies, in
// the head's rest frame: upright and slanting out at the brow's head, then along the brow toward
// its tail, rising to its arch and falling after; 4-7 mm long (shorter at the head), 0.11 mm
// wide, a little lifted at their tips. Each point is found on the brows as the texture paints
// them: at the head's shape without its features, along the same ray (the skin stands off it by
// the brow ridge, up to 5.5 mm). Their lots are fixed, as the lashes' are.
const std::vector<FaceBody::BrowHair>& FaceBody::browHairs() const {
  std::call_once(brows_once_, [&] {
    const SkinDetail& d = detail();
    const double s = surface_.scale;
    for (std::size_t k = 0; k < d.points.size(); ++k) {
      const Vec3 p = detail_rest_[k] / s;
      if (p.z() < 0.03 || p.y() < 0.0 || p.y() > 0.045) continue;
      const Vec3 ray = p.normalized(), base = head::baseRadius(ray, surface_.look) * ray;
      const head::Brow b = head::browAt(std::abs(base.x()), base.y());
      if (b.density < 0.1) continue;
      const double out = p.x() >= 0 ? 1.0 : -1.0;
      for (int q = 0; q < 3; ++q) {
        const auto rnd = [&](int stream) { return uniformAt(11, static_cast<std::uint64_t>(stream), 3 * k + static_cast<std::uint64_t>(q)); };
        if (rnd(0) > b.density) continue;  // sparser toward the brow's edges
        BrowHair h;
        h.vertex = static_cast<std::uint32_t>(k);
        h.offset = s * Vec3(0.0014 * (rnd(1) - 0.5), 0.0014 * (rnd(2) - 0.5), 0.0);
        const double t = b.along, turn = 0.5 * (rnd(3) - 0.5);
        const Vec3 along = t < head::kBrowHead ? Vec3(0.35 * out, 1.0, 0.0) : Vec3(out, 0.64 - 0.9 * t, 0.0);
        h.direction = (along.normalized() + turn * Vec3(0, 0, 1).cross(along.normalized())).normalized();
        h.length = s * (0.004 + 0.003 * rnd(4)) * (t < head::kBrowHead ? 0.8 : 1.0);
        h.lift = 0.1 + 0.15 * rnd(5);
        h.shade = static_cast<float>(0.7 + 0.6 * rnd(6));
        brows_.push_back(h);
      }
    }
  });
  return brows_;
}

void FaceBody::addBrowHairs(TriMesh& strands, const TriMesh& skin) const {
  if (!surface_.generated) return;
  const double s = surface_.scale, width = 0.00011 * s;
  const Vec3 tone(0.035, 0.024, 0.018);  // the painted brows' colour
  for (const BrowHair& h : browHairs()) {
    if (h.vertex >= skin.vertexCount()) continue;
    const Vec3 n = unitOr(skin.normal(h.vertex), R_ * Vec3::UnitZ());
    Vec3 dir = R_ * h.direction;
    dir = unitOr(dir - dir.dot(n) * n, R_ * Vec3::UnitY());
    const Vec3 side = unitOr(n.cross(dir), R_ * Vec3::UnitX());
    Vec3 offset = R_ * h.offset;
    offset -= offset.dot(n) * n;
    const Vec3 root = skin.position(h.vertex) + offset + 0.00005 * s * n;
    addStrand(strands, 2, width, side, n, 1.0, [&](double f) { return Vec3(root + h.length * (f * dir + h.lift * f * f * n)); },
              [&](double) { return Vec3(tone * h.shade); });
  }
}

}  // namespace reel
