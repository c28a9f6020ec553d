// SceneDesc: the plain, validated description of a shot (DESIGN 2, 4). io::loadScene fills it,
// sim builds a World from it, the renderer reads camera, lights and materials from it.
// Everything here is data; JSON paths (`path`) are kept so later stages can name the key at fault.
#pragma once

#include <array>
#include <memory>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "core/image.h"
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
};

enum class ObjectKind { Plane, Sphere, Box, Capsule, Mesh };

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
  // box
  Vec3 size{1, 1, 1};           // full extents, m
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
  Material material;
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

struct BodyDesc {
  std::string name, type, path;  // type as in the scene: mass_spring, rope, net, lattice
  std::variant<MassSpringDesc, RopeDesc, NetDesc, LatticeDesc> shape;
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

enum class LightKind { Directional, Point, Ambient };
struct LightDesc {
  LightKind kind = LightKind::Directional;
  Vec3 direction{-1, -2, -1}, position{0, 5, 0}, color{1, 1, 1};
  double intensity = 1.0;
  bool shadows = false;
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
