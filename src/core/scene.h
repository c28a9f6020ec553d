// SceneDesc: the plain, validated description of a shot (DESIGN 2, 4). io::loadScene fills it,
// sim builds a World from it, the renderer reads camera, lights and materials from it.
// Everything here is data; JSON paths (`path`) are kept so later stages can name the key at fault.
#pragma once

#include <algorithm>
#include <array>
#include <limits>
#include <memory>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include "core/image.h"
#include "core/light.h"
#include "core/mesh.h"
#include "core/types.h"

namespace reel {

// Integrators by name (SPlisHSPlasH-style registration by name).
enum class IntegratorKind { SymplecticEuler, ExplicitEuler, Verlet, Rk4, ImplicitEuler };
inline constexpr std::array<std::string_view, 5> kIntegratorNames = {
    "symplectic_euler", "explicit_euler", "verlet", "rk4", "implicit_euler"};
inline std::string_view integratorName(IntegratorKind k) { return kIntegratorNames[static_cast<int>(k)]; }
inline std::optional<IntegratorKind> integratorFromName(std::string_view s) {
  for (std::size_t i = 0; i < kIntegratorNames.size(); ++i)
    if (kIntegratorNames[i] == s) return static_cast<IntegratorKind>(i);
  return std::nullopt;
}

// Appearance, read by the renderer; any object or body may carry it.
struct Material {
  Vec3 color{0.8, 0.8, 0.8};  // linear albedo
  std::string texture;        // resolved path of a PNG, empty for none
  std::shared_ptr<const Image> texture_image;  // its pixels, decoded when the scene loads
  double specular = 0.0;      // 0..1
  double shininess = 32.0;    // Phong exponent
  double opacity = 1.0;       // 0..1
};

// Contact response of an object's surface.
struct Surface {
  double friction = 0.3;     // Coulomb coefficient μ
  double restitution = 0.0;  // normal velocity kept after a bounce, 0..1
  double adhesion = 0.0;     // liquids: pull towards the surface within reach, m/s² (acceleration)
};

enum class ObjectKind { Plane, Sphere, Box, Capsule, Mesh, Container };

// A keyframe of an object's motion: where its reference point is (sphere and box centre, plane
// point, capsule midpoint, mesh position) and how it is turned from its authored orientation.
struct MotionKey {
  double time = 0.0;           // s
  Vec3 position{0, 0, 0};      // m
  Vec3 rotation_deg{0, 0, 0};  // XYZ Euler angles about the reference point, degrees
};

struct ObjectDesc {
  std::string name, path;  // path: JSON path of the object, e.g. /objects/0
  ObjectKind kind = ObjectKind::Plane;
  // plane
  Vec3 point{0, 0, 0}, normal{0, 1, 0};
  std::optional<std::array<double, 2>> extent;  // plane `size` [w, h], m; infinite when absent
  bool checker = false;
  // sphere; capsule radius
  Vec3 center{0, 0, 0};
  double radius = 0.5;  // m
  // box; container (an open box: floor and four walls)
  Vec3 size{1, 1, 1};           // full (outer) extents, m
  double wall = 0.05;           // container wall and floor thickness, m
  Vec3 rotation_deg{0, 0, 0};   // XYZ Euler angles, degrees
  // capsule: segment from a to b
  Vec3 a{0, 0, 0}, b{0, 1, 0};
  // mesh: the imported triangles, placed by x ↦ R·(scale ⊙ x) + position (R from rotation_deg)
  std::string file;
  std::shared_ptr<const TriMesh> mesh;
  Vec3 position{0, 0, 0};
  Vec3 scale{1, 1, 1};
  double thickness = 0.0;  // contact offset added to the surface, m
  Surface surface;
  // Per-species surfaces for liquids: species name → surface (keys not given keep `surface`'s).
  std::vector<std::pair<std::string, Surface>> species_surface;
  // Dynamic objects move under gravity and the liquid's push (momentum exchanged both ways).
  bool dynamic = false;
  double mass = 1.0;  // kg (dynamic objects)
  Material material;
  std::vector<MotionKey> motion;  // keyframes (times increasing); empty: static
  // The reference point that motion keys place (see MotionKey).
  Vec3 referencePoint() const {
    switch (kind) {
      case ObjectKind::Plane: return point;
      case ObjectKind::Sphere:
      case ObjectKind::Box:
      case ObjectKind::Container: return center;
      case ObjectKind::Capsule: return 0.5 * (a + b);
      case ObjectKind::Mesh: return position;
    }
    return Vec3::Zero();
  }
};

// --- bodies -------------------------------------------------------------------------------
struct NodeDesc {
  Vec3 position{0, 0, 0};  // m
  Vec3 velocity{0, 0, 0};  // m/s
  double mass = 1.0;       // kg
  double damping = 0.0;    // nodal drag γ_i, N·s/m
  bool fixed = false;
};

struct SpringDesc {
  int a = 0, b = 0;
  double stiffness = 0.0;     // c, N/m
  double damping = 0.0;       // γ_ij, N·s/m
  double rest_length = -1.0;  // l, m; negative: the initial distance
};

struct SpringParams {
  double stiffness = 0.0;  // N/m
  double damping = 0.0;    // N·s/m
};

// The seed's data model: explicit nodes and springs.
struct MassSpringDesc {
  std::vector<NodeDesc> nodes;
  std::vector<SpringDesc> springs;
};

// A chain of `segments` springs from `start` to `end`.
struct RopeDesc {
  Vec3 start{0, 0, 0}, end{1, 0, 0};
  int segments = 10;
  double length = -1.0;  // rest length of the whole rope, m; negative: |end - start|
  double mass = 1.0;     // total, kg
  SpringParams spring{1000.0, 0.0};
  double node_damping = 0.0;
  Vec3 velocity{0, 0, 0};
  std::vector<int> pinned;  // node indices, resolved
};

// A rectangular grid of nodes in the local x–z plane with structural and shear springs.
struct NetDesc {
  Vec3 position{0, 0, 0};      // centre, m
  Vec3 rotation_deg{0, 0, 0};  // XYZ Euler angles
  std::array<double, 2> size{1.0, 1.0};  // [w along x, h along z], m
  std::array<int, 2> resolution{10, 10};  // nodes [nx, ny]
  double mass = 1.0;
  SpringParams structural{1000.0, 0.0}, shear{1000.0, 0.0};
  double node_damping = 0.0;
  Vec3 velocity{0, 0, 0};
  std::vector<int> pinned;  // node index = j * nx + i
};

// A 3-D block of nodes with edge, face-diagonal and body-diagonal springs.
struct LatticeDesc {
  Vec3 position{0, 0, 0};
  Vec3 rotation_deg{0, 0, 0};
  Vec3 size{1, 1, 1};
  std::array<int, 3> resolution{4, 4, 4};  // node index = (k * ny + j) * nx + i
  double mass = 1.0;
  SpringParams edge{1000.0, 0.0}, face{1000.0, 0.0}, body{1000.0, 0.0};
  double node_damping = 0.0;
  Vec3 velocity{0, 0, 0};
  std::vector<int> pinned;
};

// Air acting on each triangle of a cloth, relative to the wind w = u − v (wind minus the
// triangle's velocity), n the unit normal, A the area:
//   viscous (Terzopoulos et al. 1987):  f = c·A·(n·w)·n
//   quadratic drag and lift:            f = ½ρA|w|²·(C_d·|n·ŵ|·ŵ + C_l·(n·ŵ)·l̂),
//   l̂ the unit part of sign(n·ŵ)·n perpendicular to ŵ.
struct AirDesc {
  double viscous = 0.0;  // c, N·s/m³
  double drag = 0.0;     // C_d
  double lift = 0.0;     // C_l
  double density = 1.2;  // ρ, kg/m³
};

// Tearing (Terzopoulos & Fleischer 1988): a spring breaks when its strain (L − l)/l passes its
// threshold, strain·(1 + variation·(2ξ − 1)), ξ uniform in [0, 1) from the scene seed.
struct TearDesc {
  double strain = 0.0;     // 0: the cloth never tears
  double variation = 0.0;  // 0..1
};

// Pinned nodes moved at a constant velocity between two times (a hand pulling an edge).
struct GripDesc {
  std::vector<int> nodes;
  Vec3 velocity{0, 0, 0};  // m/s
  double start = 0.0, stop = std::numeric_limits<double>::infinity();  // s
};

// A rectangular sheet of nx × ny nodes in the local x–z plane: structural springs along the
// grid lines, shear springs across each cell, bend springs over every second node.
struct ClothDesc {
  Vec3 position{0, 0, 0};      // centre, m
  Vec3 rotation_deg{0, 0, 0};  // XYZ Euler angles
  std::array<double, 2> size{1.0, 1.0};   // [w along x, h along z], m
  std::array<int, 2> resolution{16, 16};  // nodes [nx, ny]; node index = j * nx + i
  double mass = 0.3;  // total, kg (from `mass`, or `density` × area)
  SpringParams structural{2000.0, 0.5}, shear{500.0, 0.2}, bend{20.0, 0.02};
  double node_damping = 0.0;
  Vec3 velocity{0, 0, 0};
  std::vector<int> pinned;
  std::vector<GripDesc> grips;
  double thickness = 0.005;   // m: contact offset and half the gap kept by self-collision
  bool self_collision = false;
  double strain_limit = 0.0;  // Provot: structural and shear springs at most (1 + this)·l; 0 off
  TearDesc tear;
  AirDesc air;
  std::array<double, 2> uv_scale{1.0, 1.0};  // texture repeats across the sheet
};

// Nodes and springs (structural, shear and bend) of an nx × ny sheet.
inline std::pair<long long, long long> clothCounts(long long nx, long long ny) {
  const long long structural = (nx - 1) * ny + nx * (ny - 1), shear = 2 * (nx - 1) * (ny - 1);
  const long long bend = (nx > 2 ? nx - 2 : 0) * ny + nx * (ny > 2 ? ny - 2 : 0);
  return {nx * ny, structural + shear + bend};
}

// The wind field u(x, t) = velocity + gusts: a sum of three travelling waves whose directions,
// periods and phases come from the scene seed, scaled so their amplitude is about `gust`.
struct WindDesc {
  Vec3 velocity{0, 0, 0};    // m/s
  double gust = 0.0;         // m/s
  double gust_period = 2.0;  // s, the mean period of the gusts
};

// --- the discrete particle fluid (Terzopoulos, Platt & Fleischer 1989; Miller & Pearce 1989) ---
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
  long long along(int axis) const {
    return std::max(1ll, static_cast<long long>(std::floor((max[axis] - min[axis]) / spacing + 1e-9)));
  }
  double count() const { return static_cast<double>(along(0)) * static_cast<double>(along(1)) * static_cast<double>(along(2)); }
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
  long long perLayer() const { return static_cast<long long>(hexDisc(radius, spacing).size()); }
  // Layers emitted from start to stop (stop finite): one at `start`, then every perLayer()/rate s.
  long long layers() const {
    return static_cast<long long>(std::floor((stop - start) * rate / static_cast<double>(perLayer()) + 1e-9)) + 1;
  }
};

enum class FluidDraw { Spheres, Surface };

struct FluidDesc {
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
  // Particles the emitters release in all.
  long long emitted() const {
    long long n = 0;
    for (const EmitterDesc& e : emitters) n += e.layers() * e.perLayer();
    return n;
  }
};

struct BodyDesc {
  std::string name, type, path;  // type as in the scene: mass_spring, rope, net, lattice, cloth, fluid
  std::variant<MassSpringDesc, RopeDesc, NetDesc, LatticeDesc, ClothDesc, FluidDesc> shape;
  Material material;
  double node_radius = 0.02;  // m, for drawing nodes
};

// --- what the renderer reads -------------------------------------------------------------------
struct RenderDesc {
  int width = 1280, height = 720, samples = 4;
  Vec3 background_top{0.8, 0.85, 0.9}, background_bottom{0.8, 0.85, 0.9};  // linear colours
  std::string tonemap = "none";  // none | aces
  Vec3 fog_color{0.5, 0.6, 0.7};
  double fog_density = 0.0;  // 1/m, 0: no fog
};

struct CameraKey {
  double time = 0.0;
  Vec3 position{0, 1, 5}, target{0, 0, 0};
  double fov_deg = 40.0;
};

struct CameraDesc {
  Vec3 position{0, 1, 5}, target{0, 0, 0}, up{0, 1, 0};
  double fov_deg = 40.0;  // vertical field of view
  std::vector<CameraKey> keys;
};

// Settings of the implicit integrator's conjugate-gradient solve.
struct ImplicitSettings {
  double cg_tolerance = 1e-8;  // relative residual
  int cg_max_iterations = 500;
};

struct SceneDesc {
  std::string file;  // the scene file, for messages and asset resolution
  std::string name;
  double duration = 1.0;  // s
  int fps = 30;
  int substeps = 10;
  std::uint64_t seed = 0;
  Vec3 gravity{0, -9.78, 0};
  WindDesc wind;
  IntegratorKind integrator = IntegratorKind::SymplecticEuler;
  bool auto_substeps = false;  // subdivide a step above an explicit integrator's stability bound
  ImplicitSettings implicit;
  RenderDesc render;
  CameraDesc camera;
  bool has_lights = false;  // a `lights` list was given: exactly those lights shine
  std::vector<LightDesc> lights;
  std::vector<ObjectDesc> objects;
  std::vector<BodyDesc> bodies;

  // N = round(duration · fps); frame k shows time k / fps.
  int frameCount() const { return static_cast<int>(std::lround(duration * fps)); }
};

}  // namespace reel
