// The mass-spring kinds' descriptions: the seed's explicit nodes and springs (`mass_spring`), and
// the generators `rope`, `net` and `lattice` that build the same kind of state from a few keys.
#pragma once

#include <array>
#include <utility>
#include <vector>

#include "core/scene/body.h"
#include "core/types.h"

namespace reel {

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
struct MassSpringDesc final : BodyParams {
  std::vector<NodeDesc> nodes;
  std::vector<SpringDesc> springs;
  std::pair<long long, long long> nodesAndSprings() const override {
    return {static_cast<long long>(nodes.size()), static_cast<long long>(springs.size())};
  }
};

// A chain of `segments` springs from `start` to `end`.
struct RopeDesc final : BodyParams {
  Vec3 start{0, 0, 0}, end{1, 0, 0};
  int segments = 10;
  double length = -1.0;  // rest length of the whole rope, m; negative: |end - start|
  double mass = 1.0;     // total, kg
  SpringParams spring{1000.0, 0.0};
  double node_damping = 0.0;
  Vec3 velocity{0, 0, 0};
  std::vector<int> pinned;  // node indices, resolved
  std::pair<long long, long long> nodesAndSprings() const override { return {segments + 1ll, segments}; }
};

// A rectangular grid of nodes in the local x–z plane with structural and shear springs.
struct NetDesc final : BodyParams {
  Vec3 position{0, 0, 0};      // centre, m
  Vec3 rotation_deg{0, 0, 0};  // XYZ Euler angles
  std::array<double, 2> size{1.0, 1.0};  // [w along x, h along z], m
  std::array<int, 2> resolution{10, 10};  // nodes [nx, ny]
  double mass = 1.0;
  SpringParams structural{1000.0, 0.0}, shear{1000.0, 0.0};
  double node_damping = 0.0;
  Vec3 velocity{0, 0, 0};
  std::vector<int> pinned;  // node index = j * nx + i
  std::pair<long long, long long> nodesAndSprings() const override {
    const long long x = resolution[0], y = resolution[1];
    return {x * y, (x - 1) * y + x * (y - 1) + 2 * (x - 1) * (y - 1)};
  }
};

// A 3-D block of nodes with edge, face-diagonal and body-diagonal springs.
struct LatticeDesc final : BodyParams {
  Vec3 position{0, 0, 0};
  Vec3 rotation_deg{0, 0, 0};
  Vec3 size{1, 1, 1};
  std::array<int, 3> resolution{4, 4, 4};  // node index = (k * ny + j) * nx + i
  double mass = 1.0;
  SpringParams edge{1000.0, 0.0}, face{1000.0, 0.0}, body{1000.0, 0.0};
  double node_damping = 0.0;
  Vec3 velocity{0, 0, 0};
  std::vector<int> pinned;
  // Drawn as a smooth skin over its outer nodes (Catmull–Clark, `skin_levels` times), or as
  // its nodes and springs.
  enum class Draw { Skin, Springs } draw = Draw::Skin;
  int skin_levels = 2;
  std::pair<long long, long long> nodesAndSprings() const override {
    const long long x = resolution[0], y = resolution[1], z = resolution[2];
    const long long edges = (x - 1) * y * z + x * (y - 1) * z + x * y * (z - 1);
    const long long faces = 2 * ((x - 1) * (y - 1) * z + (x - 1) * y * (z - 1) + x * (y - 1) * (z - 1));
    return {x * y * z, edges + faces + 4 * (x - 1) * (y - 1) * (z - 1)};
  }
};

}  // namespace reel
