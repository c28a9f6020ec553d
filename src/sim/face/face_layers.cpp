// The face's layers mode: the classic figure of Terzopoulos & Waters (1990) and Lee, Terzopoulos
// & Waters (1995), the lattice's layers, the skull, and the muscles coloured from muscle red
// (relaxed) to a glowing orange (fully contracted).
#include <algorithm>
#include <array>
#include <cmath>

#include "core/math.h"
#include "sim/draw_material.h"
#include "sim/face/face_body.h"

namespace reel {
namespace {

void pushTube(DrawTubes& t, const Vec3& a, const Vec3& b) {
  for (const Vec3* p : {&a, &b})
    for (int k = 0; k < 3; ++k) t.ends.push_back(static_cast<float>((*p)[k]));
}

}  // namespace

void FaceBody::drawLayers(DrawList& out) const {
  const std::size_t n = surface_.size();
  const auto& x = net_.state.x;
  const double s = surface_.scale;
  // The figure of the lattice under the face, cut away: only the front of the head, and only its
  // left half (+x), so the muscles show on the skull over the right half; and only below the
  // hairline (over the scalp the hair's thickness stood the lattice off the skull as a bulge).
  auto shown = [&](std::size_t k) {
    const Vec3& p = surface_.skin[k];
    return p.z() > -0.01 * s && p.x() > -0.002 * s && p.y() < 0.062 * s;
  };
  DrawTubes skin, fascia, across;
  skin.radius = static_cast<float>(0.0004 * s);
  fascia.radius = skin.radius;
  across.radius = static_cast<float>(0.0003 * s);
  skin.material = plainMaterial(Vec3(0.9, 0.62, 0.45));
  // (The layers below the skin in muted tones: saturated red and blue, their edges at the cut
  // read as zig-zags and a checkered pattern.)
  fascia.material = plainMaterial(Vec3(0.6, 0.4, 0.33));
  across.material = plainMaterial(Vec3(0.42, 0.46, 0.52));
  const Springs& sp = net_.model.springs;
  for (std::size_t q = 0; q < sp.size(); ++q) {
    const auto a = static_cast<std::size_t>(sp.a[q]), b = static_cast<std::size_t>(sp.b[q]);
    if (!shown(a % n) || !shown(b % n)) continue;
    if (a < n && b < n) pushTube(skin, x[a], x[b]);
    else if (a >= n && b >= n && a < 2 * n && b < 2 * n) pushTube(fascia, x[a], x[b]);
    else if (b == a + n) pushTube(across, x[a], x[b]);
  }
  out.tubes.push_back(std::move(skin));
  out.tubes.push_back(std::move(fascia));
  out.tubes.push_back(std::move(across));
  // The skull: the bone surface, in bone's ivory, and the eyes in their sockets.
  auto bone = smoothMesh(x, 2 * n, n, surface_.tris);
  out.meshes.push_back({std::move(bone), true, plainMaterial(Vec3(0.55, 0.5, 0.42), 0.2)});
  if (surface_.generated) drawEyes(out);
  // Muscles: attachment to the centre of the nodes they pull (sphincters: their ellipse).
  for (std::size_t m = 0; m < muscles_.size(); ++m) {
    const FaceMuscle& mu = muscles_[m];
    const double a = std::clamp(act_[m], 0.0, 1.0);
    DrawTubes t;
    t.radius = static_cast<float>(0.0022 * s);
    // Muscle red relaxed, glowing orange as it contracts (yellow sticks read as a debug view).
    t.material = plainMaterial((1 - a) * Vec3(0.42, 0.07, 0.06) + a * Vec3(1.0, 0.5, 0.1), 0.3);
    if (!mu.desc.sphincter) {
      Vec3 mid = Vec3::Zero();
      for (std::size_t j = 0; j < mu.nodes.size(); ++j) mid += mu.weight[j] * x[n + static_cast<std::size_t>(mu.nodes[j])];
      const Vec3 att = attachmentWorld(m);
      pushTube(t, att, mid);
    } else {
      Vec3 u, v;
      sphincterAxes(mu.desc.normal.normalized(), u, v);
      // Its ring lies in the tissue: each point on the fascia node its nodes hold nearest to it
      // across the muscle's plane (the ring follows the face's curve and its contraction).
      const double shrink = 1.0 - 0.25 * a;
      auto at = [&](int j) {
        const double ang = 2 * kPi * j / 24;
        const Vec3 q = mu.desc.center + shrink * 0.6 * (mu.desc.radii[0] * std::cos(ang) * u + mu.desc.radii[1] * std::sin(ang) * v);
        const Vec3 axis = mu.desc.normal.normalized();
        std::size_t best = 0;
        double bd = 1e300;
        for (int k : mu.nodes) {
          const Vec3 r = surface_.skin[static_cast<std::size_t>(k)] - q;
          const double off = (r - r.dot(axis) * axis).squaredNorm();
          if (off < bd) bd = off, best = static_cast<std::size_t>(k);
        }
        return mu.nodes.empty() ? Vec3(desc_.position + R_ * q) : Vec3(x[n + best]);
      };
      // (Each point on its nearest node, the ring steps from node to node: smoothed, it runs round.)
      std::array<Vec3, 24> ring;
      for (int i = 0; i < 24; ++i) ring[static_cast<std::size_t>(i)] = at(i);
      for (int pass = 0; pass < 4; ++pass) {
        const std::array<Vec3, 24> was = ring;
        for (std::size_t i = 0; i < 24; ++i) ring[i] = 0.5 * was[i] + 0.25 * (was[(i + 23) % 24] + was[(i + 1) % 24]);
      }
      for (std::size_t i = 0; i < 24; ++i) pushTube(t, ring[i], ring[(i + 1) % 24]);
    }
    out.tubes.push_back(std::move(t));
  }
}

}  // namespace reel
