// What bodies see of one another: the typed view the World publishes to every step
// (StepContext::shown). No body reads another body's internals or looks for its kind: each
// body lists, once when the World is built (Body::show), the state it shows others (a school its
// agents, a fish body its fish as seen, a food body its particles and the meals of its last
// step), and readers take that list. Entries point at the showing body's own published state, so
// a reader sees it as of the shower's last step: this step for bodies earlier in scene order.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/scene/fish.h"
#include "core/types.h"
#include "sim/grid.h"

namespace reel {

// A fish as others see it (published by its body after each step).
struct FishSighting {
  Vec3 center{0, 0, 0}, mouth{0, 0, 0}, velocity{0, 0, 0}, forward{0, 0, 1};
  double length = 0.5;
  int body = -1, index = -1;  // its body among the world's bodies, and its index there
  FishSpecies species = FishSpecies::Prey;
  bool hunts = false, mates = false, caught = false;
  bool biting = false;  // its mouth is open for food (intention eat)
};

// A particle of food eaten: by which fish of which body.
struct FoodMeal {
  int body = -1, fish = -1;  // the eater: its body among the world's bodies, its index there
};

// The points of every body that has them (nodes and particles, with their contact radii, as the
// World's contact layer sees them), gathered by the World at the start of each step when a body
// steers around others (Body::watchRadius): the boxes of the points grown by their radius and
// `reach` in a grid, so the points within `reach` of a place are those whose boxes hold it.
struct BodyPoints {
  std::vector<Vec3> x;    // m
  std::vector<double> r;  // m
  double reach = 0.0;     // m
  BoxGrid grid;
};

struct SharedView {
  // A school's agents (a predator school for another school).
  struct Agents {
    std::string body;  // the school's name
    const std::vector<Vec3>* x = nullptr;
    const std::vector<Vec3>* v = nullptr;
  };
  // A fish body's fish.
  struct Fish {
    int body = -1;
    const std::vector<FishSighting>* sightings = nullptr;
  };
  // A food body's particles, their ids and the meals of its last step.
  struct Food {
    int body = -1;
    const std::vector<Vec3>* x = nullptr;
    const std::vector<std::int64_t>* id = nullptr;
    const std::vector<FoodMeal>* meals = nullptr;
  };
  std::vector<Agents> agents;  // each in scene order
  std::vector<Fish> fish;
  std::vector<Food> food;
  const BodyPoints* points = nullptr;  // none when no body watches the others
};

}  // namespace reel
