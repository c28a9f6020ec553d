// Where a run's time goes, by stage (reel bench film, DESIGN 8): a scope names the stage its code
// belongs to and its time is charged there; nested scopes take their time out of the enclosing
// one, so the stages add up to the time measured. Off by default: then a scope costs one load of
// a flag. Scopes are placed in serial code only (around parallel loops, never inside them).
// Timing never changes what is computed.
#pragma once

#include <array>
#include <chrono>
#include <cstddef>
#include <string_view>

namespace reel::profile {

enum class Stage : int {
  Other,          // whatever no scope claims: setup, bookkeeping, the stepping loop itself
  Integration,    // forces and the integrator's update (the implicit solve included)
  Contacts,       // bodies against objects
  SelfCollision,  // a sheet against itself
  StrainLimit,    // Provot's strain limiting
  Tearing,        // threads breaking, the incidence rebuilt
  Neighbours,     // neighbour lists and grids
  PairForces,     // particle pair forces
  Coupling,       // exchanges between kinds (liquid and cloth) and free objects taking their share
  Surface,        // liquid surface extraction (drawing a liquid)
  DrawList,       // filling the draw lists besides the surface (meshes, normals)
  Count
};
inline constexpr std::array<std::string_view, static_cast<std::size_t>(Stage::Count)> kStageNames = {
    "other", "integration", "contacts", "self_collision", "strain_limit", "tearing",
    "neighbours", "pair_forces", "coupling", "surface", "draw_list"};

using Seconds = std::array<double, static_cast<std::size_t>(Stage::Count)>;

// Starts charging time to stages (reset to zero) or stops.
void enable(bool on);
bool enabled();
// The seconds charged to each stage since enable(true); the running scope's time so far included.
Seconds totals();

namespace detail {
void enter(Stage s, Stage& previous);
void leave(Stage previous);
extern bool g_on;
extern thread_local bool t_muted;
}  // namespace detail

class Scope {
 public:
  explicit Scope(Stage s) {
    if (detail::g_on && !detail::t_muted) {
      on_ = true;
      detail::enter(s, previous_);
    }
  }
  ~Scope() {
    if (on_) detail::leave(previous_);
  }
  Scope(const Scope&) = delete;
  Scope& operator=(const Scope&) = delete;

 private:
  bool on_ = false;
  Stage previous_ = Stage::Other;
};

// While one lives, this thread's scopes charge nothing: bodies stepping side by side on the worker
// threads (World::stepTogether), whose time the simulation thread's enclosing scope takes.
class Mute {
 public:
  Mute() : saved_(detail::t_muted) { detail::t_muted = true; }
  ~Mute() { detail::t_muted = saved_; }
  Mute(const Mute&) = delete;
  Mute& operator=(const Mute&) = delete;

 private:
  bool saved_;
};

}  // namespace reel::profile
