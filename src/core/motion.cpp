#include "core/motion.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

#include "core/math.h"

namespace reel {
namespace {

void lerp(std::vector<float>& out, const std::vector<float>& a, double s) {
  const auto t = static_cast<float>(s);
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = a[i] + t * (out[i] - a[i]);
}

// A per-frame mesh moved back to fraction s, when both frames drew it with the same topology.
std::shared_ptr<const TriMesh> meshAt(const DrawMesh& a, const DrawMesh& b, double s) {
  if (!b.per_frame || !a.mesh || !b.mesh || a.mesh == b.mesh) return b.mesh;
  const TriMesh& ma = *a.mesh;
  const TriMesh& mb = *b.mesh;
  if (ma.positions.size() != mb.positions.size() || ma.indices.size() != mb.indices.size() ||
      ma.normals.size() != mb.normals.size())
    return b.mesh;
  auto m = std::make_shared<TriMesh>(mb);
  lerp(m->positions, ma.positions, s);
  lerp(m->normals, ma.normals, s);
  for (std::size_t v = 0; v + 2 < m->normals.size(); v += 3) {
    const double len = std::hypot(m->normals[v], m->normals[v + 1], m->normals[v + 2]);
    if (len > 0)
      for (int c = 0; c < 3; ++c) m->normals[v + static_cast<std::size_t>(c)] /= static_cast<float>(len);
  }
  return m;
}

// For each item of `after`, the item of `before` drawn by the same body as its same ordinal
// (−1: none). Items of no body (the objects, always first) pair by index.
template <class T>
std::vector<int> pairing(const std::vector<T>& before, const std::vector<T>& after) {
  std::map<std::pair<int, int>, int> at;
  std::map<int, int> count;
  for (std::size_t i = 0; i < before.size(); ++i)
    if (before[i].source >= 0) at[{before[i].source, count[before[i].source]++}] = static_cast<int>(i);
  count.clear();
  std::vector<int> out(after.size(), -1);
  for (std::size_t i = 0; i < after.size(); ++i) {
    if (after[i].source < 0) {
      if (i < before.size() && before[i].source < 0) out[i] = static_cast<int>(i);
    } else if (auto it = at.find({after[i].source, count[after[i].source]++}); it != at.end()) {
      out[i] = it->second;
    }
  }
  return out;
}

}  // namespace

int picturesPerFrame(const DrawList& list) {
  const bool blur = list.shutter_deg > 0.0 && list.previous && list.shutter_samples > 1;
  const bool lens = list.camera.aperture > 0.0 && list.camera.lens_samples > 1;
  return std::max({1, blur ? list.shutter_samples : 1, lens ? list.camera.lens_samples : 1});
}

DrawList picture(const DrawList& list, int j, int n) {
  const bool blur = list.shutter_deg > 0.0 && list.previous;
  DrawList out = blur ? shutterSample(*list.previous, list, shutterTimes(list.shutter_deg, n)[static_cast<std::size_t>(j)]) : list;
  out.previous = nullptr;
  DrawCamera& c = out.camera;
  if (c.aperture > 0.0 && n > 1) {
    const Vec3 axis = (c.target - c.position).normalized();
    const double focus = c.focus_distance > 0.0 ? c.focus_distance : (c.target - c.position).norm();
    Vec3 right = axis.cross(c.up);
    if (right.norm() < 1e-9) right = axis.cross(std::abs(axis.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitZ());  // looking along up
    right.normalize();
    const Vec3 up = right.cross(axis);
    // Lens point l(j) = j·stride mod n, the stride coprime to n near n/φ: the shutter's early and
    // late times each see points all over the lens, not its centre or its rim only.
    int stride = std::max(1, static_cast<int>(std::lround(n / 1.618033988749895)));
    while (std::gcd(stride, n) != 1) ++stride;
    const int l = static_cast<int>((static_cast<long long>(j) * stride) % n);
    const double r = 0.5 * c.aperture * std::sqrt((l + 0.5) / n), a = l * 2.399963229728653;  // the golden angle
    const Vec3 in_focus = c.position + focus * axis;
    c.position += r * (std::cos(a) * right + std::sin(a) * up);
    c.target = in_focus;
  }
  return out;
}

std::vector<double> shutterTimes(double shutter_deg, int samples) {
  const double open = std::clamp(shutter_deg, 0.0, 360.0) / 360.0;
  std::vector<double> t;
  for (int j = 0; j < samples; ++j) t.push_back(1.0 - open + open * (j + 0.5) / samples);
  return t;
}

DrawList shutterSample(const DrawList& before, const DrawList& after, double s) {
  DrawList out = after;
  out.previous = nullptr;
  out.camera.position = before.camera.position + s * (after.camera.position - before.camera.position);
  out.camera.target = before.camera.target + s * (after.camera.target - before.camera.target);
  out.camera.fov_deg = before.camera.fov_deg + s * (after.camera.fov_deg - before.camera.fov_deg);
  const std::vector<int> pm = pairing(before.meshes, after.meshes), ps = pairing(before.spheres, after.spheres),
                         pt = pairing(before.tubes, after.tubes), pi = pairing(before.instances, after.instances);
  auto was = [](const std::vector<int>& p, std::size_t i) { return static_cast<std::size_t>(p[i]); };
  for (std::size_t i = 0; i < out.meshes.size(); ++i)
    if (pm[i] >= 0) out.meshes[i].mesh = meshAt(before.meshes[was(pm, i)], after.meshes[i], s);
  for (std::size_t i = 0; i < out.spheres.size(); ++i)
    if (ps[i] >= 0 && before.spheres[was(ps, i)].centers.size() == out.spheres[i].centers.size())
      lerp(out.spheres[i].centers, before.spheres[was(ps, i)].centers, s);
  for (std::size_t i = 0; i < out.tubes.size(); ++i)
    if (pt[i] >= 0 && before.tubes[was(pt, i)].ends.size() == out.tubes[i].ends.size())
      lerp(out.tubes[i].ends, before.tubes[was(pt, i)].ends, s);
  for (std::size_t i = 0; i < out.instances.size(); ++i) {
    if (pi[i] < 0) continue;
    DrawInstances& d = out.instances[i];
    const DrawInstances& a = before.instances[was(pi, i)];
    if (a.transforms.size() != d.transforms.size()) continue;
    lerp(d.transforms, a.transforms, s);
    if (a.phases.size() != d.phases.size()) continue;
    for (std::size_t k = 0; k < d.phases.size(); ++k) {
      const double turn = std::remainder(static_cast<double>(d.phases[k]) - a.phases[k], 2.0 * kPi);
      d.phases[k] = static_cast<float>(a.phases[k] + s * turn);
    }
  }
  return out;
}

}  // namespace reel
