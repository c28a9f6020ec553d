#include "sim/rigid/parts.h"

#include <algorithm>

#include "sim/rigid/rigid.h"

namespace reel {

Pose colliderPose(const Collider& c) { return {c.pose.rot, c.pose.pos - c.pose.rot * c.shape->pivot}; }

void buildParts(const std::vector<Collider>& colliders, ObjectParts& cache, bool with_free, std::size_t skip_first,
                std::size_t skip_end) {
  cache.parts.clear();
  cache.mesh_parts.assign(colliders.size(), {0, 0});
  auto add = [&](std::size_t k, ConvexShape s) {
    ObjectPart p;
    p.collider = k;
    p.shape = std::move(s);
    shapeBounds(p.shape, Pose{}, p.lo, p.hi);
    cache.parts.push_back(std::move(p));
  };
  auto box = [&](std::size_t k, const Vec3& centre, const Mat3& R, const Vec3& half) {
    ConvexShape s;
    s.kind = CoreKind::Polytope;
    s.poly = std::make_shared<ConvexPolytope>(transformedPolytope(boxPolytope(half), R, centre));
    add(k, std::move(s));
  };
  for (std::size_t k = 0; k < colliders.size(); ++k) {
    const Collider& c = colliders[k];
    if (c.shape->free_body && (!with_free || (k >= skip_first && k < skip_end))) continue;
    ConvexShape s;
    switch (c.shape->kind) {
      case ObjectKind::Plane: {
        ObjectPart p;
        p.collider = k;
        p.half_space = true;
        p.frame = c.shape->R;
        p.normal = c.shape->R.col(1);
        p.offset = p.normal.dot(c.shape->p0) + c.shape->thickness;
        p.half_w = c.shape->half.x();
        p.half_d = c.shape->half.z();
        p.lo = Vec3::Constant(-1e300);
        p.hi = Vec3::Constant(1e300);
        cache.parts.push_back(std::move(p));
        break;
      }
      case ObjectKind::Sphere:
        s.kind = CoreKind::Point;
        s.a = c.shape->p0;
        s.radius = c.shape->radius + c.shape->thickness;
        add(k, std::move(s));
        break;
      case ObjectKind::Capsule:
        s.kind = CoreKind::Segment;
        s.a = c.shape->p0;
        s.b = c.shape->p1;
        s.radius = c.shape->radius + c.shape->thickness;
        add(k, std::move(s));
        break;
      case ObjectKind::Box:
        box(k, c.shape->p0, c.shape->R, c.shape->half + Vec3::Constant(c.shape->thickness));
        break;
      case ObjectKind::Container: {
        for (const auto& [centre, size] : containerBoxes(2.0 * c.shape->half, c.shape->wall)) box(k, c.shape->p0 + c.shape->R * centre, c.shape->R, 0.5 * size);
        break;
      }
      case ObjectKind::Mesh: {
        const MeshShape& m = *c.shape->mesh;
        cache.mesh_parts[k] = {cache.parts.size(), m.triangles.size()};
        for (const auto& t : m.triangles) {
          ConvexShape ts;
          ts.kind = CoreKind::Polytope;
          ts.poly = std::make_shared<ConvexPolytope>(trianglePolytope(m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]));
          add(k, std::move(ts));
        }
        break;
      }
    }
  }
  cache.built = true;
}

// The parts of an object whose box meets [lo, hi] (world), in part order.
void partsNear(const ObjectParts& cache, const std::vector<Collider>& colliders, const Vec3& lo, const Vec3& hi,
               std::vector<std::uint32_t>& out) {
  out.clear();
  for (std::size_t p = 0; p < cache.parts.size();) {
    const ObjectPart& part = cache.parts[p];
    const Collider& c = colliders[part.collider];
    // The collider's bounding sphere against the box first: one point carried instead of eight.
    if (c.shape->bound_radius < 1e300) {
      const Vec3 centre = c.fromAuthored(c.shape->bound_center);
      const Vec3 nearest = centre.cwiseMax(lo).cwiseMin(hi);
      if ((nearest - centre).squaredNorm() > c.shape->bound_radius * c.shape->bound_radius) {
        const auto [first, count] = cache.mesh_parts[part.collider];
        p = count > 0 && p == first ? first + count : p + 1;
        continue;
      }
    }
    // The box carried into the object's authored frame.
    Vec3 alo = Vec3::Constant(1e300), ahi = Vec3::Constant(-1e300);
    for (int corner = 0; corner < 8; ++corner) {
      const Vec3 q((corner & 1) ? hi.x() : lo.x(), (corner & 2) ? hi.y() : lo.y(), (corner & 4) ? hi.z() : lo.z());
      const Vec3 a = c.toAuthored(q);
      alo = alo.cwiseMin(a);
      ahi = ahi.cwiseMax(a);
    }
    const auto [first, count] = cache.mesh_parts[part.collider];
    if (count > 0 && p == first) {
      // A mesh: its triangles through its grid, each once, in order.
      const BoxGrid& g = c.shape->mesh->grid;
      const double cell = g.cell();
      const std::size_t start = out.size();
      const auto c0 = g.cellOf(alo), c1 = g.cellOf(ahi);
      double cells = 1.0;
      for (int k = 0; k < 3; ++k) cells *= static_cast<double>(c1[static_cast<std::size_t>(k)] - c0[static_cast<std::size_t>(k)] + 1);
      if (g.entries() > 0 && cells <= 4096.0) {
        // Each cell the box meets, by its centre.
        for (std::int64_t k = c0[2]; k <= c1[2]; ++k)
          for (std::int64_t j = c0[1]; j <= c1[1]; ++j)
            for (std::int64_t i = c0[0]; i <= c1[0]; ++i)
              g.forEachAt(Vec3((static_cast<double>(i) + 0.5) * cell, (static_cast<double>(j) + 0.5) * cell, (static_cast<double>(k) + 0.5) * cell),
                          [&, first = first](std::int32_t t) { out.push_back(static_cast<std::uint32_t>(first + static_cast<std::size_t>(t))); });
      } else {
        for (std::size_t t = 0; t < count; ++t) out.push_back(static_cast<std::uint32_t>(first + t));
      }
      std::sort(out.begin() + static_cast<std::ptrdiff_t>(start), out.end());
      out.erase(std::unique(out.begin() + static_cast<std::ptrdiff_t>(start), out.end()), out.end());
      std::size_t keep = start;
      for (std::size_t i = start; i < out.size(); ++i)
        if (overlaps(alo, ahi, cache.parts[out[i]].lo, cache.parts[out[i]].hi)) out[keep++] = out[i];
      out.resize(keep);
      p = first + count;
      continue;
    }
    if (overlaps(alo, ahi, part.lo, part.hi)) out.push_back(static_cast<std::uint32_t>(p));
    ++p;
  }
}

// Contacts of body A with an object part.
bool collidePart(const ConvexShape& shape, const Pose& pose, const ObjectPart& part, const Collider& c, double margin,
                 Manifold& m) {
  if (!part.half_space) return collide(shape, pose, part.shape, colliderPose(c), margin, m);
  const Vec3 n = c.pose.rot * part.normal;
  const double offset = n.dot(c.fromAuthored(part.offset * part.normal));
  if (!collideHalfSpace(shape, pose, n, offset, margin, m)) return false;
  if (part.half_w <= 0 && part.half_d <= 0) return true;
  // A finite plane: only the points over it.
  int keep = 0;
  for (int i = 0; i < m.count; ++i) {
    const Vec3 a = c.toAuthored(m.points[static_cast<std::size_t>(i)].position) - c.shape->p0;
    if ((part.half_w <= 0 || std::abs(a.dot(part.frame.col(0))) <= part.half_w) &&
        (part.half_d <= 0 || std::abs(a.dot(part.frame.col(2))) <= part.half_d))
      m.points[static_cast<std::size_t>(keep++)] = m.points[static_cast<std::size_t>(i)];
  }
  m.count = keep;
  return keep > 0;
}

}  // namespace reel
