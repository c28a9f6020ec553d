// A liquid's surface from its particles: each particle's smoothing kernel (an ellipsoid stretched
// along its neighbourhood), their density splatted on a grid, the level set extracted by marching
// tetrahedra (core/isosurface) and smoothed.
#include "sim/fluid/fluid_surface.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include <Eigen/Eigenvalues>

#include "core/isosurface.h"
#include "core/parallel.h"
#include "sim/row_grid.h"
#include "core/union_find.h"
#include "sim/grid.h"

namespace reel {

namespace {

// Yu & Turk's constants: the centre moved λ of the way to the neighbours' weighted mean (a
// Laplacian smoothing that flattens a resting surface and rounds a stream), no axis shorter than
// 1/k_r of the longest, and fewer than N_ε neighbours leave a particle's kernel a ball. Their λ is
// 0.9 to 1 for kernels of about the particle spacing; ours reach 2.5 spacings, and λ = 0.9 sank a
// resting pool's surface by 6 mm of its 64 (a loss of volume) where 0.5 sinks it by 2 mm and leaves
// it flatter than isotropic kernels do (tests/test_liquid_surface.cpp). Their N_ε = 25
// counts neighbours within twice the kernel's support; within the support itself a flat
// surface's particle has about 15 (a settled bulk about 33) and a stream one particle thick 2: 4
// still takes the kernel of a stream two or three particles across along its length.
constexpr double kCentreSmoothing = 0.5;  // λ
constexpr double kAxisRatio = 4.0;        // k_r
constexpr int kMinNeighbours = 4;         // N_ε

}  // namespace

// Yu & Turk 2013, "Reconstructing surfaces of particle-based fluids using anisotropic kernels"
// (ACM TOG 32(1)), §4–5: with weights w_ij = 1 − (|x_j − x_i|/R)³ over the neighbours within R,
// the weighted mean x̄_i = Σ w_ij x_j / Σ w_ij and covariance C_i = Σ w_ij (x_j − x̄_i)(x_j − x̄_i)ᵀ / Σ w_ij;
// C_i = V diag(σ₁, σ₂, σ₃) Vᵀ (σ₁ largest) and the kernel's axes along V in proportion to
// σ₁, max(σ₂, σ₁/k_r), max(σ₃, σ₁/k_r). Where Yu & Turk scale the axes by a constant k_s, they
// are scaled here so that their product is R³: a kernel keeps the volume of the isotropic one, so
// a bulk (isotropic spread) keeps the density it had, a sheet one particle thick spreads its
// particles' mass along the sheet (and gets a surface), and a stream along its length.
std::vector<SurfaceKernel> surfaceKernels(const std::vector<Vec3>& x, const std::vector<std::size_t>& part, double R,
                                          bool anisotropic) {
  const std::size_t n = part.size();
  std::vector<SurfaceKernel> out(n);
  std::vector<Vec3> p(n);
  for (std::size_t i = 0; i < n; ++i) p[i] = x[part[i]];
  auto ball = [&](SurfaceKernel& k, const Vec3& c) {
    k.centre = c;
    k.A = Mat3::Identity() / R;
    k.half = Vec3::Constant(R);
  };
  if (!anisotropic) {
    for (std::size_t i = 0; i < n; ++i) ball(out[i], p[i]);
    return out;
  }
  // Each particle's neighbours within R from a row grid (sim/row_grid.h): 9 runs of sorted
  // entries, rows of them in parallel.
  RowGrid grid;
  grid.build(p, R);
  const double R2 = R * R;
  const double *gx = grid.x(), *gy = grid.y(), *gz = grid.z();
  const std::span<const std::int32_t> order = grid.order();
  // One particle's kernel from the runs around its sorted entry `self`.
  auto kernelOf = [&](std::uint32_t self, std::span<const RowGrid::Run> runs) {
    const auto i = static_cast<std::size_t>(order[self]);
    const Vec3 pi(gx[self], gy[self], gz[self]);  // p[i], from the sorted copies
    Vec3 mean = Vec3::Zero();
    double wsum = 0.0;
    int near = 0;
    // Calls f(k, p, w) for the sorted entries k within R (the particle itself included, weight 1).
    auto forEachNear = [&](auto&& f) {
      for (const RowGrid::Run& run : runs)
        for (std::uint32_t k = run[0]; k < run[1]; ++k) {
          const Vec3 pj(gx[k], gy[k], gz[k]);
          const double r2 = (pj - pi).squaredNorm();
          if (!(r2 < R2)) continue;
          const double q = std::sqrt(r2) / R;
          f(k, pj, 1.0 - q * q * q);
        }
    };
    forEachNear([&](std::uint32_t k, const Vec3& pj, double w) {
      if (w <= 0.0) return;
      mean += w * pj;
      wsum += w;
      near += k != self;
    });
    mean /= wsum;  // (the particle itself weighs 1)
    const Vec3 centre = (1.0 - kCentreSmoothing) * pi + kCentreSmoothing * mean;
    if (near < kMinNeighbours) {
      ball(out[i], centre);
      return;
    }
    Mat3 C = Mat3::Zero();
    forEachNear([&](std::uint32_t, const Vec3& pj, double w) {
      if (w <= 0.0) return;
      const Vec3 d = pj - mean;
      C += w * d * d.transpose();
    });
    C /= wsum;
    const Eigen::SelfAdjointEigenSolver<Mat3> eig(C);
    const Vec3 e = eig.eigenvalues();  // ascending
    if (eig.info() != Eigen::Success || !(e[2] > 0.0)) {
      ball(out[i], centre);
      return;
    }
    Vec3 s;
    for (int a = 0; a < 3; ++a) s[a] = std::max(e[a], e[2] / kAxisRatio);
    s /= std::cbrt(s[0] * s[1] * s[2]);
    const Mat3& V = eig.eigenvectors();
    SurfaceKernel& k = out[i];
    k.centre = centre;
    k.A = V * Vec3(1.0 / (R * s[0]), 1.0 / (R * s[1]), 1.0 / (R * s[2])).asDiagonal() * V.transpose();
    for (int a = 0; a < 3; ++a) k.half[a] = R * V.row(a).cwiseProduct(s.transpose()).norm();
  };
  parallelBlocks(static_cast<std::ptrdiff_t>(grid.rows()), 16, [&](std::ptrdiff_t r0, std::ptrdiff_t r1) {
    grid.visitRows(r0, r1, kernelOf);
  }, static_cast<std::ptrdiff_t>(n));
  return out;
}

// A film camera sees a fast stream of drops as one streak: each kernel swept over the path its
// particle took while the shutter was open, every point of the path as dense as the kernel's
// centre (the sweep's envelope: a solid streak rather than the shutter's semi-transparent blur),
// so a string of drops reads as the stream it is. A sweep is at most `longest` (m): a kernel's box
// grows with it, and one flung at tens of metres a second would cost a grid of its own.
void sweepKernels(std::vector<SurfaceKernel>& kernels, const std::vector<Vec3>& v, const std::vector<std::size_t>& part,
                  double exposure, double longest) {
  if (!(exposure > 0)) return;
  for (std::size_t i = 0; i < kernels.size(); ++i) {
    Vec3 travel = -exposure * v[part[i]];
    const double len = travel.norm();
    if (!std::isfinite(len)) continue;
    if (len > longest) travel *= longest / len;
    kernels[i].sweep(travel);
  }
}

namespace {

// The surface of the particles `part` (whose ball kernels overlap no other group's): their density
// splatted on a grid with their kernels W = (1 − q²)³, normalised by the density of a bulk at the
// species' rest spacing, cut at `surface_iso`. Colours (and clarity) are the splatted particles',
// colours darkened with the depth of liquid behind the surface (colour^(1 + 1.5·o·density one
// kernel radius inside): Beer–Lambert-like) by the vertex's opacity o: 1 for an opaque liquid,
// 1 − clarity for a see-through one (whose clear parts the renderer absorbs along the true depth).
TriMesh pieceSurface(const Fluid& fl, const SurfacePaint& paint, const std::vector<std::size_t>& part, double exposure) {
  const std::vector<Vec3>& colors = paint.colors;
  const bool clarity = paint.clarity.size() == colors.size();
  if (part.empty()) return {};
  const double R = fl.surface_kernel;
  double cell = fl.surface_cell;
  std::vector<SurfaceKernel> kernels = surfaceKernels(fl.x, part, R, fl.surface_anisotropic);
  sweepKernels(kernels, fl.v, part, exposure, 4.0 * R);  // (a pour at 5 m/s sweeps 8 cm of 16 in half a frame at 30 fps)
  Vec3 lo = kernels[0].lo(), hi = kernels[0].hi();
  for (const SurfaceKernel& k : kernels) {
    lo = lo.cwiseMin(k.lo());
    hi = hi.cwiseMax(k.hi());
  }
  lo -= Vec3::Constant(2 * cell);
  hi += Vec3::Constant(2 * cell);
  auto dimsFor = [&](double c) {
    return std::array<double, 3>{std::ceil((hi.x() - lo.x()) / c) + 1, std::ceil((hi.y() - lo.y()) / c) + 1,
                                 std::ceil((hi.z() - lo.z()) / c) + 1};
  };
  // At most 16 million nodes: a coarser grid when the liquid spreads wide.
  while ([&] { auto d = dimsFor(cell); return d[0] * d[1] * d[2] > 1.6e7; }()) cell *= 1.25;
  cell = std::max(cell, 1e-6);
  const auto dd = dimsFor(cell);
  GridField f;
  f.dims = {static_cast<int>(dd[0]), static_cast<int>(dd[1]), static_cast<int>(dd[2])};
  f.origin = lo;
  f.cell = cell;
  f.value.assign(static_cast<std::size_t>(dd[0] * dd[1] * dd[2]), 0.0f);
  f.color.assign(3 * f.value.size(), 0.0f);
  // Clarity's weighted sum (`clear`), when the particles differ in it (a vertex's clarity is its trilinear
  // sample over f's: their weighted mean there).
  GridField clear;
  clear.dims = f.dims;
  clear.origin = f.origin;
  clear.cell = f.cell;
  if (clarity) clear.value.assign(f.value.size(), 0.0f);
  const double spacing = fl.packed_spacing;
  const double bulk = 0.6383 * R * R * R / (spacing * spacing * spacing);  // ∫W dV / spacing³
  const double inv_bulk = 1.0 / bulk;
  // Splatted in slabs of grid layers, one per task, each task scanning every kernel and writing
  // its own layers only: every node still sums its particles in their order, so the field is the
  // same bits as one pass over the particles, on any number of threads.
  const int layers = f.dims[2], slab = std::max(1, (layers + 7) / 8);
  auto node = [&](double v, int a) { return static_cast<int>(std::floor((v - lo[a]) / cell)); };
  parallelBlocks(layers, slab, [&](std::ptrdiff_t k0, std::ptrdiff_t k1) {
    const bool with_clarity = clarity;  // (a local: not reloaded at every node)
    for (std::size_t q = 0; q < part.size(); ++q) {
      const SurfaceKernel& K = kernels[q];
      const Vec3 blo = K.lo(), bhi = K.hi();
      const int klo = std::max(static_cast<int>(k0), node(blo.z(), 2) + 1), khi = std::min(static_cast<int>(k1) - 1, node(bhi.z(), 2));
      if (klo > khi) continue;
      const int jlo = std::max(0, node(blo.y(), 1) + 1), jhi = std::min(f.dims[1] - 1, node(bhi.y(), 1));
      const int ilo = std::max(0, node(blo.x(), 0) + 1), ihi = std::min(f.dims[0] - 1, node(bhi.x(), 0));
      const Vec3& c = colors[part[q]];
      // Along a row of nodes y = A·(x − centre) moves by a constant step, and q² of an unswept
      // kernel is a quadratic in the node's index: a row that misses the ellipsoid is skipped
      // whole, and the others visit only the nodes around its chord (one more each side for the
      // rounding; each node is still tested).
      const Vec3 step = K.A.col(0) * cell;
      const double step2 = step.squaredNorm();
      for (int k = klo; k <= khi; ++k)
        for (int j = jlo; j <= jhi; ++j) {
          const Vec3 y0 = K.local(lo + cell * Vec3(ilo, j, k));
          int i0 = ilo, i1 = ihi;
          if (!K.swept() && step2 > 0) {
            const double t = -y0.dot(step) / step2, closest = (y0 + t * step).squaredNorm();
            if (!(closest < 1.0)) continue;
            const double half = std::sqrt((1.0 - closest) / step2), span = static_cast<double>(ihi - ilo) + 1.0;
            i0 = std::max(ilo, ilo + static_cast<int>(std::floor(std::clamp(t - half, -1.0, span))) - 1);
            i1 = std::min(ihi, ilo + static_cast<int>(std::ceil(std::clamp(t + half, -1.0, span))) + 1);
          }
          for (int i = i0; i <= i1; ++i) {
            const double q2 = K.q2Local(y0 + static_cast<double>(i - ilo) * step);
            if (q2 >= 1.0) continue;
            const double w = (1 - q2) * (1 - q2) * (1 - q2) * inv_bulk;
            const std::size_t id = f.index(i, j, k);
            f.value[id] += static_cast<float>(w);
            for (int a = 0; a < 3; ++a) f.color[3 * id + static_cast<std::size_t>(a)] += static_cast<float>(w * c[a]);
            if (with_clarity) clear.value[id] += static_cast<float>(w * paint.clarity[part[q]]);
          }
        }
    }
  }, static_cast<std::ptrdiff_t>(part.size()) * 64);
  parallelFor(static_cast<std::ptrdiff_t>(f.value.size()), [&](std::ptrdiff_t i) {
    const auto id = static_cast<std::size_t>(i);
    if (!(f.value[id] > 0)) return;
    for (int a = 0; a < 3; ++a) f.color[3 * id + static_cast<std::size_t>(a)] /= f.value[id];
  });
  TriMesh m = isosurface(f, fl.surface_iso);
  smoothSurface(m, fl.surface_smoothing);
  if (clarity) m.clarity.resize(m.vertexCount());
  if (paint.see_through && !clarity) return m;  // all clear: the renderer absorbs along the real depth
  parallelFor(static_cast<std::ptrdiff_t>(m.vertexCount()), [&](std::ptrdiff_t vi) {
    const auto v = static_cast<std::size_t>(vi);
    const Vec3 p(m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]);
    const Vec3 nv(m.normals[3 * v], m.normals[3 * v + 1], m.normals[3 * v + 2]);
    double opacity = 1.0;
    if (clarity) {
      const double weight = f.sample(p);
      m.clarity[v] = weight > 0 ? static_cast<float>(std::clamp(clear.sample(p) / weight, 0.0, 1.0)) : 0.0f;
      if (paint.see_through) opacity = 1.0 - m.clarity[v];
    }
    const double depth = opacity * std::clamp(f.sample(p - R * nv), 0.0, 1.0);
    for (int a = 0; a < 3; ++a) {
      float& c = m.colors[3 * v + static_cast<std::size_t>(a)];
      c = static_cast<float>(std::pow(std::clamp(static_cast<double>(c), 1e-3, 1.0), 1.0 + 1.5 * depth));
    }
  });
  return m;
}

// Groups of fewer particles than this are spray: drawn as droplets, not as a surface.
constexpr std::size_t kSprayParticles = 12;

}  // namespace

// Piece by piece: particles are grouped by cells of 2·(kernel radius + 2 cells) (a group is the
// particles of cells joined through their 26 neighbours), so no ball kernel reaches from one group
// into another and a particle's neighbours within the kernel radius (which shape its anisotropic
// kernel) are in its group; each group's surface is extracted on a grid over its own box. A splash
// far from the pool costs a small grid of its own, not one spanning both. (An anisotropic kernel
// reaches up to 2.5 radii along a stream, and one swept over the shutter up to 4 radii further
// along its travel: groups cut by the cells' rule may then overlap a little where they face each
// other, two surfaces that meet instead of one (a broken stream with gaps of 3 to 6 radii); cells
// as large as that reach would join a droplet half a metre above a pool to the pool, where its
// lone ball has no surface.)
TriMesh liquidSurface(const Fluid& fl, const SurfacePaint& paint, std::vector<std::size_t>& spray, double exposure) {
  const double C = 2.0 * (fl.surface_kernel + 2.0 * fl.surface_cell);
  std::vector<std::array<std::int64_t, 3>> key;  // each finite particle's cell
  std::vector<std::size_t> who;
  for (std::size_t p = 0; p < fl.x.size(); ++p) {
    if (!fl.x[p].allFinite() || !(fl.x[p].cwiseAbs().maxCoeff() < 1e9)) continue;
    key.push_back({static_cast<std::int64_t>(std::floor(fl.x[p].x() / C)), static_cast<std::int64_t>(std::floor(fl.x[p].y() / C)),
                   static_cast<std::int64_t>(std::floor(fl.x[p].z() / C))});
    who.push_back(p);
  }
  // Distinct cells, sorted; groups of cells by union–find over their neighbours.
  std::vector<std::array<std::int64_t, 3>> cells = key;
  std::sort(cells.begin(), cells.end());
  cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
  std::vector<int> parent(cells.size());
  for (std::size_t c = 0; c < cells.size(); ++c) parent[c] = static_cast<int>(c);
  for (std::size_t c = 0; c < cells.size(); ++c)
    for (int dk = -1; dk <= 1; ++dk)
      for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di) {
          const std::array<std::int64_t, 3> q = {cells[c][0] + di, cells[c][1] + dj, cells[c][2] + dk};
          const auto it = std::lower_bound(cells.begin(), cells.end(), q);
          if (it != cells.end() && *it == q) unite(parent, static_cast<int>(c), static_cast<int>(it - cells.begin()));
        }
  std::vector<std::vector<std::size_t>> groups(cells.size());
  for (std::size_t k = 0; k < who.size(); ++k) {
    const auto c = static_cast<std::size_t>(std::lower_bound(cells.begin(), cells.end(), key[k]) - cells.begin());
    groups[static_cast<std::size_t>(findRoot(parent, static_cast<int>(c)))].push_back(who[k]);
  }
  TriMesh out;
  for (const auto& g : groups) {
    if (g.empty()) continue;
    if (g.size() < kSprayParticles) {
      spray.insert(spray.end(), g.begin(), g.end());
      continue;
    }
    const TriMesh m = pieceSurface(fl, paint, g, exposure);
    const auto base = static_cast<std::uint32_t>(out.vertexCount());
    out.positions.insert(out.positions.end(), m.positions.begin(), m.positions.end());
    out.normals.insert(out.normals.end(), m.normals.begin(), m.normals.end());
    out.colors.insert(out.colors.end(), m.colors.begin(), m.colors.end());
    out.clarity.insert(out.clarity.end(), m.clarity.begin(), m.clarity.end());
    for (std::uint32_t i : m.indices) out.indices.push_back(base + i);
  }
  return out;
}


}  // namespace reel
