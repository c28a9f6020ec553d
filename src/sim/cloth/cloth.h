// Cloth: a mass-spring sheet (the shared machinery of mass_spring.h, built by buildCloth) plus
// what only a sheet has: triangles, air forces on them, a wind field, strain limiting,
// self-collision, grips that pull its edges, and tearing with the triangle topology split
// along broken springs.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/mesh.h"
#include "core/scene.h"
#include "core/scene/cloth.h"
#include "core/types.h"
#include "sim/collide.h"
#include "sim/grid.h"
#include "sim/mass_spring.h"
#include "sim/wind.h"

namespace reel {

// What the sheet is: fixed unless it tears (then `ClothState` says which springs are left).
struct ClothModel {
  int nx = 0, ny = 0;
  std::vector<std::array<int, 3>> tris;         // node indices, counter-clockwise from local +y (triangles)
  std::vector<std::array<int, 3>> tri_springs;  // original ids of the springs on edges 01, 12, 20 (triangles)
  std::vector<std::array<int, 3>> tri_adj;      // triangle across edges 01, 12, 20, or −1 (triangles)
  std::vector<int> node_tri_start, node_tri;    // node → incident triangles (nodes + 1; 3·triangles)
  std::vector<float> uv;                        // texture coordinates, 2 per node
  std::vector<std::array<int, 4>> holds;  // by original id: the threads a shear or bend spring needs (−1: none)
  int structural = 0;  // original ids below this are structural springs (the threads)
  double strain_limit = 0.0;
  double thickness = 0.005;
  bool self_collision = false;
  AirDesc air;
  std::vector<GripDesc> grips;
  std::vector<Vec3> grip_origin;  // where each gripped node starts, per grip in order of nodes
  std::vector<int> grip_collider;  // per grip: the collider that holds it (GripDesc::object), or −1
  WettingDesc wetting;            // how it meets liquids (sim/coupling/cloth_liquid.h)
  std::vector<double> dry_mass;   // kg (nodes): a node's mass is this plus its wetness
  std::vector<double> capacity;   // liquid a node holds before it drips, kg (nodes; empty: not absorbent)
};

// What changes as the sheet moves and tears (besides the nodes and the springs themselves, in the
// mass-spring state and model).
struct ClothState {
  std::vector<int> spring_id;       // original id of each current spring (springs)
  std::vector<std::uint8_t> intact; // by original spring id
  std::vector<std::uint8_t> limited;  // structural or shear spring: strain-limited (springs)
  std::vector<double> tear_strain;    // breaking strain (springs; infinite for shear and bend); empty: never tears
  std::vector<std::uint8_t> tri_alive;  // both structural edges intact (triangles)
  std::vector<Vec3> x_prev;  // node positions at the last self-collision pass, m (nodes)
  long long self_passes = 0;
  long long springs_broken = 0;
  // Liquid soaked up (absorbent sheets): kg per node, and the species of the last particle each
  // node took (what it drips).
  std::vector<double> wet;
  std::vector<int> wet_species;
  std::uint64_t wet_from = 0;  // FNV hash of the name of the liquid it soaked up last (its drips go back there)
  long long absorbed = 0, dripped = 0;  // particles soaked up and drops released so far
  Vec3 pin_liquid_force{0, 0, 0};  // the liquid's force on pinned and gripped nodes over the last step, N
};

// Arrays reused from step to step; their contents do not outlive a step.
struct ClothScratch {
  std::vector<Vec3> f_air;      // air force per node, N (nodes)
  std::vector<Vec3> wind;       // wind velocity at each node, m/s (nodes)
  std::vector<Vec3> tri_force;  // (triangles)
  std::vector<Vec3> x_in, v_in, corr;  // (nodes)
  std::vector<std::uint8_t> hit;  // self-collision moved the node this sweep (nodes)
  std::vector<Vec3> tri_n;        // triangles' unit normals this sweep
  std::vector<Vec3> tri_n0;       // triangles' normals at the last pass, from x_prev (this pass)
  std::vector<double> tri_double_area;  // twice the triangles' areas this sweep, m²
  std::vector<Vec3> lo, hi;     // triangle boxes (triangles)
  BoxGrid grid;
};

// The sheet's data besides its mass-spring network: model, state and scratch.
struct Cloth : ClothModel, ClothState, ClothScratch {};

// Builds the sheet's nodes and springs (structural, shear, bend: in that order) and its cloth
// data. Node masses are lumped by area: corners ¼, edges ½, interior 1 cell each.
MassSpringDesc buildCloth(const ClothDesc& d, std::uint64_t seed, Cloth& c);

// Air forces per node from the drawn triangles (viscous normal force, quadratic drag and lift),
// each triangle in the mean of the wind at its corners.
void airForces(Cloth& c, const Wind& wind, double t, const std::vector<Vec3>& x,
               const std::vector<Vec3>& v);

// Grips: sets the gripped nodes' velocity at time t (applied over the next step) and, after the
// step, places them exactly at origin + velocity·(time gripped so far).
// A grip held by an object follows its collider (its pose now, its surface's velocity).
void gripVelocities(const Cloth& c, double t, const std::vector<Collider>& colliders, std::vector<Vec3>& v);
void gripPositions(const Cloth& c, double t, const std::vector<Collider>& colliders, std::vector<Vec3>& x);
// What the cloth pulls on each object that holds a grip with, over the step h: handed to it.
void handBackGrips(const Cloth& c, const MassSpringModel& m, const MassSpringState& s, double h,
                   const std::vector<Collider>& colliders, Coupling& coupling);

// Provot 1995, "Deformation constraints in a mass-spring model to describe rigid cloth
// behavior": structural and shear springs stretched beyond (1 + limit)·l are shortened by
// moving their ends (Jacobi sweeps, deterministic); velocities follow the moved positions.
void limitStrain(Cloth& c, const MassSpringModel& m, double h, std::vector<Vec3>& x,
                 std::vector<Vec3>& v);

// Self-collision: every free node kept at least 2·thickness from the drawn triangles that do
// not contain it, on the side it was on at the last pass (x_prev); its velocity relative to the
// triangle loses its approaching normal part. Candidates from a BoxGrid. A pass runs when some
// node has moved a quarter of the gap since the last one (so no node can cross the gap
// between passes), which at cloth step sizes is every few steps rather than every step.
void selfCollide(Cloth& c, const MassSpringModel& m, std::vector<Vec3>& x, std::vector<Vec3>& v);

// Terzopoulos & Fleischer 1988: the threads (structural springs) strained past their threshold
// break; a shear spring goes with its cell when one of the cell's four threads has broken, and
// a bend spring with either thread it spans. Rebuilds the incidence and marks the triangles
// that lost a thread: those open the tear. Returns how many springs went.
int tearSprings(Cloth& c, MassSpringModel& m, const std::vector<Vec3>& x);
// Marks the triangles that still have both threads (after `intact` changed).
void refreshTriangles(Cloth& c);

// The drawn sheet: intact triangles; a node is split into one vertex per fan of triangles still
// joined through intact edges (torn edges get their own vertices), each with its own smooth
// normal and the node's UV.
TriMesh clothMesh(const Cloth& c, const std::vector<Vec3>& x);

// --- wetness (cloth_wet.cpp): an absorbent sheet's liquid ----------------------------------
// Wicking and drainage over one step h: liquid spreads between structurally joined nodes towards
// the drier one (kWickRate, on wetness relative to capacity), and what a node holds beyond its
// capacity runs to its lowest neighbour below it (kDrainRate). Each move of mass dm from node i
// to j carries its momentum dm·v_i, so the sheet's momentum is unchanged.
inline constexpr double kWickRate = 4.0;    // 1/s
inline constexpr double kDrainRate = 12.0;  // 1/s
void spreadWetness(Cloth& c, MassSpringModel& m, const std::vector<Vec3>& x, std::vector<Vec3>& v,
                   const Vec3& gravity, double h);
// Node i takes or loses liquid mass dm (kg) moving at velocity u: its mass becomes dry + wet and
// its velocity vi the mass-weighted mean (a fixed node keeps its own).
void wetNode(Cloth& c, MassSpringModel& m, Vec3& vi, std::size_t i, double dm, const Vec3& u);

// The force the pinned and gripped nodes hold the sheet with (their reaction: minus the springs,
// weight and liquid acting on them), N; at rest it balances the weight of sheet and liquid.
Vec3 supportForce(const Cloth& c, const MassSpringModel& m, const MassSpringState& s);

// Connected pieces of the sheet (union of nodes over intact springs).
int clothPieces(std::size_t nodes, const Springs& s);

}  // namespace reel
