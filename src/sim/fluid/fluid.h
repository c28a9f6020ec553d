// The discrete particle fluid of Terzopoulos, Platt & Fleischer 1989 ("Heating and melting
// deformable models (from goop to glop)") and Miller & Pearce 1989 ("Globular dynamics: a
// connected particle system for animating viscous fluids"): particles of several species that
// attract at a distance and repel up close through the pair force
//   g_ij = m_i m_j (x_i − x_j)(−α/(r + ε)^a + β/r^b),   r = |x_i − x_j| < cutoff  (0 beyond),
// applied exactly so (no smoothing of the cut), plus a viscosity that damps the relative
// velocity of neighbours. Neighbours come from a Verlet list (pairs closer than the cutoff plus
// a skin) rebuilt through the shared hashed grid (sim/grid.h) when the two largest displacements
// since the last build add up to the skin: never an O(N²) loop. Particles meet the scene's
// objects through the shared collision primitives (sim/collide.h) with per-species surfaces
// (adhesion, friction, restitution); rigid bodies and figures' links meet them in the World's
// contact layer (point–convex), by the same per-species surfaces.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/scene.h"
#include "core/scene/fluid.h"
#include "core/types.h"
#include "sim/collide.h"
#include "sim/body.h"
#include "sim/grid.h"
#include "sim/row_grid.h"
#include "sim/stability.h"

namespace reel {

// Where the pair repulsion stops growing, as a fraction of the rest distance (PairParams::cap_r):
// close enough that a jammed, viscous pool still holds a heavy ball up ("agitation melts the
// glass": 0.5 let it sink), far enough that particles stacked by a landing stream are not kicked
// faster than their fall (0.3 let drops out of the tank).
inline constexpr double kRepulsionCap = 0.35;

// Parameters of the force between two species (symmetric).
struct PairParams {
  double alpha = 0, beta = 0, a = 2, b = 4, epsilon = 0, cutoff = 0.05, viscosity = 0;
  double cutoff2 = 0.0025;
  int ia = 2, ib = 4;  // a and b when they are small whole numbers (fast powers), else −1
  // Set by buildFluid from the two species' masses, for the force loop: m_s·m_t, γ·m_s·m_t/(m_s + m_t),
  // 1/cutoff, and whether the force is the seed's a = 2, b = 4, ε = 0 (one division per pair).
  double mass_product = 1.0, visc_mu = 0.0, inv_cutoff = 20.0;
  double sigma = 0.0;  // random pair force amplitude √(2·γμ·kT), kT = mean of m·agitation², N·√s
  bool seed_form = false;
  // Closer than cap_r (kRepulsionCap of the rest distance) the repulsion stops growing: the force keeps its
  // magnitude at cap_r. Two particles pressed nearly onto each other (stacked by a contact, a
  // stream landing on a plane) would otherwise meet β/r^b without bound and fling each other off
  // at thousands of m/s. Normal liquid never comes this close. 0: no cap (no rest distance).
  double cap_r = 0.0, cap_r2 = 0.0;
};

PairParams makePair(double alpha, double beta, double a, double b, double epsilon, double cutoff, double viscosity);

// The pair force on particle i (mass mi at xi) from j (mj at xj), N: zero at or beyond the
// cutoff and for coincident particles (no direction).
Vec3 pairForce(const PairParams& p, double mi, double mj, const Vec3& xi, const Vec3& xj);

// The distance where the pair force vanishes (attraction balances repulsion), m; 0 when it has
// none below the cutoff.
double restDistance(const PairParams& p);

// The spacing of a cubic lattice of these particles in equilibrium (the virial Σ r·F(r) over the
// lattice neighbours inside the cutoff is zero: near ones push, far ones pull), m; 0 when there
// is none (no attraction). Blocks laid out at this spacing start at rest.
double bulkSpacing(const PairParams& p);

// A nozzle as the fluid holds it (its layers emitted so far are state: FluidState::layers).
struct FluidEmitter {
  EmitterDesc desc;
  std::vector<std::array<double, 2>> disc;  // the nozzle's pattern, m
  Vec3 u{1, 0, 0}, w{0, 0, 1};  // the disc's axes
  double layer_dt = 1.0;        // s between layers
  long long max_layers = 0;
};

// What the liquid is: species, pair table, surfaces, nozzles, limits, how it is drawn.
struct FluidModel {
  std::string name;
  int species_count = 1;
  std::vector<std::string> species_names;
  std::vector<double> species_mass;  // kg (species)
  std::vector<Vec3> species_color;   // linear rgb (species)
  std::vector<double> species_transmission;  // 0..1 (species): how clear it is drawn
  std::vector<PairParams> pairs;  // species × species
  double radius = 0.01;           // contact radius, m
  double cutoff_max = 0.05;       // m
  double skin = 0.01;             // Verlet-list margin, m (FluidState::list_skin: the one in use)
  double ref_spacing = 0.01;      // m: how close neighbours come in a settled liquid (step splitting)
  double packed_spacing = 0.02;   // m: a settled bulk's nearest neighbours, 0.8 of the bulk spacing (drawing)
  std::vector<Surface> surfaces;  // colliders × species
  std::vector<double> adhesion_range;  // per species: how far a sticky surface pulls (its own cutoff), m
  std::vector<Vec3> x_start;  // (scratch) where each particle was when the step's motion began: its path for the contact layer, m
  std::uint64_t seed = 0;
  long long max_particles = 0;
  bool agitated = false;  // some pair has random forces
  FluidDraw draw = FluidDraw::Spheres;
  double surface_cell = 0.01, surface_kernel = 0.04, surface_iso = 0.5;
  bool surface_anisotropic = true;
  int surface_smoothing = 2;
  double foam = 0.0;
  double foam_life = 2.0;  // s: a diffuse particle's mean life
  double shutter = 0.5;
  std::vector<FluidEmitter> emitters;
  // The dfsph model (fluid_dfsph.h): its kernel's support (twice the particles' spacing), each
  // species' rest volume mass/density, and the volume of a flat wall inside the kernel, tabled
  // over its distance (wall_volume[k]: at k/kWallTable of the support; wall_area: minus its slope).
  LiquidModel model = LiquidModel::Pairs;
  double kernel_support = 0.0;            // m
  std::vector<double> species_volume;     // m³ (species)
  std::vector<double> wall_volume, wall_area;  // 1, 1/m (kWallTable + 1 samples)
  double wall_offset = 0.0;               // m: walls are taken this much farther (fluid_dfsph.cpp)
};

// What changes: the particles (in slots that re-sorting permutes; `id` follows each particle),
// the nozzles' progress, and the neighbour list with the positions it was built at (the list
// is rebuilt only when particles have moved a skin since, so it is part of what a step depends on).
struct FluidState {
  std::vector<Vec3> x, v;        // positions, m; velocities, m/s (particles)
  std::vector<int> s;            // species of each particle (particles)
  std::vector<double> m;         // mass of each particle, kg (particles)
  std::vector<std::int32_t> id;  // each slot's particle: its number in order of creation (particles)
  std::vector<long long> layers; // layers each nozzle has emitted (emitters)
  std::vector<Vec3> x_built;     // positions at the last list build, m (particles then)
  std::vector<std::uint32_t> nbr_start;  // the neighbour list: particle i's entries (particles + 1)
  std::vector<std::int32_t> nbr;         // neighbour slots
  double list_skin = 0.0;  // the margin the list was built with, m (Fluid::skin, or less while it cannot last: refreshNeighbours)
  long long list_age = 0;  // neighbour checks since the list was built
  long long thermal_draws = 0;  // force evaluations with random pair forces (their random stream)
  // Statistics.
  long long rebuilds = 0;
  long long pair_tests = 0;   // list entries visited by the force loop (pair evaluations)
  long long split_steps = 0;  // extra parts of steps split at violent moments
  long long skipped = 0;      // emitter points skipped because liquid was there
  // Diffuse particles (fluid_diffuse.h: spray, foam and bubbles, a drawing layer).
  std::vector<Vec3> diffuse_x, diffuse_v;  // positions, m; velocities, m/s
  std::vector<double> diffuse_life;        // s left
  std::vector<std::uint8_t> diffuse_kind;  // DiffuseKind at their last update
  std::vector<long long> diffuse_id;       // each one's serial number (its look)
  double diffuse_time = 0.0;               // when they were last updated, s
  long long diffuse_ticks = 0;             // how many updates there were (the seeding draws' index)
  long long diffuse_made = 0;              // how many were ever seeded (their random stream)
};

// Arrays reused from step to step; their contents do not outlive a step (the grid: a list build).
struct FluidScratch {
  std::vector<Vec3> f;  // force per particle, N
  std::vector<std::vector<std::int32_t>> chunk_lists;  // neighbour-list scratch: each block of rows' lists
  std::vector<std::array<std::uint32_t, 2>> list_at;   // each particle's list: block, offset
  RowGrid rows;  // the list build's search (sim/row_grid.h)
  struct alignas(64) Packed {  // what the force loop reads of a neighbour, in one cache line
    double x[3];
    double m;
    double v[3];
    int s;
  };
  std::vector<Packed> packed;
  BoxGrid grid;  // the last list build's particles at x_built: listedGrid() builds it when first asked
  bool grid_current = false;
  // The dfsph model's pressure solve (fluid_dfsph.cpp), per particle: relative density, factor α,
  // pressure, the walls' volume gradient and flux, working velocity; the neighbours inside the
  // kernel's reach (the Verlet list without its skin: the solver's iterations read only these)
  // with V_j ∇W_ij for each.
  struct Sph {
    std::vector<double> density, factor, pressure, wall_flux;
    std::vector<Vec3> wall_grad, u;
    std::vector<std::uint32_t> start;  // particle i's entries: [start[i], start[i + 1])
    std::vector<std::int32_t> nbr;
    std::vector<Vec3> grad;
    long long iterations = 0;  // pressure iterations so far (statistics)
  } sph;
  // The state in order of creation (dumps and hashes), filled by fluidById.
  std::vector<Vec3> x_by_id, v_by_id;
  std::vector<int> s_by_id;
};

struct Fluid : FluidModel, FluidState, FluidScratch {
  std::size_t size() const { return x.size(); }
  // The pair parameters of particles i and j (their species' entry of the table).
  const PairParams& pairOf(std::size_t i, std::size_t j) const {
    return pairs[static_cast<std::size_t>(s[i]) * static_cast<std::size_t>(species_count) + static_cast<std::size_t>(s[j])];
  }
};

// Builds the particles (blocks, explicit particles), emitters, pair table and surfaces. Block
// points inside an object (closer than its thickness plus the particle radius) are left out, so
// a pool may be filled around what stands in it. `colliders` are the scene's objects.
Fluid buildFluid(const FluidDesc& d, const std::string& name, const std::vector<Collider>& colliders,
                 std::uint64_t seed);

// The stable step of symplectic Euler for this fluid (see docs/fluids.md): a cubic lattice at 0.65
// of the bulk spacing (2 × radius without one), Gershgorin's bound over its neighbours inside the
// cutoff, ω² = 2 Σ (|dF/dr| + |F|/r)/m, and the viscous rate β = 2 Σ γ·μ·(1 − r/c)/m;
// h²ω² + 2hβ < 4. `node` holds the index S·s + t of the pair that sets it.
StepBound fluidStableStep(const Fluid& fl);

// One step h from t0 to t1 = t0 + h: emission, pair and viscous forces with gravity, symplectic
// Euler, adhesion and contacts with the scene's objects (not the free bodies': the contact layer
// meets those). A step
// in which some particle would move more than 5% of the spacing through its acceleration (or 40%
// through its speed) is split into equal parts, each with fresh forces (up to 16).
void stepFluid(Fluid& fl, const std::vector<Collider>& colliders, const Vec3& gravity, double h,
               double t0, double t1);

// Rebuilds the neighbour list now (the step does it when needed).
void buildNeighbours(Fluid& fl);
// The grid of the last list build's particles (at x_built, cells of the cutoff plus the skin),
// built on the first call after a build (emitters and diffuse particles ask; most steps do not).
const BoxGrid& listedGrid(Fluid& fl);
// Marks that grid out of date, as after restoring a state.
void rebuildGrid(Fluid& fl);

// Reorders the particles' slots along a Morton curve of their grid cells (memory locality); the
// list must be rebuilt after. Particles keep their ids (`id`), so dumps keep following them.
void sortParticles(Fluid& fl);

// Particles taken from the liquid and given to it by another body (a cloth soaking liquid up,
// dripping it back). Removing renumbers the ids of those left in order of creation (so ids stay
// 0..n−1) and rebuilds the neighbour list; an added particle gets the next id, and the next step
// lists it. `gone`: one flag per slot.
void removeParticles(Fluid& fl, const std::vector<std::uint8_t>& gone);
void addParticle(Fluid& fl, const Vec3& x, const Vec3& v, int species);

// Fills x_by_id, v_by_id and s_by_id: the state in order of creation.
void fluidById(Fluid& fl);

// Kinetic energy, J, and momentum, kg·m/s.
double kineticEnergy(const Fluid& fl);
Vec3 momentum(const Fluid& fl);

}  // namespace reel
