// Catmull & Clark (1978) subdivision of a quad mesh, "Recursively generated B-spline surfaces on
// arbitrary topological meshes", kept as stencils: every vertex of the refined mesh is a fixed
// weighted sum of the control points, worked out once for the mesh's connectivity, so a surface
// over moving points (a jelly lattice's skin) costs one sparse product a frame.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <utility>
#include <vector>

#include "core/mesh.h"
#include "core/types.h"

namespace reel {

class SubdivisionSurface {
 public:
  // `quads`: control point indices, counter-clockwise seen from outside. Rules of the paper on a
  // closed mesh: face point = mean of the face; edge point = mean of its ends and of its two face
  // points; vertex point = (F + 2R + (n − 3)P)/n with n its valence, F the mean of its faces'
  // points and R of its edges' midpoints. An edge with one face (an open mesh's border) takes its
  // midpoint and a border vertex stays (1/8, 3/4, 1/8 along the border).
  SubdivisionSurface(int control_points, std::span<const std::array<int, 4>> quads, int levels);

  // The refined points for these control points (control.size() == the count given).
  std::vector<Vec3> points(std::span<const Vec3> control) const;
  // The refined surface, smooth-shaded: its normals the area-weighted means of its triangles',
  // each point moved `offset` (m) along its normal (a skin over nodes of that radius).
  std::shared_ptr<TriMesh> mesh(std::span<const Vec3> control, double offset = 0.0) const;

  std::size_t pointCount() const { return offsets_.size() - 1; }
  const std::vector<std::uint32_t>& triangles() const { return triangles_; }

 private:
  int control_ = 0;
  // Point k = Σ weights_[j]·control[sources_[j]] over j in [offsets_[k], offsets_[k + 1]).
  std::vector<std::uint32_t> offsets_, sources_;
  std::vector<double> weights_;
  std::vector<std::uint32_t> triangles_;
};

}  // namespace reel
