// A read-only view of one frame's simulated state, filled by sim and written by io (dumps).
// The spans point into the World and stay valid until it next steps.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "core/types.h"

namespace reel {

// Numbers a kind adds to its dump entry, per item (a fish's muscle contractions, its mental state):
// `values` holds `per_item` numbers for each item, item after item.
struct ViewField {
  std::string name;
  int per_item = 1;
  std::vector<double> values;
};

// A joint of an articulated body: its child link's name and its angles, rad.
struct JointView {
  std::string name;
  std::vector<double> angles;
};

struct BodyView {
  std::string name;
  std::string type;       // dump type: "mass_spring", "particles" or "agents"
  std::string generator;  // scene type that built it: mass_spring, rope, net, lattice, cloth, fluid, school
  std::span<const Vec3> positions;   // m (nodes)
  std::span<const Vec3> velocities;  // m/s (nodes)
  std::span<const int> spring_a, spring_b;  // intact springs as index pairs (springs)
  std::span<const int> species;              // particles: species index of each
  std::vector<std::string> species_names;    // particles: the species, by index
  std::span<const double> masses;            // nodes' masses, kg (when the kind lists them)
  std::vector<ViewField> fields;             // the kind's own numbers
  std::vector<std::string> link_names;       // articulated: per item (link), its name
  std::vector<JointView> joints;             // articulated: per joint, its angles
};

// A quantity of a body at one frame, for `reel simulate --stats` (a school's polarisation, say).
struct Statistic {
  std::string name;
  double value = 0.0;
};

struct FrameView {
  int frame = 0;
  double time = 0.0;  // s, = frame / fps
  std::vector<BodyView> bodies;
};

// A FrameView that owns what its spans show: it stays valid after the World steps on (the last
// good frame a dump still writes after the next one goes unstable; after a tear its springs are
// the frame's own, not the model's now).
class FrameCopy {
 public:
  FrameCopy() = default;
  FrameCopy(const FrameCopy&) = delete;
  FrameCopy& operator=(const FrameCopy&) = delete;
  void take(const FrameView& v) {
    view_ = v;
    store_.assign(v.bodies.size(), {});
    for (std::size_t b = 0; b < v.bodies.size(); ++b) {
      BodyView& bv = view_.bodies[b];
      Store& s = store_[b];
      s.x.assign(bv.positions.begin(), bv.positions.end());
      s.v.assign(bv.velocities.begin(), bv.velocities.end());
      s.a.assign(bv.spring_a.begin(), bv.spring_a.end());
      s.b.assign(bv.spring_b.begin(), bv.spring_b.end());
      s.species.assign(bv.species.begin(), bv.species.end());
      s.masses.assign(bv.masses.begin(), bv.masses.end());
      bv.positions = s.x;
      bv.velocities = s.v;
      bv.spring_a = s.a;
      bv.spring_b = s.b;
      bv.species = s.species;
      bv.masses = s.masses;
    }
  }
  const FrameView& view() const { return view_; }

 private:
  struct Store {
    std::vector<Vec3> x, v;
    std::vector<int> a, b, species;
    std::vector<double> masses;
  };
  FrameView view_;
  std::vector<Store> store_;
};

}  // namespace reel
