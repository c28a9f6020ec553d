// The cloth kind's description: a sheet of nodes with structural, shear and bend springs, air,
// grips, strain limiting, self-collision and tearing.
#pragma once

#include <array>
#include <limits>
#include <utility>
#include <string>
#include <vector>

#include "core/scene/body.h"
#include "core/scene/mass_spring.h"
#include "core/scene/material.h"
#include "core/types.h"

namespace reel {

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

// Pinned nodes moved at a constant velocity between two times (a hand pulling an edge), or along
// keyframes: `keys` (time, offset from where the nodes start), linear between keys, held outside.
struct GripDesc {
  std::vector<int> nodes;
  Vec3 velocity{0, 0, 0};  // m/s
  double start = 0.0, stop = std::numeric_limits<double>::infinity();  // s
  std::vector<std::pair<double, Vec3>> keys;  // (s, m); non-empty: used instead of the velocity
  // Or held by an object: the nodes move with it (a cape on a figure's chest, "figure/chest"), and
  // it takes their pull and weight (the coupling stage).
  std::string object;
};

// How a sheet meets a liquid (the cloth–liquid exchange, sim/coupling/cloth_liquid.h).
struct WettingDesc {
  Surface surface;                  // friction, restitution, adhesion of the liquid on the sheet
  SpeciesSurfaces species_surface;  // per species
  // 0: impermeable; up to 1: liquid seeps through as through a permeable membrane (Darcy): the
  // sheet resists the liquid's normal speed through it with a drag of time constant
  // kSeepTime·p/(1 − p), so a drop pressed by its own weight seeps at g·that; 1: no resistance.
  double porosity = 0.0;
  // 0: the liquid only runs off; up to 1: the fabric soaks up touching particles until it holds
  // absorbency × kFabricHolds × its dry mass (per node), wicks, drains and drips.
  double absorbency = 0.0;
};
inline constexpr double kSeepTime = 0.01;   // s
inline constexpr double kFabricHolds = 4.0;  // kg of liquid per kg of dry fabric at absorbency 1

// A rectangular sheet of nx × ny nodes in the local x–z plane: structural springs along the
// grid lines, shear springs across each cell, bend springs over every second node.
struct ClothDesc final : BodyParams {
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
  WettingDesc wetting;
  std::pair<long long, long long> nodesAndSprings() const override;
  const SpeciesSurfaces* speciesSurfaces() const override { return &wetting.species_surface; }
  double contactRadius(double) const override { return thickness; }
};

// Nodes and springs (structural, shear and bend) of an nx × ny sheet.
inline std::pair<long long, long long> clothCounts(long long nx, long long ny) {
  const long long structural = (nx - 1) * ny + nx * (ny - 1), shear = 2 * (nx - 1) * (ny - 1);
  const long long bend = (nx > 2 ? nx - 2 : 0) * ny + nx * (ny > 2 ? ny - 2 : 0);
  return {nx * ny, structural + shear + bend};
}

inline std::pair<long long, long long> ClothDesc::nodesAndSprings() const { return clothCounts(resolution[0], resolution[1]); }

}  // namespace reel
