// SceneDesc: the plain, validated description of a shot (DESIGN 2, 4). io::loadScene fills it,
// sim builds a World from it, the app hands its camera, lights and look to the renderer.
// Everything here is data; JSON paths (`path`) are kept so later stages can name the key at fault.
// Objects are in core/scene/object.h; each body kind's description in core/scene/<kind>.h.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/environment.h"
#include "core/light.h"
#include "core/scene/body.h"
#include "core/scene/object.h"
#include "core/types.h"

namespace reel {

// Integrators by name (SPlisHSPlasH-style registration by name).
enum class IntegratorKind { SymplecticEuler, ExplicitEuler, Verlet, Rk4, ImplicitEuler, Bdf2 };
inline constexpr std::array<std::string_view, 6> kIntegratorNames = {
    "symplectic_euler", "explicit_euler", "verlet", "rk4", "implicit_euler", "bdf2"};
// The integrators that solve a linear system each step and have no stability bound on the step.
inline bool implicitIntegrator(IntegratorKind k) { return k == IntegratorKind::ImplicitEuler || k == IntegratorKind::Bdf2; }
inline std::string_view integratorName(IntegratorKind k) { return kIntegratorNames[static_cast<int>(k)]; }
inline std::optional<IntegratorKind> integratorFromName(std::string_view s) {
  for (std::size_t i = 0; i < kIntegratorNames.size(); ++i)
    if (kIntegratorNames[i] == s) return static_cast<IntegratorKind>(i);
  return std::nullopt;
}

// The wind field u(x, t) = velocity + gusts: a sum of three travelling waves whose directions,
// periods and phases come from the scene seed, scaled so their amplitude is about `gust`.
struct WindDesc {
  Vec3 velocity{0, 0, 0};    // m/s
  double gust = 0.0;         // m/s
  double gust_period = 2.0;  // s, the mean period of the gusts
};

// The water the fish kinds live in (docs/fish.md): its density and its currents. Read by the
// `fish`, `food` and `seaweed` kinds; a scene without `water` has still water of 1000 kg/m³.
struct CurrentDesc {
  enum class Kind { Uniform, Source, Sink } kind = Kind::Uniform;
  Vec3 velocity{0, 0, 0};   // uniform: mean flow, m/s
  Vec3 amplitude{0, 0, 0};  // uniform: the flow varies by amplitude·sin(2πt/period), m/s
  double period = 10.0;     // s
  std::string object;       // source, sink: the object it flows from or to
  int collider = -1;        // that object's index in `objects`
  double rate = 0.0;        // source, sink: volume flow, m³/s
  double core = 0.5;        // m: inside this radius the flow falls linearly to zero
};
struct WaterDesc {
  double density = 1000.0;  // kg/m³; 0: no water
  std::vector<CurrentDesc> currents;
};

// --- what the renderer reads -------------------------------------------------------------------
// render.environment: light from every direction, a procedural sky or an HDR picture
// (docs/rendering.md, "Image-based light"), prefiltered once when the scene loads.
struct EnvironmentDesc {
  enum class Kind { None, Sky, File } kind = Kind::None;
  Vec3 zenith{0, 0, 0}, horizon{0, 0, 0}, ground{0, 0, 0};  // sky: linear radiance
  std::string file;                   // file: the resolved path
  double intensity = 1.0;             // scales the radiance
  double rotation_deg = 0.0;          // turns the picture about +y
  bool background = true;             // seen where nothing covers the picture
  std::shared_ptr<const Environment> maps;
};

struct RenderDesc {
  int width = 1280, height = 720, samples = 4;
  Vec3 background_top{0.8, 0.85, 0.9}, background_bottom{0.8, 0.85, 0.9};  // linear colours
  BackgroundGlow background_glow;
  std::string tonemap = "none";  // none | aces
  double exposure = 0.0;         // EV
  EnvironmentDesc environment;
  double ao_radius = 0.0;        // m; 0: no ambient occlusion
  double ao_strength = 1.0;
  Vec3 fog_color{0.5, 0.6, 0.7};
  double fog_density = 0.0;  // 1/m, 0: no fog
  double shutter_deg = 0.0;  // motion blur: the shutter angle (0: none, 360: the whole frame)
  int shutter_samples = 5;   // pictures averaged over the shutter interval
};

struct CameraKey {
  double time = 0.0;
  Vec3 position{0, 1, 5}, target{0, 0, 0};
  double fov_deg = 40.0;
};

// A camera that keeps a body in the picture (scene keys `follow` and `frame`): the body's centre
// (and, to frame it, its size) are smoothed by a critically damped spring that trails a body moving
// at a steady speed by `lag` seconds, so the camera moves like an operator's, not like the body.
struct CameraRigDesc {
  enum class Mode {
    None,
    Track,  // follow: the camera and its target move with the smoothed centre
    Pan,    // follow: the camera stays, its target moves with the smoothed centre
    Frame,  // frame: aims at the smoothed centre from a distance that fits the body in view
  };
  Mode mode = Mode::None;
  std::string body;     // the body's name
  double lag = 0.5;     // s: how far behind a steadily moving body the camera trails; 0: rigidly
  double margin = 1.3;  // frame: the picture's half-size over the body's radius
  std::string path;     // JSON path of the body's name, for errors
};

struct CameraDesc {
  Vec3 position{0, 1, 5}, target{0, 0, 0}, up{0, 1, 0};
  double fov_deg = 40.0;  // vertical field of view
  std::vector<CameraKey> keys;
  CameraRigDesc rig;
  // Depth of field (scene key depth_of_field): the lens' diameter (m; 0: a pinhole, all sharp),
  // the distance in focus (m; 0: the target's), and the pictures averaged over the lens.
  double aperture = 0.0, focus_distance = 0.0;
  int lens_samples = 8;
};

// Settings of the implicit integrator's conjugate-gradient solve.
// Unless the scene gives `cg_tolerance`, each kind solves to its own default: a sheet, rope, net
// or lattice to 10⁻² of the right-hand side, Blender's cloth criterion (no visible difference from
// a tight solve in a film, docs/cloth.md, and 7x faster than 10⁻⁸), a fish to 10⁻⁴ (its thrust
// comes from the body wave's small differences).
inline constexpr double kFilmTolerance = 1e-2;
// The implicit solve's linear solver: conjugate gradients, a direct factorisation of each piece
// of a spring network (sim/skyline.h), or auto: the direct one where a network's factorisation
// costs less than kDirectIterations iterations of CG would (fish, ropes, kelp; not sheets).
enum class LinearSolver { Auto, Cg, Direct };
inline constexpr double kDirectIterations = 6.0;
struct ImplicitSettings {
  double cg_tolerance = kFilmTolerance;  // relative residual ‖r‖ ≤ tol·‖b‖
  int cg_max_iterations = 500;
  bool tolerance_given = false;  // the scene set cg_tolerance: every kind uses it
  LinearSolver solver = LinearSolver::Auto;
};

// Steps a frame by default: 10, or this many with implicit_euler or bdf2.
inline constexpr int kImplicitSubsteps = 5;

struct SceneDesc {
  std::string file;  // the scene file, for messages and asset resolution
  std::string name;
  double duration = 1.0;  // s
  int fps = 30;
  int substeps = 10;
  std::uint64_t seed = 0;
  Vec3 gravity{0, -9.78, 0};
  WindDesc wind;
  WaterDesc water;
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

// The index of the object named `name` in scene.objects (its collider's index too), or −1.
inline int objectIndex(const SceneDesc& scene, const std::string& name) {
  for (std::size_t k = 0; k < scene.objects.size(); ++k)
    if (scene.objects[k].name == name) return static_cast<int>(k);
  return -1;
}

}  // namespace reel
