// Perception and behaviour of the artificial fish (Tu & Terzopoulos 1994, §4 and §5; Tu 1996,
// chapters 5 and 6): what a fish perceives is a list (`Percept`) that the behaviour reads, never
// the world; the mental state (hunger, libido, fear), the intention generator in the paper's
// priority order with a short memory, and the behaviour routines that command the motor
// controllers.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/scene/fish.h"
#include "core/types.h"
#include "sim/collide.h"
#include "sim/fish/fish.h"
#include "sim/grid.h"
#include "sim/school/school.h"
#include "sim/shared_view.h"

namespace reel {

enum class Intention : int { Wander, AvoidObstacle, AvoidFish, Escape, School, Chase, Eat, Mate, Caught };
inline constexpr std::array<const char*, 9> kIntentionNames = {"wander", "avoid_obstacle", "avoid_fish", "escape",
                                                                "school", "chase", "eat", "mate", "caught"};

// One thing a fish perceives.
struct Seen {
  enum class Kind : int { Fish, Food, Hook } kind = Kind::Fish;
  int body = -1, index = -1;  // its body and, for a fish, its index there, for food its id; hook: −1
  Vec3 x{0, 0, 0}, v{0, 0, 0};
  double distance = 0.0;
  double length = 0.0;           // fish: its length
  bool predator = false;         // a hunter larger than the viewer
  bool prey = false;             // smaller than a hunting viewer, of another body
  bool kin = false;              // of the viewer's own body
  bool mate = false;             // of the viewer's species and a mating species, not caught
};

struct Percept {
  std::vector<Seen> seen;  // nearest first, at most kMaxSeen
  Steering surroundings;   // objects ahead (push, urgency)
  Steering bounds;         // the walls of the fish's bounds ahead (a bias on the course)
};
inline constexpr std::size_t kMaxSeen = 16;

// What the eyes and the nose have: every fish of the world, the food, the hook, the objects.
struct FishWorldView {
  const std::vector<FishSighting>* fish = nullptr;  // all fish of the world
  const BoxGrid* fish_grid = nullptr;               // over their centres, cell ≥ the largest vision radius
  struct Food {
    int body = -1;
    const std::vector<Vec3>* x = nullptr;            // particle positions
    const std::vector<std::int64_t>* id = nullptr;   // and their ids (what a Seen's index holds)
  };
  std::vector<Food> food;
  const Collider* hook = nullptr;
  const std::vector<Collider>* obstacles = nullptr;  // the objects but the hook
};

// Vision (a 300° cone within a radius, scaled by the other's size, occluded by objects) and smell
// (food within a larger radius, through anything).
void perceive(const FishDesc& d, const FishFrame& self, int self_body, int self_index, const FishWorldView& w,
              Percept& out);

// The mental state and the intention with its memory (a snapshot keeps it).
struct FishMind {
  double hunger = 0.0, libido = 0.0, fear = 0.0;  // each 0..1
  int intention = 0, previous = 0;  // Intention; the one interrupted by an avoidance
  double since = 0.0;               // s the intention has held
  int target_body = -1, target_index = -1;
  double courting = 0.0;            // s of courtship with the current mate
  std::array<double, 3> wander{0, 0, 1};  // the wandering direction, unit (plain numbers: snapshots copy it)
};

// Hunger, libido and fear after dt (Tu & Terzopoulos 1994 §5.1): hunger grows as the meal is
// digested, libido as the urge grows while not hungry, fear is the sum over seen predators of
// min(D₀/d, 1) scaled by timidity.
void updateMind(const FishDesc& d, const Percept& p, double dt, FishMind& m);

// The intention generator and the behaviour routines: the command for the motor controllers.
// `decision` numbers this decision (the wander's random stream).
MotorCommand behave(const FishDesc& d, const FishFrame& self, const Percept& p, double dt, std::uint64_t seed,
                    std::int64_t decision, std::size_t fish, FishMind& m);

}  // namespace reel
