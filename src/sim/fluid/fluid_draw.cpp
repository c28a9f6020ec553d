// What a liquid gives the renderer: its particles as spheres coloured by species (colours blended
// over neighbours where species mix), or its surface as a mesh (fluid_surface.cpp); its spray, foam
// and bubbles (fluid_diffuse.cpp).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "core/math.h"
#include "core/mesh.h"
#include "core/profile.h"
#include "core/parallel.h"
#include "sim/draw_material.h"
#include "sim/fluid/fluid_body.h"
#include "sim/fluid/fluid_diffuse.h"
#include "sim/fluid/fluid_surface.h"

namespace reel {

namespace {

// Each particle's look: its species' value (colour, clarity) blended with its neighbours' (weights
// (1 − r/c)² inside the pair cutoff), so where species mix their colours mix, and a pure region
// keeps its own.
template <class T>
std::vector<T> blended(const Fluid& fl, const std::vector<T>& of_species) {
  const std::size_t n = fl.x.size();
  std::vector<T> c(n);
  const auto S = static_cast<std::size_t>(fl.species_count);
  const bool listed = fl.nbr_start.size() == n + 1;
  parallelFor(static_cast<std::ptrdiff_t>(n), [&](std::ptrdiff_t ii) {
    const auto i = static_cast<std::size_t>(ii);
    T sum = of_species[static_cast<std::size_t>(fl.s[i])];
    double wsum = 1.0;
    if (S > 1 && listed)
      for (std::uint32_t e = fl.nbr_start[i]; e < fl.nbr_start[i + 1]; ++e) {
        const auto j = static_cast<std::size_t>(fl.nbr[e]);
        const PairParams& p = fl.pairOf(i, j);
        const double r = (fl.x[i] - fl.x[j]).norm();
        if (r >= p.cutoff) continue;
        const double w = (1.0 - r / p.cutoff) * (1.0 - r / p.cutoff);
        sum += w * of_species[static_cast<std::size_t>(fl.s[j])];
        wsum += w;
      }
    c[i] = sum / wsum;
  });
  return c;
}

// The diffuse particles (fluid_diffuse.h): foam as white flecks of 0.15 to 0.3 of a particle's
// radius (each its own size by its serial place, shrinking over its last half second: foam thins
// out rather than vanishing at once), bubbles inside the liquid as smaller glassy white beads, spray
// as fine white droplets. None casts a shadow (specks whose shadows no one sees).
void addDiffuse(const Fluid& fl, DrawList& out) {
  const std::size_t m = fl.diffuse_x.size();
  if (m == 0 || fl.diffuse_kind.size() != m || fl.diffuse_life.size() != m || fl.diffuse_id.size() != m) return;
  std::array<DrawSpheres, 5> sets;  // foam in three sizes, bubbles, spray
  const std::array<double, 5> radius = {0.15, 0.22, 0.3, 0.12, 0.12};
  for (std::size_t k = 0; k < sets.size(); ++k) {
    sets[k].radius = static_cast<float>(radius[k] * fl.radius);
    sets[k].material.color = Vec3(0.95, 0.96, 0.97);
    sets[k].material.specular = k < 3 ? 0.3 : 0.6;
    sets[k].material.roughness = k < 3 ? 0.6 : 0.15;
    sets[k].material.casts_shadow = false;
  }
  for (std::size_t d = 0; d < m; ++d) {
    std::size_t set = 0;
    switch (static_cast<DiffuseKind>(fl.diffuse_kind[d])) {
      case DiffuseKind::Foam: {
        const double fade = std::clamp(fl.diffuse_life[d] / 0.5, 0.0, 1.0);  // 1 until its last half second
        set = static_cast<std::size_t>(std::min(2.0, std::floor(fade * static_cast<double>(1 + fl.diffuse_id[d] % 3))));
        break;
      }
      case DiffuseKind::Bubble: set = 3; break;
      case DiffuseKind::Spray: set = 4; break;
    }
    for (int a = 0; a < 3; ++a) sets[set].centers.push_back(static_cast<float>(fl.diffuse_x[d][a]));
  }
  for (DrawSpheres& s : sets)
    if (!s.centers.empty()) out.spheres.push_back(std::move(s));
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
  // Each species its own clarity (`transmission`); the surface's material has the clearest one's
  // and each vertex the share of it that passes there (clarity).
  const auto S = static_cast<std::size_t>(fl.species_count);
  std::vector<double> transmission = fl.species_transmission;  // (set by the body's builder; else the material's)
  if (transmission.size() != S) transmission.assign(S, material.transmission);
  const double clearest = *std::max_element(transmission.begin(), transmission.end());
  DrawMaterial dm = drawMaterial(material);
  dm.color = Vec3(1, 1, 1);  // the species colours carry the albedo
  dm.texture = nullptr;
  dm.bump = nullptr;  // (the surface has no UVs for a texture's or a bump map's)
  dm.transmission = clearest;
  // A clear liquid lets the light through to what lies under it (a tub's floor under water is lit,
  // not in the water's shadow; the caustics it would focus are not drawn): when every species is
  // at least half clear, the liquid casts no shadow.
  dm.casts_shadow = *std::min_element(transmission.begin(), transmission.end()) < 0.5;
  SurfacePaint paint;
  paint.colors = blended(fl, fl.species_color);
  paint.see_through = clearest > 0;
  if (paint.see_through && std::any_of(transmission.begin(), transmission.end(), [&](double t) { return t != clearest; })) {
    std::vector<double> share;
    for (double t : transmission) share.push_back(t / clearest);
    paint.clarity = blended(fl, share);
  }
  const std::vector<Vec3>& colors = paint.colors;
  // Per species, with its own clarity: balls, spray's droplets (0.6 of a particle's radius, smooth
  // and glossy) and their streaks.
  std::vector<DrawSpheres> balls(S), drops(S);
  std::vector<DrawTubes> streaks(S);
  for (std::size_t k = 0; k < S; ++k) {
    balls[k].radius = static_cast<float>(fl.radius);
    balls[k].material = dm;
    balls[k].material.transmission = transmission[k];
    drops[k] = balls[k];
    drops[k].radius = static_cast<float>(0.6 * fl.radius);
    drops[k].material.roughness = std::min(dm.roughnessValue(), 0.1);
    drops[k].material.casts_shadow = false;
    // Tubes carry no colour of their own: the species' colour; specks cast no shadow worth seeing.
    streaks[k].radius = drops[k].radius;
    streaks[k].material = drops[k].material;
    streaks[k].material.color = fl.species_color[k];
    streaks[k].material.casts_shadow = false;
  }
  auto species = [&](std::size_t i) { return static_cast<std::size_t>(fl.s[i]); };
  // Particle i's sphere at `at` (where it is, or where its streak began).
  auto add = [&](DrawSpheres& set, std::size_t i, const Vec3& at) {
    for (int a = 0; a < 3; ++a) {
      set.centers.push_back(static_cast<float>(at[a]));
      set.colors.push_back(static_cast<float>(colors[i][a]));
    }
  };
  // A droplet that moves more than its radius while the shutter is open (`shutter` of a frame; half
  // a frame is a film camera's 180° shutter) is drawn as the streak it leaves over that time: a
  // tube from where it was to where it is, capped by droplets at both ends.
  const double exposure = fl.shutter * out.frame_time;
  auto addSpray = [&](std::size_t i) {
    DrawSpheres& set = drops[species(i)];
    add(set, i, fl.x[i]);
    const Vec3 tail = fl.x[i] - exposure * fl.v[i];
    if (!((tail - fl.x[i]).norm() > set.radius) || !tail.allFinite()) return;
    DrawTubes& t = streaks[species(i)];
    for (int a = 0; a < 3; ++a) t.ends.push_back(static_cast<float>(tail[a]));
    for (int a = 0; a < 3; ++a) t.ends.push_back(static_cast<float>(fl.x[i][a]));
    add(set, i, tail);
  };
  auto finish = [&] {
    for (DrawSpheres& set : balls)
      if (!set.centers.empty()) out.spheres.push_back(std::move(set));
    addDiffuse(fl, out);
    for (DrawSpheres& set : drops)
      if (!set.centers.empty()) out.spheres.push_back(std::move(set));
    for (DrawTubes& t : streaks)
      if (!t.ends.empty()) out.tubes.push_back(std::move(t));
  };
  if (fl.draw == FluidDraw::Surface) {
    profile::Scope stage(profile::Stage::Surface);
    DrawMesh mesh;
    std::vector<std::size_t> spray;
    mesh.mesh = std::make_shared<const TriMesh>(liquidSurface(fl, paint, spray, exposure));
    mesh.per_frame = true;
    mesh.material = dm;
    if (mesh.mesh->triangleCount() > 0) out.meshes.push_back(std::move(mesh));
    std::sort(spray.begin(), spray.end());  // in particle order, the same draw run to run
    for (std::size_t i : spray) addSpray(i);
    finish();
    return;
  }
  // Particles drawn as balls; those with fewer than two neighbours within their pair cutoff are
  // spray, drawn as droplets or streaks.
  const bool listed = fl.nbr_start.size() == fl.x.size() + 1;
  for (std::size_t i = 0; i < fl.x.size(); ++i) {
    int near = 0;
    if (listed)
      for (std::uint32_t e = fl.nbr_start[i]; e < fl.nbr_start[i + 1] && near < 2; ++e) {
        const auto j = static_cast<std::size_t>(fl.nbr[e]);
        near += (fl.x[i] - fl.x[j]).norm() < fl.pairOf(i, j).cutoff ? 1 : 0;
      }
    if (!listed || near >= 2)
      add(balls[species(i)], i, fl.x[i]);
    else
      addSpray(i);
  }
  finish();
}

}  // namespace reel
