// Isosurfaces of a scalar field sampled on a regular grid (a liquid's surface from its particle
// density), by marching tetrahedra: every grid cube is cut into six tetrahedra around its main
// diagonal (Kuhn's triangulation, which neighbouring cubes share face by face), and each
// tetrahedron crossed by the level contributes one triangle or two. Unlike the 256-case marching
// cubes table it has no ambiguous cases, so the surface is closed wherever the field is.
// Reference: Doi & Koide 1991, "An efficient method of triangulating equi-valued surfaces by
// using tetrahedral cells"; Kuhn's triangulation as in Freudenthal 1942.
#pragma once

#include <array>
#include <vector>

#include "core/mesh.h"
#include "core/types.h"

namespace reel {

// A scalar field (and optional rgb per node) on nx × ny × nz nodes, node (i, j, k) at
// origin + cell·(i, j, k), stored at index (k·ny + j)·nx + i.
struct GridField {
  std::array<int, 3> dims{0, 0, 0};
  Vec3 origin{0, 0, 0};
  double cell = 1.0;  // m
  std::vector<float> value;
  std::vector<float> color;  // 3 per node, or empty
  std::size_t index(int i, int j, int k) const {
    return (static_cast<std::size_t>(k) * static_cast<std::size_t>(dims[1]) + static_cast<std::size_t>(j)) *
               static_cast<std::size_t>(dims[0]) + static_cast<std::size_t>(i);
  }
  // Trilinear value at p (0 outside the grid).
  double sample(const Vec3& p) const;
};

// The surface value = iso: triangles counter-clockwise seen from the side of lower values,
// vertices shared between triangles (one per crossed grid edge), normals from the field's
// gradient (pointing towards lower values), colours interpolated when the field has them.
TriMesh isosurface(const GridField& f, double iso);

// `passes` of Taubin's smoothing (Taubin 1995, "A signal processing approach to fair surface
// design"): each pass moves every vertex λ = 0.5 of the way to the mean of its edge neighbours, then
// μ = −0.53 of the way (back out), which damps the grid's stair steps and a kernel's bumps without
// shrinking the surface as plain Laplacian smoothing does. Normals are left as they are (an
// isosurface's come from the field's gradient, smoother than its facets'). Vertices are moved all
// at once each half-pass: the same bits on any number of threads.
void smoothSurface(TriMesh& m, int passes);

}  // namespace reel
