// The liquid kind's description: the discrete particle fluid (Terzopoulos, Platt & Fleischer 1989;
// Miller & Pearce 1989): species, their pair parameters, blocks, particles and nozzles.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "core/mesh.h"
#include "core/scene/body.h"
#include "core/types.h"

namespace reel {

// A liquid species: particles of mass m whose pair force on particle i from j is
//   g_ij = m_i m_j (x_i − x_j)(−α/(r + ε)^a + β/r^b)   for r < cutoff, 0 beyond,
// plus viscosity: f_i = γ · m_i m_j/(m_i + m_j) · (1 − r/cutoff) · (v_j − v_i).
struct SpeciesDesc {
  std::string name, path;
  double mass = 0.01;       // kg per particle
  double alpha = 0.0;       // attraction, N/(kg²·m^(a−2)) scale (see docs/fluids.md)
  double beta = 0.0;        // repulsion
  double a = 2.0, b = 4.0;  // exponents
  double epsilon = 0.0;     // m, softens the attraction near r = 0
  double cutoff = 0.05;     // m
  double viscosity = 0.0;   // γ, 1/s
  double agitation = 0.0;   // m/s: thermal speed per axis kept by random pair forces (DPD); 0 off
  Vec3 color{0.2, 0.4, 0.9};  // linear rgb
  // 0..1: how much of what lies behind shows through it (drawn as a surface); none: the liquid's
  // `transmission`. Clear water and opaque paint in one liquid.
  std::optional<double> transmission;
  double density = 1000.0;  // kg/m³: rest density (the dfsph model; its particles' volume is mass/density)
  // The dfsph model's spacing of these particles at rest, (mass/density)^(1/3), m.
  double spacing() const { return std::cbrt(mass / density); }
};

// Pair parameters of two species (an `interactions` entry); unset ones are the mean of the two.
struct InteractionDesc {
  int s = 0, t = 0;  // species indices
  std::string path;
  std::optional<double> alpha, beta, a, b, epsilon, cutoff, viscosity;
};

struct FluidBlockDesc {
  int species = 0;
  Vec3 min{0, 0, 0}, max{0.1, 0.1, 0.1};  // m
  double spacing = 0.02;  // m, a cubic lattice
  double jitter = 0.0;    // fraction of the spacing, from the seed
  Vec3 velocity{0, 0, 0};
  // Lattice points per axis: the points (i + ½)·spacing from `min` that fit below `max` (at least 1).
  // Counted in double, so that a block past any integer (1e10 m at 1e-9 m) is seen as such; the
  // loader refuses a count over its cap before along() converts it.
  double span(int axis) const { return std::max(1.0, std::floor((max[axis] - min[axis]) / spacing + 1e-9)); }
  long long along(int axis) const { return static_cast<long long>(std::min(span(axis), 1e15)); }
  double count() const { return span(0) * span(1) * span(2); }
};

struct FluidParticlesDesc {
  int species = 0;
  std::vector<Vec3> positions, velocities;
};

// A nozzle: particles leave a disc of `radius` around `position` along `direction` at `speed`,
// `rate` per second from `start` to `stop`, in layers of a hexagonal pattern `spacing` apart.
struct EmitterDesc {
  int species = 0;
  Vec3 position{0, 0, 0}, direction{0, -1, 0};  // direction: unit
  double speed = 1.0, radius = 0.05, rate = 100.0;  // m/s, m, particles/s
  double start = 0.0, stop = std::numeric_limits<double>::infinity();  // s
  double spacing = 0.02;  // m, between neighbours of a layer (the loader's default: 2 × radius)
  bool nozzle = true;     // drawn as a metal pipe whose mouth is the disc (false: a scene's own object is)
  long long perLayer() const { return static_cast<long long>(hexDisc(radius, spacing).size()); }
  // Layers emitted from start to stop (stop finite): one at `start`, then every perLayer()/rate s;
  // in double (the loader caps the count before layers() converts it).
  double layerCount() const { return std::floor((stop - start) * rate / static_cast<double>(perLayer()) + 1e-9) + 1; }
  long long layers() const { return static_cast<long long>(std::min(layerCount(), 1e15)); }
};

enum class FluidDraw { Spheres, Surface };

// How the particles push each other: the seed's pair force (Terzopoulos, Platt & Fleischer 1989),
// or divergence-free SPH (Bender & Koschier 2015), an incompressible liquid of a rest density.
enum class LiquidModel { Pairs, Dfsph };

struct FluidDesc final : BodyParams {
  LiquidModel model = LiquidModel::Pairs;
  std::vector<SpeciesDesc> species;
  std::vector<InteractionDesc> interactions;
  std::vector<FluidBlockDesc> blocks;
  std::vector<FluidParticlesDesc> particles;
  std::vector<EmitterDesc> emitters;
  double radius = 0.01;  // m: contact radius of a particle (and drawn sphere radius)
  long long max_particles = 0;  // resolved limit
  FluidDraw draw = FluidDraw::Spheres;
  double surface_cell = 0.0;    // m, marching grid cell; 0: the particle radius
  double surface_kernel = 0.0;  // m, smoothing radius of the density field; 0: 4 × radius
  double surface_iso = 0.5;     // density level of the surface, in particles per kernel volume
  bool surface_anisotropic = true;  // kernels stretched along each particle's neighbourhood (Yu & Turk 2013)
  int surface_smoothing = 2;        // passes of Taubin's smoothing over the extracted mesh
  double foam = 0.0;                // 0..1: churned liquid seeds spray, foam and bubbles (0: none)
  double foam_life = 2.0;           // s: their mean life
  double shutter = 0.5;             // of a frame: spray and surface drawn swept along their motion (0: sharp)
  // Particles the emitters release in all.
  long long emitted() const {
    long long n = 0;
    for (const EmitterDesc& e : emitters) n += e.layers() * e.perLayer();
    return n;
  }
  // The dfsph model's particle spacing: the cube root of the largest species' volume mass/density, m
  // (its kernel reaches twice that).
  double sphSpacing() const {
    double v = 0.0;
    for (const SpeciesDesc& s : species) v = std::max(v, s.spacing());
    return v;
  }
  // Colliders find its points this far: contact, and in dfsph the walls' share of the kernel.
  double contactRadius(double) const override { return model == LiquidModel::Dfsph ? std::max(radius, 2.0 * sphSpacing()) : radius; }
  double adhesionRange() const override {
    double r = 0.0;
    for (const SpeciesDesc& s : species) r = std::max(r, s.cutoff);
    return r;
  }
  std::vector<std::string> speciesNames() const override {
    std::vector<std::string> names;
    for (const SpeciesDesc& s : species) names.push_back(s.name);
    return names;
  }
};

}  // namespace reel
