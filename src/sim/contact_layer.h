// The World's contact layer (DESIGN 2, "one world"): every body that has points hands them to
// the layer each step as contact proxies in flat arrays (position, velocity, inverse mass,
// radius), with the triangles of its surface over them; one broad phase runs over all of them,
// and the narrow phase is keyed by the pair of proxy types, never by the pair of kinds:
//   point–triangle: a node or particle against a sheet, a fish's skin, a lattice's skin;
//   point–convex: a node or particle (a sphere of its radius) against a convex part moved by a
//   system (a rigid body, a figure's link), with the part's surface law (restitution, friction,
//   a liquid's adhesion, per species where the scene says so);
//   point–point: two nodes or particles as spheres;
//   edge–edge: two threads (a rope's segments, a net's threads, a kelp stalk) as capsules;
//   triangle–convex: a sheet's, a fish's or a lattice's surface against a convex part (a rigid
//   body, a figure's link, whose impulse the World's Coupling carries to the system that moves
//   it in the same step; or a scene object's sphere, box, capsule, container wall or mesh
//   triangle thinner than the surface's longest edge, which nothing moves).
// A pair of bodies may have a law of its own for its point–triangle contacts (a liquid and a
// sheet: porosity, soaking up, adhesion): a ContactHook, which takes the pairs the layer found.
// Impulses are equal and opposite (a point's against the triangle's corners by the barycentric
// weights of the contact), applied in the same step, pairs processed in id order: momentum is
// kept to rounding and a run is bit-identical for any thread count. The layer keeps no state
// between steps: where a point was at the start of the step is x − h·v, or where its body says
// it was (ContactExport::starts).
//
// A kind that exports points and triangles (Body::exportContacts, Body::importContacts) needs no
// contact code of its own: it touches every other kind that does.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "core/scene/material.h"
#include "core/types.h"
#include "sim/grid.h"
#include "sim/rigid/contact.h"

namespace reel {

class Body;
struct StepContext;
struct Collider;
struct Coupling;
struct ObjectParts;

// Coulomb friction between two bodies' proxies, the same for every pair.
inline constexpr double kContactFriction = 0.3;

// The proxies of one step, flat arrays addressed by ids: a body's points are a contiguous range,
// bodies in scene order, so ids are stable for as long as the bodies keep their point counts.
struct ContactProxies {
  std::vector<Vec3> x, v;                 // positions, m; velocities, m/s (points)
  std::vector<Vec3> x0;                   // positions at the start of the step (the body's, or x − h·v), m (points)
  std::vector<std::uint8_t> x0_given;     // its body handed where its points started (slots)
  std::vector<double> w;                  // inverse masses, 1/kg; 0 for a held point (points)
  std::vector<double> r;                  // contact radii, m (points)
  std::vector<std::uint32_t> piece;       // points of one piece never meet each other (points)
  std::vector<std::uint32_t> slot;        // the exporting body's slot (points)
  std::vector<std::array<std::uint32_t, 3>> tri;  // point ids, counter-clockwise from outside (triangles)
  std::vector<std::array<std::uint32_t, 2>> edge;  // point ids of a thread's ends (edges)
  std::vector<std::uint8_t> gone;         // taken by another body in the step (a drop soaked up), out of its contacts (points)
  std::vector<std::int32_t> material;     // the row of its body's surface table it meets parts by; -1: the part's own (points)
  // A convex part of a body moved by a system (a rigid body, a figure's link): its shape at its
  // pose now, its velocity, how it answers an impulse, and the collider whose Coupling entry
  // takes what it is given. v and w change as the layer's contacts act on it.
  // A scene object's part (a sphere, a box, a capsule, a container's wall, a mesh's triangle)
  // is one too, with inverse mass 0 and `body` kObject.
  struct Convex {
    const ConvexShape* shape = nullptr;
    Pose pose;                          // the shape's frame, m
    Vec3 v{0, 0, 0}, w{0, 0, 0};        // m/s at `centre`; rad/s, world
    double inv_mass = 0.0;              // 1/kg; 0: moved by keys, nothing moves it
    Mat3 inv_inertia = Mat3::Zero();    // world, 1/(kg·m²)
    std::size_t collider = 0;           // its collider (the World's Coupling entry)
    std::size_t body = 0;               // the exporting body's World index; kObject for an object
    Vec3 centre{0, 0, 0};               // a point inside it: a body's part's centre of mass (pose.p), m
  };
  static constexpr std::size_t kObject = ~std::size_t{0};
  std::vector<Convex> convex;  // (convex parts)
  // Per exporting body (slots): its World index, first point.
  std::vector<std::size_t> body;
  std::vector<std::uint32_t> first;       // (slots + 1)
  std::vector<std::uint32_t> tri_first;   // its first triangle (slots + 1)
  // Per slot: how its points meet convex parts when not by the part's own surface (a liquid's
  // species): surfaces per (collider, material), `materials` wide, and each material's adhesion
  // range, m. Empty: every point by the part's own surface.
  struct Surfaces {
    std::span<const Surface> table;
    int materials = 0;
    std::span<const double> range;
  };
  std::vector<Surfaces> surfaces;
  // The surface point i meets collider k by, and its adhesion range (m; 0 without adhesion).
  const Surface& surfaceOf(std::uint32_t i, std::size_t k, const Surface& own, double& range) const;
  void clear();
  // Appends body b's points and triangles (b is the World's body `index`; its pieces numbered
  // from `base_piece`) as the next slot; returns how many pieces it used.
  std::uint32_t add(const Body& b, std::size_t index, std::uint32_t base_piece = 0);
};

// What a body writes its proxies through (Body::exportContacts).
class ContactExport {
 public:
  explicit ContactExport(ContactProxies& p) : p_(p) {}
  // The body's points: positions (m), velocities (m/s), inverse masses (1/kg, 0: held), one
  // radius (m). `piece`: per point, which piece of the body it is (pieces of one body meet each
  // other: the fish of a school); empty: the body is one piece and never meets itself.
  void points(std::span<const Vec3> x, std::span<const Vec3> v, std::span<const double> inv_mass, double radius,
              std::span<const int> piece = {});
  // A triangle over the body's points (indices as handed to points()).
  void triangle(int a, int b, int c);
  // A thread between two of its points (a capsule of the points' radius).
  void edge(int a, int b);
  // Where the points were at the start of the step (after points()), for a body whose step is not
  // one straight move at its end velocity (a liquid that splits a violent step); without it the
  // layer takes x − h·v.
  void starts(std::span<const Vec3> x0);
  // How the points meet convex parts (after points()): `table[k · materials + m]` is the surface
  // a point of material m meets collider k by, `range[m]` its adhesion range (m), `material` each
  // point's row (-1: the collider's own surface). Without it: every point by the collider's own.
  void surfaces(std::span<const Surface> table, int materials, std::span<const double> range,
                std::span<const int> material);
  // A convex part (Body::exportConvex): `shape` in its frame, posed at `pose` (pose.p at the
  // centre of mass), moving at v (m/s) and w (rad/s), answering an impulse with inv_mass (1/kg)
  // and inv_inertia (world); the impulses it takes go to `collider`'s Coupling entry.
  void convex(const ConvexShape& shape, const Pose& pose, const Vec3& v, const Vec3& w, double inv_mass,
              const Mat3& inv_inertia, std::size_t collider);

 private:
  friend class ContactLayer;
  friend struct ContactProxies;
  ContactProxies& p_;
  std::uint32_t base_piece_ = 0;  // the body's first piece id
  std::uint32_t pieces_ = 1;      // pieces the body used
  std::size_t body_ = 0;          // the World index of the body exporting (convex parts)
};

// Counts of the last step (tests, statistics).
struct ContactCounts {
  std::size_t point_triangle = 0;  // pairs that touched
  std::size_t point_point = 0;
  std::size_t edge_edge = 0;
  std::size_t triangle_convex = 0;
  std::size_t point_convex = 0;
  std::size_t hooked = 0;  // points a hook's law touched
};

// A law of its own for the point–triangle contacts between the points of one body and the
// triangles of another (a liquid and a sheet: porosity, soaking up, adhesion; the registry's
// InteractionRow makes it). The layer's broad phase finds the pairs (the surface's triangles
// grown by margin()) and hands them to the hook after its own pairs, point by point in id order;
// the two bodies meet in no other way through the layer.
class ContactHook {
 public:
  virtual ~ContactHook() = default;
  // How far beyond the sum of the radii the law reaches (adhesion), m.
  virtual double margin() const = 0;
  // Before the step's first pair: the slots of the points' body and the surface's body in p.
  virtual void begin(const ContactProxies& p, std::uint32_t points, std::uint32_t surface, double h) = 0;
  // Point i against its candidate triangles (ascending ids). It may change the positions and
  // velocities in p of the point and of the triangles' corners (equal and opposite), and mark
  // the point gone (taken by the surface's body: Body::dropPoints takes it out after the step).
  // True when it changed anything.
  virtual bool point(ContactProxies& p, std::uint32_t i, std::span<const std::uint32_t> tris, double h) = 0;
  // After the layer's step, every step (also one without pairs): what the law does to the two
  // bodies beyond their points' motion (drips).
  virtual void end(const StepContext& ctx) = 0;
};

// A hook and the World indices of its points' body and surface's body.
struct HookedPair {
  std::size_t points = 0, surface = 0;
  ContactHook* hook = nullptr;
};

class ContactLayer {
 public:
  // Which bodies export proxies (Body::exportsContacts) and which pairs of them meet by a law of
  // their own (`hooks`, which outlive the layer's use of them). The scene objects (the static and
  // keyed colliders: not the free bodies') are convex parts the bodies' triangles meet. active()
  // is false when no two proxies could ever meet: then step() costs nothing.
  void setup(const std::vector<std::unique_ptr<Body>>& bodies, std::span<const HookedPair> hooks,
             const std::vector<Collider>& colliders);
  bool active() const { return active_ || objects_active_; }

  // Gathers every exporting body's proxies, finds the contacts over the step h, resolves them and
  // hands each touched body its new positions and velocities (Body::importContacts) and the points
  // a hook took from it (Body::dropPoints); what the convex parts took goes into `coupling` (per
  // collider; angular about the collider's pose.pos). The hooks' end() is the caller's.
  void step(const std::vector<std::unique_ptr<Body>>& bodies, double h, const std::vector<Collider>& colliders,
            Coupling& coupling);

  // The last step's contacts, and every step's since the World was made (not part of a snapshot).
  const ContactCounts& counts() const { return counts_; }
  const ContactCounts& total() const { return total_; }
  // The World indices of the bodies whose points the last step moved (they need a state check).
  const std::vector<std::size_t>& touchedBodies() const { return touched_bodies_; }
  const ContactProxies& proxies() const { return p_; }

 private:
  bool skipped(std::size_t a, std::size_t b) const;  // World indices of a hooked pair
  int hookOf(std::uint32_t point_slot, std::uint32_t surface_slot) const;  // index in hooks_, or -1
  bool meet(std::uint32_t i, std::uint32_t j) const;  // points of two pieces that may touch
  void findPointTriangle();
  void findPointPoint();
  void findEdgeEdge();
  void gatherObjectParts(const std::vector<Collider>& colliders);
  void findTriangleConvex(double h);
  bool solveTriangleConvex(std::uint32_t t, std::uint32_t c, double h);
  void findPointConvex(double h);
  bool solvePointConvex(std::uint32_t i, std::uint32_t c, double h, bool adhere);
  template <class F>
  void gatherPairs(std::size_t n, std::vector<std::array<std::uint32_t, 2>>& pairs, F&& candidates);
  bool solveEdgeEdge(std::uint32_t e, std::uint32_t f, double h);
  bool solvePointTriangle(std::uint32_t i, std::uint32_t t, double h);
  bool solvePointPoint(std::uint32_t i, std::uint32_t j, double h);
  // One contact between weighted points of each side (a point, a thread's two ends, a triangle's
  // three corners), n from side b towards side a.
  void apply(const std::uint32_t* ka, const double* ba, int na, const std::uint32_t* kb, const double* bb, int nb,
             const Vec3& n, double depth, double h);

  bool active_ = false;
  std::vector<std::size_t> exporters_;              // World indices, in order
  std::vector<std::size_t> convex_exporters_;       // World indices of the bodies with convex parts
  std::vector<std::array<std::size_t, 2>> held_;    // sorted (World index, collider): a body and what holds it
  std::vector<std::array<std::size_t, 2>> held_bodies_;  // sorted (World index, World index): a body and the body holding it
  std::vector<std::array<std::size_t, 2>> skip_;    // sorted pairs (a < b) of hooked bodies
  struct Hook {
    std::uint32_t points, surface;  // slots
    ContactHook* hook;
  };
  std::vector<Hook> hooks_;
  std::vector<std::int16_t> hook_of_;  // per (point slot, surface slot): index in hooks_, or -1
  std::vector<double> grow_;  // per slot: how far beyond the radii its triangles reach (hooks' margins), m
  // The scene objects as convex parts (built once, shared by copies of the World), and the
  // sorted (slot, collider) pairs the layer leaves apart: a body held at a point on or in an
  // object (a flag pinned to its pole), when the World was made or in the step, and an object no
  // thinner than the body's longest triangle edge (its nodes' contacts hold the body off it).
  std::shared_ptr<const ObjectParts> objects_;
  bool objects_active_ = false;  // some body's triangles may meet some object that is not a plane
  std::vector<std::uint32_t> object_near_;
  std::vector<std::array<std::size_t, 2>> held_at_start_, object_held_;
  const std::vector<Collider>* colliders_ = nullptr;  // the step's (objects' parts)
  // Adds to `out` the (slot, collider) pairs of p's held points with triangles on or within 1 cm
  // of the colliders `which`.
  static void objectHolds(const ContactProxies& p, const std::vector<Collider>& colliders,
                          const std::vector<std::size_t>& which, std::vector<std::array<std::size_t, 2>>& out);
  std::vector<std::uint8_t> touches_points_;  // per exporter: some other body may meet it
  std::vector<std::uint8_t> self_meet_;       // per exporter: its pieces meet each other
  ContactProxies p_;
  std::vector<std::uint8_t> touched_;  // per slot: some point moved
  std::vector<std::size_t> touched_bodies_;
  // Per piece: its box over the step (grown by its radii), its slot, and whether that box meets
  // the box of a piece it may touch (only those take part in the step's search).
  std::vector<Vec3> piece_lo_, piece_hi_;
  std::vector<std::uint32_t> piece_slot_;
  std::vector<std::uint8_t> near_;  // kPlain | kHooked
  static constexpr std::uint8_t kPlain = 1, kHooked = 2;
  std::vector<std::uint32_t> big_;  // pieces too large for the pieces' grid
  bool nearPieces(std::uint32_t pieces);
  bool near(std::size_t point) const { return near_[p_.piece[point]] != 0; }
  // Near a piece it meets by the layer's own law (point–point, edge–edge).
  bool nearPlain(std::size_t point) const { return (near_[p_.piece[point]] & kPlain) != 0; }
  // Broad phase scratch.
  BoxGrid tri_grid_, point_grid_;
  std::vector<Vec3> lo_, hi_;
  std::vector<std::vector<std::array<std::uint32_t, 2>>> chunk_pairs_;
  std::vector<std::array<std::uint32_t, 2>> pt_pairs_, pp_pairs_, ee_pairs_;  // (point, triangle), (point, point), (edge, edge)
  std::vector<std::array<std::uint32_t, 2>> tc_pairs_;  // (triangle, convex part)
  std::vector<std::array<std::uint32_t, 2>> pc_pairs_;  // (point, convex part)
  std::vector<std::uint32_t> pc_parts_;                 // the parts points meet (those moved by a system)
  std::vector<Vec3> pc_lo_, pc_hi_;                     // their boxes over the step, grown by the reach
  std::vector<std::vector<std::uint32_t>> pc_slot_parts_;  // per slot: the parts its points' box meets (scratch)
  std::vector<std::array<std::uint32_t, 3>> hk_pairs_;  // (point, triangle, hook): a hook's
  std::vector<std::uint32_t> hk_tris_;                  // (scratch)
  std::vector<Vec3> slot_lo_, slot_hi_;                 // per slot: its triangles' grown boxes together
  struct TriangleConvexScratch {  // findTriangleConvex's, kept between steps
    std::vector<Vec3> clo, chi, slot_lo, slot_hi, blo, bhi, llo, lhi;
    std::vector<std::uint8_t> slot_near;
    std::vector<std::uint32_t> live, blocks;
    std::vector<double> extent;
  } tc_;
  std::vector<Vec3> convex_J_, convex_L_;  // per convex part: impulse this step (N·s), its moment about the centre of mass
  ContactCounts counts_, total_;
};

}  // namespace reel
