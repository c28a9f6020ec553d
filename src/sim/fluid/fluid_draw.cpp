// What a liquid gives the renderer: its particles as spheres coloured by species (colours blended
// over neighbours where species mix), or its surface as a mesh (marching tetrahedra over the
// particles' density).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "core/isosurface.h"
#include "core/math.h"
#include "core/mesh.h"
#include "core/profile.h"
#include "core/union_find.h"
#include "core/parallel.h"
#include "sim/draw_material.h"
#include "sim/fluid/fluid_body.h"

namespace reel {

namespace {

// Each particle's colour: its species colour blended with its neighbours' (weights (1 − r/c)²
// inside the pair cutoff), so where species mix their colours mix, and a pure region keeps its own.
std::vector<Vec3> blendedColors(const Fluid& fl) {
  const std::size_t n = fl.x.size();
  std::vector<Vec3> c(n);
  const auto S = static_cast<std::size_t>(fl.species_count);
  const bool listed = fl.nbr_start.size() == n + 1;
  parallelFor(static_cast<std::ptrdiff_t>(n), [&](std::ptrdiff_t ii) {
    const auto i = static_cast<std::size_t>(ii);
    Vec3 sum = fl.species_color[static_cast<std::size_t>(fl.s[i])];
    double wsum = 1.0;
    if (S > 1 && listed)
      for (std::uint32_t e = fl.nbr_start[i]; e < fl.nbr_start[i + 1]; ++e) {
        const auto j = static_cast<std::size_t>(fl.nbr[e]);
        const PairParams& p = fl.pairs[static_cast<std::size_t>(fl.s[i]) * S + static_cast<std::size_t>(fl.s[j])];
        const double r = (fl.x[i] - fl.x[j]).norm();
        if (r >= p.cutoff) continue;
        const double w = (1.0 - r / p.cutoff) * (1.0 - r / p.cutoff);
        sum += w * fl.species_color[static_cast<std::size_t>(fl.s[j])];
        wsum += w;
      }
    c[i] = sum / wsum;
  });
  return c;
}

// The liquid's surface: the particles' density splatted on a grid with the kernel
// W(q) = (1 − q²)³, q = r/R, normalised by the density of a bulk at the species' rest spacing,
// cut at `surface_iso`. Colours are the splatted particle colours, darkened with the depth of
// liquid behind the surface (colour^(1 + 1.5·density one kernel radius inside): Beer–Lambert-like)
// when `tint` (not for a see-through liquid, which the renderer absorbs along its true depth).
// The surface of the particles `part` (whose kernels overlap no other particle's).
TriMesh liquidSurface(const Fluid& fl, const std::vector<Vec3>& colors, const std::vector<std::size_t>& part, bool tint) {
  if (part.empty()) return {};
  const double R = fl.surface_kernel;
  double cell = fl.surface_cell;
  Vec3 lo = fl.x[part[0]], hi = lo;
  for (std::size_t p : part) {
    lo = lo.cwiseMin(fl.x[p]);
    hi = hi.cwiseMax(fl.x[p]);
  }
  lo -= Vec3::Constant(R + 2 * cell);
  hi += Vec3::Constant(R + 2 * cell);
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
  // A settled liquid packs its nearest neighbours at about 0.8 of the lattice spacing.
  double spacing = 0.8 * bulkSpacing(fl.pairs[0]);
  if (!(spacing > 0)) spacing = 2.0 * fl.radius;
  const double bulk = 0.6383 * R * R * R / (spacing * spacing * spacing);  // ∫W dV / spacing³
  const int reach = static_cast<int>(std::ceil(R / cell));
  // Splatted in slabs of grid layers, one per task, each task scanning every particle and writing
  // its own layers only: every node still sums its particles in their order, so the field is the
  // same bits as one pass over the particles, on any number of threads.
  const int layers = f.dims[2], slab = std::max(1, (layers + 7) / 8);
  parallelBlocks(layers, slab, [&](std::ptrdiff_t k0, std::ptrdiff_t k1) {
    for (std::size_t p : part) {
      const Vec3& x = fl.x[p];
      const Vec3 g = (x - lo) / cell;
      const int ci = static_cast<int>(std::lround(g.x())), cj = static_cast<int>(std::lround(g.y())),
                ck = static_cast<int>(std::lround(g.z()));
      if (ck + reach < k0 || ck - reach >= k1) continue;
      for (int k = std::max(static_cast<int>(k0), ck - reach); k <= std::min(static_cast<int>(k1) - 1, ck + reach); ++k)
        for (int j = std::max(0, cj - reach); j <= std::min(f.dims[1] - 1, cj + reach); ++j)
          for (int i = std::max(0, ci - reach); i <= std::min(f.dims[0] - 1, ci + reach); ++i) {
            const double q2 = (lo + cell * Vec3(i, j, k) - x).squaredNorm() / (R * R);
            if (q2 >= 1.0) continue;
            const double w = (1 - q2) * (1 - q2) * (1 - q2) / bulk;
            const std::size_t id = f.index(i, j, k);
            f.value[id] += static_cast<float>(w);
            for (int a = 0; a < 3; ++a) f.color[3 * id + static_cast<std::size_t>(a)] += static_cast<float>(w * colors[p][a]);
          }
    }
  }, static_cast<std::ptrdiff_t>(part.size()) * 64);
  parallelFor(static_cast<std::ptrdiff_t>(f.value.size()), [&](std::ptrdiff_t i) {
    const auto id = static_cast<std::size_t>(i);
    if (f.value[id] > 0)
      for (int a = 0; a < 3; ++a) f.color[3 * id + static_cast<std::size_t>(a)] /= f.value[id];
  });
  TriMesh m = isosurface(f, fl.surface_iso);
  if (!tint) return m;  // a see-through liquid: the renderer absorbs along the real depth
  parallelFor(static_cast<std::ptrdiff_t>(m.vertexCount()), [&](std::ptrdiff_t vi) {
    const auto v = static_cast<std::size_t>(vi);
    const Vec3 p(m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]);
    const Vec3 nv(m.normals[3 * v], m.normals[3 * v + 1], m.normals[3 * v + 2]);
    const double depth = std::clamp(f.sample(p - R * nv), 0.0, 1.0);
    for (int a = 0; a < 3; ++a) {
      float& c = m.colors[3 * v + static_cast<std::size_t>(a)];
      c = static_cast<float>(std::pow(std::clamp(static_cast<double>(c), 1e-3, 1.0), 1.0 + 1.5 * depth));
    }
  });
  return m;
}

// Groups of fewer particles than this are spray: drawn as droplets, not as a surface.
constexpr std::size_t kSprayParticles = 12;

// The liquid's surface, piece by piece: particles are grouped by cells of 2·(kernel + cell) (a
// group is the particles of cells joined through their 26 neighbours), so no kernel reaches from
// one group into another, and each group's surface is extracted on a grid over its own box. A
// splash far from the pool costs a small grid of its own, not one spanning both. The particles of
// groups too small for a surface are added to `spray`.
TriMesh liquidSurface(const Fluid& fl, const std::vector<Vec3>& colors, std::vector<std::size_t>& spray, bool tint) {
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
    const TriMesh m = liquidSurface(fl, colors, g, tint);
    const auto base = static_cast<std::uint32_t>(out.vertexCount());
    out.positions.insert(out.positions.end(), m.positions.begin(), m.positions.end());
    out.normals.insert(out.normals.end(), m.normals.begin(), m.normals.end());
    out.colors.insert(out.colors.end(), m.colors.begin(), m.colors.end());
    for (std::uint32_t i : m.indices) out.indices.push_back(base + i);
  }
  return out;
}

}  // namespace

std::shared_ptr<const TriMesh> nozzleMesh(const Fluid& fluid) {
  TriMesh all;
  for (const FluidEmitter& e : fluid.emitters) {
    if (!e.desc.nozzle) continue;
    const double r = e.desc.radius + std::max(0.003, 0.25 * e.desc.radius), len = std::max(0.08, 4.0 * e.desc.radius);
    TriMesh pipe = makeCylinder(r, len, 24);
    // Along the direction the liquid leaves, its mouth at the emitter's position.
    pipe.transform(rotationFromUp(e.desc.direction), e.desc.position - 0.5 * len * e.desc.direction);
    const auto base = static_cast<std::uint32_t>(all.vertexCount());
    all.positions.insert(all.positions.end(), pipe.positions.begin(), pipe.positions.end());
    all.normals.insert(all.normals.end(), pipe.normals.begin(), pipe.normals.end());
    for (std::uint32_t i : pipe.indices) all.indices.push_back(base + i);
  }
  if (all.indices.empty()) return nullptr;
  return std::make_shared<const TriMesh>(std::move(all));
}

void FluidBody::draw(DrawList& out) const {
  const Fluid& fl = fluid_;
  const Material& material = material_;
  if (nozzles_) {
    DrawMesh pipes;
    pipes.mesh = nozzles_;
    pipes.material.color = Vec3(0.55, 0.56, 0.58);
    pipes.material.specular = 0.6;
    pipes.material.shininess = 60;
    out.meshes.push_back(std::move(pipes));
  }
  if (fl.x.empty()) return;
  DrawMaterial dm = drawMaterial(material);
  dm.color = Vec3(1, 1, 1);  // the species colours carry the albedo
  dm.texture = nullptr;
  const std::vector<Vec3> colors = blendedColors(fl);
  // Spray: droplets of 0.6 of a particle's radius, smooth and glossy.
  DrawSpheres drops;
  drops.radius = static_cast<float>(0.6 * fl.radius);
  drops.material = dm;
  drops.material.roughness = std::min(dm.roughnessValue(), 0.1);
  auto add = [&](DrawSpheres& set, std::size_t i) {
    for (int a = 0; a < 3; ++a) {
      set.centers.push_back(static_cast<float>(fl.x[i][a]));
      set.colors.push_back(static_cast<float>(colors[i][a]));
    }
  };
  if (fl.draw == FluidDraw::Surface) {
    profile::Scope stage(profile::Stage::Surface);
    DrawMesh mesh;
    std::vector<std::size_t> spray;
    mesh.mesh = std::make_shared<const TriMesh>(liquidSurface(fl, colors, spray, material.transmission <= 0));
    mesh.per_frame = true;
    mesh.material = dm;
    if (mesh.mesh->triangleCount() > 0) out.meshes.push_back(std::move(mesh));
    std::sort(spray.begin(), spray.end());  // in particle order, the same draw run to run
    for (std::size_t i : spray) add(drops, i);
    if (!drops.centers.empty()) out.spheres.push_back(std::move(drops));
    return;
  }
  // Particles drawn as balls; those with fewer than two neighbours within their pair cutoff are
  // spray, drawn as droplets.
  DrawSpheres sp;
  sp.radius = static_cast<float>(fl.radius);
  sp.material = dm;
  sp.centers.reserve(3 * fl.x.size());
  sp.colors.reserve(3 * fl.x.size());
  const bool listed = fl.nbr_start.size() == fl.x.size() + 1;
  const auto S = static_cast<std::size_t>(fl.species_count);
  for (std::size_t i = 0; i < fl.x.size(); ++i) {
    int near = 0;
    if (listed)
      for (std::uint32_t e = fl.nbr_start[i]; e < fl.nbr_start[i + 1] && near < 2; ++e) {
        const auto j = static_cast<std::size_t>(fl.nbr[e]);
        const PairParams& p = fl.pairs[static_cast<std::size_t>(fl.s[i]) * S + static_cast<std::size_t>(fl.s[j])];
        near += (fl.x[i] - fl.x[j]).norm() < p.cutoff ? 1 : 0;
      }
    add(!listed || near >= 2 ? sp : drops, i);
  }
  out.spheres.push_back(std::move(sp));
  if (!drops.centers.empty()) out.spheres.push_back(std::move(drops));
}

}  // namespace reel
