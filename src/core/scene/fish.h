// The kinds of the fish world (Tu & Terzopoulos 1994, "Artificial Fishes"): `fish` (muscle-driven
// mass-spring bodies with perception and behaviour), `food` (drifting plankton) and `seaweed`
// (strands pinned to the seabed, swayed by the currents). docs/fish.md lists every key.
#pragma once

#include <algorithm>
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "core/scene/body.h"
#include "core/scene/school.h"
#include "core/types.h"

namespace reel {

// The twelve muscles: 3 segments (front, middle, rear) × 2 sides (left, right) × 2 (upper, lower).
// Muscle m = 4·segment + 2·side + (lower ? 1 : 0). Left is +x of a fish heading +z with +y up.
inline constexpr int kFishMuscles = 12;
inline constexpr std::array<const char*, 3> kFishSegments = {"front", "middle", "rear"};
inline constexpr std::array<const char*, 2> kFishSides = {"left", "right"};

// A contraction applied to muscles directly (`drive.muscles`): amplitude·max(0, sin(2πf(t −
// start) + phase)) between start and stop, or the amplitude throughout when f = 0.
struct MusclePatternDesc {
  std::vector<int> muscles;  // indices as above
  double contraction = 0.0;  // 0..1 of the muscle's largest contraction
  double frequency = 0.0;    // Hz
  double phase_deg = 0.0;
  double start = 0.0, stop = 1e30;  // s
};

// The motor controllers run directly (`"behaviour": "none"`), for tests and choreographed shots.
struct FishDriveDesc {
  double swim_frequency = 0.0;  // Hz of the tail beat; 0: no swimming
  double swim_amplitude = 1.0;  // 0..1
  double swim_start = 0.0, swim_stop = 1e30;  // s
  int turn_side = 0;            // +1 left, −1 right, 0 none
  double turn_amount = 1.0;     // 0..1 of the largest bend
  double turn_start = 0.0, turn_stop = 0.0;  // s
  double turn_angle_deg = 0.0;  // > 0: turn by this angle (closed loop) instead of until turn_stop
  double pitch_deg = 0.0;       // pectoral fins: + rises, − dives
  double yaw_deg = 0.0;         // pectoral fins: + opens the left fin (yaws left), − the right
  std::vector<MusclePatternDesc> muscles;
};

enum class FishSpecies { Prey, Predator, Pacifist };
inline constexpr std::array<const char*, 4> kFishPatternNames = {"stripes", "spots", "gradient", "plain"};
inline constexpr std::array<const char*, 3> kFishSpeciesNames = {"prey", "predator", "pacifist"};

// What the species presets set (each key may be given to override it).
struct FishHabits {
  bool schools = false;   // prey: keeps with its own body's fish, about one length apart
  bool hunts = false;     // predator: chases fish of other bodies that are smaller than itself
  bool mates = false;     // pacifist: courtship circling when libido is high
  double timidity = 0.5;  // 0..1: how strongly a predator in view raises fear
};

struct FishDesc final : BodyParams {
  FishSpecies species = FishSpecies::Prey;
  FishHabits habits;
  bool behaviour = true;  // false: "behaviour": "none", the drive below runs the controllers
  FishDriveDesc drive;

  long long count = 1;
  bool start_given = false;           // `start` (or `count` > 1): random places in it
  StartRegion start;
  Vec3 position{0, 0, 0};             // for one fish (count 1 without start)
  std::optional<Vec3> heading;        // for one fish: unit (absent: +z)
  double length = 0.5;                // m, nose to tail tip
  double cruise_speed = 1.0;          // body lengths per second when wandering
  double max_speed = 2.0;             // body lengths per second when fleeing or chasing

  // Mental state at the start, each in [0, 1].
  double hunger = 0.3, libido = 0.0, fear = 0.0;
  double digestion = 0.05;  // 1/s: how fast a meal is digested (hunger comes back)
  double urge = 0.02;       // 1/s: how fast libido grows while not hungry

  // Perception.
  double vision_radius = 10.0;      // m
  double field_of_view_deg = 300.0;
  double smell_radius = 20.0;       // m: food is smelt (not seen) within this
  std::string hook;                 // an object the fish may bite (and be caught on)
  std::vector<std::string> ignore;  // objects the fish do not steer around (a fishing line)
  std::optional<SchoolBoundsDesc> bounds;  // a box or ball the fish turn back from

  // Look.
  bool wireframe = false;          // "draw": "wireframe": nodes, springs and muscles
  std::string pattern = "stripes"; // `skin`: stripes | spots | gradient | plain
  Vec3 pattern_color{0.1, 0.1, 0.12};  // `skin_color`: linear rgb of the stripes, spots or back

  std::pair<long long, long long> nodesAndSprings() const override { return {23 * count, 91 * count}; }
  double contactRadius(double) const override { return 0.04 * length; }
};

// Plankton: particles emitted at random points of a box at a rate up to a number alive, drifting
// with the water and sinking slowly; eaten by fish (and then gone).
struct FoodDesc final : BodyParams {
  Vec3 min{-1, -1, -1}, max{1, 1, 1};  // the emitter region, m
  long long initial = 50;              // particles at the start
  double rate = 5.0;                   // particles per second
  long long max_alive = 200;
  double sink_speed = 0.02;            // m/s
  double jitter = 0.05;                // m/s: random swimming of the plankton
  double size = 0.03;                  // m: drawn radius
  double bite = 0.0;                   // m: a mouth this close eats it (0: a tenth of the fish)
};

// Strands of seaweed or kelp pinned at the seabed: ropes of nodes and springs, buoyant, dragged by
// the water's flow.
struct SeaweedDesc final : BodyParams {
  std::vector<Vec3> bases;    // where each strand is pinned, m
  long long count = 0;        // or this many at random points of [min, max] (y of min)
  Vec3 min{-1, 0, -1}, max{1, 0, 1};
  double height = 2.0;        // m
  double height_variation = 0.3;  // 0..1: strands differ by up to this fraction
  int segments = 10;
  double mass = 0.2;          // kg per strand
  double stiffness = 400.0;   // N/m per spring
  double buoyancy = 1.5;      // times its weight, upward
  double drag = 2.0;          // N·s/m per node, toward the water's velocity
  double width = 0.05;        // m: drawn as ribbons this wide
  std::pair<long long, long long> nodesAndSprings() const override {
    const long long n = bases.empty() ? count : static_cast<long long>(bases.size());
    return {n * (segments + 1), n * (2 * segments - 1)};
  }
};

}  // namespace reel
