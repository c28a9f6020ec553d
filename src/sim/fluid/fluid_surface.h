// The surface a liquid is drawn with, from its particles (fluid_surface.cpp).
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

#include "core/mesh.h"
#include "core/types.h"
#include "sim/fluid/fluid.h"

namespace reel {

// One particle's smoothing kernel: W(x) = (1 − q²)³ for q = |A·(x − centre)| < 1, A symmetric
// with det A = 1/R³ (every kernel holds the volume of the isotropic one of radius R); `half` the
// half-extents of the box around its ellipsoid. Swept along `travel` (m, from where it is back to
// where it was), q is the least over the sweep: q = min over s in [0, 1] of |A·(x − centre − s·travel)|.
struct SurfaceKernel {
  Vec3 centre{0, 0, 0};
  Mat3 A = Mat3::Identity();
  Vec3 half{0, 0, 0};
  Vec3 travel{0, 0, 0};
  // Sweeps the kernel along `t` (after A is set).
  void sweep(const Vec3& t) {
    travel = t;
    trail = A * t;
    trail2 = trail.squaredNorm();
  }
  // q² at x.
  double q2(const Vec3& x) const { return q2Local(local(x)); }
  // The same in two halves, for a splat that steps y = A·(x − centre) along a row of nodes.
  Vec3 local(const Vec3& x) const { return A * (x - centre); }
  double q2Local(const Vec3& y) const {
    const double s = trail2 > 0 ? std::clamp(y.dot(trail) / trail2, 0.0, 1.0) : 0.0;
    return (y - s * trail).squaredNorm();
  }
  bool swept() const { return trail2 > 0; }
  // The box around the swept kernel.
  Vec3 lo() const { return centre.cwiseMin(centre + travel) - half; }
  Vec3 hi() const { return centre.cwiseMax(centre + travel) + half; }

 private:
  Vec3 trail{0, 0, 0};  // A·travel, and its squared length: set once, read at every node
  double trail2 = 0.0;
};

// The kernels of the particles `part` of x (positions, m), of radius R. Anisotropic (after Yu &
// Turk 2013): each particle's neighbours within R give its centre (moved towards their weighted
// mean) and its ellipsoid (the axes of their spread); isotropic: a ball of radius R at the particle.
std::vector<SurfaceKernel> surfaceKernels(const std::vector<Vec3>& x, const std::vector<std::size_t>& part, double R,
                                          bool anisotropic);

// Each kernel swept back along its particle's velocity v over `exposure` s (what an open shutter
// sees of it): travel = −v·exposure, at most `longest` m long.
void sweepKernels(std::vector<SurfaceKernel>& kernels, const std::vector<Vec3>& v, const std::vector<std::size_t>& part,
                  double exposure, double longest);

// What the surface carries from each particle: its colour (linear rgb) and its clarity, the share
// of the liquid's transmission that passes where it is (0..1; empty: all of it everywhere).
// see_through: the liquid is drawn with transmission (the renderer absorbs along the true depth);
// else, and where clarity is below 1, colours darken with the depth of liquid behind them.
struct SurfacePaint {
  std::vector<Vec3> colors;
  std::vector<double> clarity;
  bool see_through = false;
};

// The liquid's surface (the particles' paint splatted with their kernels, swept over `exposure`
// s, marching tetrahedra, Taubin smoothing), piece by piece; the particles of pieces too small for
// a surface are added to `spray`. The mesh's per-vertex colours and (when paint.clarity is given)
// clarity are the splatted ones.
TriMesh liquidSurface(const Fluid& fl, const SurfacePaint& paint, std::vector<std::size_t>& spray, double exposure);

}  // namespace reel
