// What a liquid gives the renderer: its particles as spheres coloured by species (colours blended
// over neighbours where species mix), or its surface as a mesh (fluid_surface.cpp).
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
#include "sim/fluid/fluid_surface.h"

namespace reel {

namespace {

// The force parameters between particles i and j (their species' pair).
const PairParams& pairOf(const Fluid& fl, std::size_t i, std::size_t j) {
  return fl.pairs[static_cast<std::size_t>(fl.s[i]) * static_cast<std::size_t>(fl.species_count) + static_cast<std::size_t>(fl.s[j])];
}

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
        const PairParams& p = pairOf(fl, i, j);
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

// Foam where the liquid is churned, a drawing only (the dynamics do not change), after Ihmsen,
// Akinci, Akinci & Teschner 2012, "Unified spray, foam and bubbles for particle-based fluids"
// (The Visual Computer 28(6)), §4: a particle's trapped-air potential
//   I_ta = Σ_j |v_ij| (1 − v̂_ij·x̂_ij) W(x_ij),   W(r) = 1 − r/cutoff,
// large where neighbours rush past or into it (air folded in), not where they move along the
// line between them, and its speed |v_i| are each clamped into 0..1 by
// Φ(I) = (min(I, τ_max) − min(I, τ_min))/(τ_max − τ_min) and multiplied. Ihmsen et al. seed
// diffuse particles at that rate and carry them on; here the amount is drawn at the particle
// itself each frame, as a white bubble whose size grows with it in three steps (a set of spheres
// each, as one set has one radius), so a splash turns white where it churns and clears as it
// settles. The thresholds in reel's units: I_ta 1..5 m/s, speed 0.2..1.5 m/s (a splash's
// churn stays white for a few tenths of a second as it slows).
void addFoam(const Fluid& fl, DrawList& out) {
  const std::size_t n = fl.x.size();
  if (!(fl.foam > 0) || fl.nbr_start.size() != n + 1) return;
  auto phi = [](double I, double lo, double hi) { return (std::min(I, hi) - std::min(I, lo)) / (hi - lo); };
  std::vector<float> amount(n, 0.0f);
  parallelFor(static_cast<std::ptrdiff_t>(n), [&](std::ptrdiff_t ii) {
    const auto i = static_cast<std::size_t>(ii);
    const double speed = phi(fl.v[i].norm(), 0.2, 1.5);
    if (speed <= 0) return;
    double ta = 0;
    for (std::uint32_t e = fl.nbr_start[i]; e < fl.nbr_start[i + 1]; ++e) {
      const auto j = static_cast<std::size_t>(fl.nbr[e]);
      const double cutoff = pairOf(fl, i, j).cutoff;
      const Vec3 xij = fl.x[i] - fl.x[j], vij = fl.v[i] - fl.v[j];
      const double r = xij.norm(), u = vij.norm();
      if (!(r < cutoff) || !(r > 0) || !(u > 0)) continue;
      ta += u * (1.0 - vij.dot(xij) / (u * r)) * (1.0 - r / cutoff);
    }
    amount[i] = static_cast<float>(fl.foam * speed * phi(ta, 1.0, 5.0));
  });
  std::array<DrawSpheres, 3> foam;
  for (std::size_t k = 0; k < foam.size(); ++k) {
    foam[k].radius = static_cast<float>((0.35 + 0.15 * static_cast<double>(k)) * fl.radius);
    foam[k].material.color = Vec3(0.95, 0.96, 0.97);
    foam[k].material.specular = 0.3;
    foam[k].material.roughness = 0.6;
    foam[k].material.casts_shadow = false;  // flecks on the water: their shadows are specks no one sees
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (amount[i] < 0.1f) continue;
    DrawSpheres& set = foam[std::min<std::size_t>(2, static_cast<std::size_t>(3.0f * amount[i]))];
    for (int a = 0; a < 3; ++a) set.centers.push_back(static_cast<float>(fl.x[i][a]));
  }
  for (DrawSpheres& set : foam)
    if (!set.centers.empty()) out.spheres.push_back(std::move(set));
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
  dm.transmission = clearest;
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
    addFoam(fl, out);
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
        near += (fl.x[i] - fl.x[j]).norm() < pairOf(fl, i, j).cutoff ? 1 : 0;
      }
    if (!listed || near >= 2)
      add(balls[species(i)], i, fl.x[i]);
    else
      addSpray(i);
  }
  finish();
}

}  // namespace reel
