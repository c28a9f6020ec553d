// Convex polytopes for the rigid-body narrow phase (sim/rigid/contact.h): boxes, prisms, flat
// triangles and the convex hull of a point set, each with polygon faces, edges and the faces on
// both sides of every edge (what the separating-axis test's edge pairs need).
#pragma once

#include <array>
#include <optional>
#include <span>
#include <vector>

#include "core/types.h"

namespace reel {

// A convex polytope in its local frame.
struct ConvexPolytope {
  std::vector<Vec3> vertices;  // m (vertices)
  // Plane n·x = offset (n unit, outward); loop: vertex indices counter-clockwise seen from outside.
  struct Face {
    Vec3 normal;
    double offset;
    std::vector<int> loop;
  };
  std::vector<Face> faces;                   // coplanar triangles merged into one polygon (faces)
  std::vector<std::array<int, 2>> edges;     // vertex indices, each edge once (edges)
  // The faces on either side of each edge (edges): [0] walks its loop from edges[e][0] to
  // edges[e][1], [1] the other way. Derived from the loops by finishPolytope.
  std::vector<std::array<int, 2>> edge_faces;
};

// Completes a polytope given its vertices and faces: lists the edges when `edges` is empty and
// finds every edge's two faces. The builders below call it; a hand-made polytope calls it once
// (collide works without it, but builds the adjacency on every call).
void finishPolytope(ConvexPolytope& poly);

// A box centred on the origin with half extents `half` (m).
ConvexPolytope boxPolytope(const Vec3& half);
// A cylinder approximated by a prism of `sides` (at least 3) side faces, its axis local y, centred:
// the vertices lie on the circle of `radius` at heights ±half_height (m).
ConvexPolytope prismPolytope(double radius, double half_height, int sides);
// A flat triangle: two faces (front: counter-clockwise a, b, c; back: the reverse), 3 edges.
ConvexPolytope trianglePolytope(const Vec3& a, const Vec3& b, const Vec3& c);

// Convex hull of points (quickhull, Barber, Dobkin & Huhdanpaa 1996), coplanar triangles merged
// into polygon faces (tolerance relative to the points' extent); vertices are the hull's corners
// only, in the order of the input. Returns std::nullopt when the points are (nearly)
// coplanar or collinear: no volume.
std::optional<ConvexPolytope> convexHull(std::span<const Vec3> points);

}  // namespace reel
