// Body: every simulated thing behind one interface (DESIGN 2). A body kind lives in its own
// folder (sim/<kind>/), with its drawing in *_draw.cpp, and is known to the rest of reel through
// one row of the registry (app/body_kinds.cpp): its scene name, its reader, its builder.
//
// The World steps its bodies in a fixed order, each against the same context, and runs the
// coupling stage between kinds (see Coupling): so a run is the same for any thread count, and
// snapshot() and restore() of every body resume it bit for bit from any frame.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "core/drawlist.h"
#include "core/error.h"
#include "core/hash.h"
#include "core/scene.h"
#include "core/frame_view.h"
#include "core/state_blob.h"
#include "core/types.h"
#include "sim/collide.h"
#include "sim/integrators.h"
#include "sim/stability.h"

namespace reel {

class Wind;
struct SharedView;
class Water;
class ContactExport;
class ContactHook;

// A state whose speed or distance from the origin passes these is a runaway (exit 3).
inline constexpr double kRunawaySpeed = 1e4;     // m/s
inline constexpr double kRunawayDistance = 1e6;  // m

// The implicit solves of a run: the last step's, and how many stopped short of their tolerance.
struct SolverStats {
  StepStats last;
  long long unconverged = 0;  // implicit steps whose CG solve stopped before its tolerance
  double worst_residual = 0.0;
};

// What a body's step sees: the step, the scene's fields and the objects.
struct StepContext {
  double h = 0.0;          // step length, s
  double t0 = 0.0, t1 = 0.0;  // the step runs from t0 to t1 = t0 + h, s
  int frame = 0;           // the frame this step leads to (messages)
  IntegratorKind integrator = IntegratorKind::SymplecticEuler;
  const ImplicitSettings* implicit = nullptr;
  Vec3 gravity{0, -9.78, 0};  // m/s²
  const Wind* wind = nullptr;
  const Water* water = nullptr;  // the fish kinds' water
  std::vector<Collider>* colliders = nullptr;  // at their pose at t1 (keyframed ones moved)
  Coupling* coupling = nullptr;
  SolverStats* solver = nullptr;
  // What the bodies show one another (sim/shared_view.h): a body that reacts to another (a school
  // fleeing a predator school, a fish seeing fish and food) reads it here. Bodies earlier in scene
  // order have already taken this step.
  const SharedView* shown = nullptr;
  // Per collider: its body has already stepped this step and met the others' parts itself (a
  // figure stepping before another whose reach it shares): a later body leaves those contacts to
  // it and takes what it handed back (Coupling). Null: none has.
  const std::vector<std::uint8_t>* solved = nullptr;
};


// What a builder sees: the scene, the colliders (built before any body) and the body's own
// stream of random numbers from the scene seed.
struct BuildContext {
  const SceneDesc* scene = nullptr;
  const std::vector<Collider>* colliders = nullptr;
  std::size_t first_object = 0;  // the collider of the body's first own object (BodyParams::ownObjects)
  std::uint64_t seed = 0;
};

// A body's explicit step bound and how to say what sets it (refusal messages).
struct StepLimit {
  StepBound bound;   // infinite h_max: none
  std::string what;  // e.g. "of fluid 'water' (species 'a' with 'b'"
  std::string instead;  // what else would do besides more substeps
};

class Body {
 public:
  explicit Body(std::string name) : name_(std::move(name)) {}
  virtual ~Body() = default;
  Body(const Body&) = delete;
  Body& operator=(const Body&) = delete;

  const std::string& name() const { return name_; }
  // The largest step an explicit method takes stably, and what to say when a scene's is above it.
  virtual StepLimit stepLimit(IntegratorKind integrator) const = 0;
  // What a run needs before its first frame and a check does not (a face settles under gravity):
  // done once the World has accepted every body's step (so a refusal comes first and fast), never
  // for `reel check`.
  virtual void prepare() {}
  // Free objects take what the other bodies handed them in the coupling stage (see Coupling).
  virtual bool coupled() const { return false; }
  // A coupled body whose step writes only its own state (its colliders and what it hands back wait
  // for publish): all of them step in parallel, each reading the others' colliders as they were
  // after the last step (articulated figures); when the reach of two may overlap, they step one
  // after another in scene order instead, each publishing before the next steps (StepContext::solved).
  virtual bool stepsAlone() const { return false; }
  // A body that steps alone shows the others its new state here (poses its colliders, hands back
  // impulses), after every body of its run has stepped, in order: so each read the others' last
  // step whatever the threads' timing.
  virtual void publish(StepContext& /*ctx*/) {}
  // Advances the body from ctx.t0 to ctx.t1.
  virtual void step(StepContext& ctx) = 0;
  // The elements its step's loops run over (a spring network's nodes), for one decision whether
  // they all run in parallel (core/parallel.h, ParallelScope); −1: each loop decides by its size.
  virtual std::ptrdiff_t parallelWork() const { return -1; }
  // A body whose step reads only the objects, the scene's fields and its own state, and writes
  // only its own state and its solver's statistics (no SharedView, no Coupling), returns the
  // elements its step works on (nodes, particles); −1 otherwise. The World steps such bodies that
  // are small side by side, each on one thread (World::stepTogether): a body of a few thousand
  // elements keeps two threads busy poorly on its own.
  virtual std::ptrdiff_t togetherWork() const { return -1; }
  // Adds to `out` what the body shows the others (sim/shared_view.h), as pointers to its own
  // published state; called once, when the World is built. `self`: its index in scene order.
  virtual void show(SharedView& /*out*/, int /*self*/) {}
  // How far (m) the body looks for other bodies' points to steer around (SharedView::points);
  // 0: it does not (then the World gathers none).
  virtual double watchRadius() const { return 0.0; }
  // The World's contact layer (sim/contact_layer.h): a body that has points hands them (and the
  // triangles of its surface over them) each step after stepping, and takes back their positions
  // and velocities once the layer has resolved its contacts with every other body's.
  virtual bool exportsContacts() const { return false; }
  // Whether pieces of the body meet each other (the fish of one body); else it never meets itself.
  virtual bool meetsItself() const { return false; }
  virtual void exportContacts(ContactExport& /*out*/) const {}
  virtual void importContacts(std::span<const Vec3> /*x*/, std::span<const Vec3> /*v*/) {}
  // Takes out the points a contact hook gave to another body (`gone`: per point, after
  // importContacts; a drop a sheet soaked up). Only a body whose points a hook may take (a
  // liquid's) has any to drop.
  virtual void dropPoints(std::span<const std::uint8_t> /*gone*/) {}
  // A body moved by a system (rigid bodies, figures) hands the layer its convex parts
  // (ContactExport::convex) at their pose and velocity before its system steps; what the layer's
  // contacts give them comes back through the World's Coupling, which the system reads.
  virtual bool exportsConvex() const { return false; }
  virtual void exportConvex(ContactExport& /*out*/) const {}
  // The colliders that hold some of its points (a cloth's grips): the layer leaves its surface and
  // the convex parts of the body that holds it apart (a cape does not push its wearer; its nodes
  // still meet the wearer's links as colliders).
  virtual void heldBy(std::vector<std::size_t>& /*colliders*/) const {}
  // Exit-3 check after a step: a non-finite or runaway state names body, point and quantity.
  virtual Status checkState(const StepContext& ctx) const = 0;
  // The state a dump shows (positions, velocities, springs, species); false: nothing to show.
  virtual bool view(BodyView& out) const = 0;
  // The complete state, enough to resume bit for bit (restore into a body built from the same
  // scene); restore returns false when the blob is not this body's.
  virtual void snapshot(StateBlob& out) const = 0;
  virtual bool restore(const StateBlob& in) = 0;
  // Adds the state that determinism checks compare (positions, velocities) to h.
  virtual void hash(Hasher& h) const = 0;
  // What the renderer gets of it (its *_draw.cpp).
  virtual void draw(DrawList& out) const = 0;
  // Quantities that describe the state (order parameters), each frame; none by default.
  virtual void statistics(std::vector<Statistic>& /*out*/) const {}
  // Lines `reel check` prints about it (what its parameters mean in practice); `h`: the step.
  virtual std::vector<std::string> notes(double /*h*/) const { return {}; }

 private:
  std::string name_;
};

// The exit-3 check of a body made of points (nodes, particles): `what` names a point ("node").
Status checkPoints(const StepContext& ctx, const std::string& body, const char* what, const std::vector<Vec3>& x,
                   const std::vector<Vec3>& v, const StepBound& bound);

// Whether every point lies within `limit` of the origin (NaN does not): a restored state must be
// one that could have passed the state check (kRunawayDistance for positions, kRunawaySpeed for
// velocities).
inline bool allWithin(const std::vector<Vec3>& x, double limit) {
  for (const Vec3& p : x)
    if (!(p.squaredNorm() <= limit * limit)) return false;
  return true;
}

// A builder: makes a body of its kind from its description (BadInput when it cannot be built).
using BodyBuilder = Result<std::unique_ptr<Body>> (*)(const BodyDesc& desc, const BuildContext& ctx);

// A system the World owns that solves every body of one kind together (the rigid bodies: one
// joint contact solve over all of them). No body steps another: the World hands the system its
// members, in scene order, and the system keeps what belongs to all of them (a solver's
// warm-start cache) in its own snapshot.
class BodySystem {
 public:
  virtual ~BodySystem() = default;
  // Called once, before the first step: the members, in scene order (they outlive the system).
  virtual void adopt(std::vector<Body*> members) = 0;
  // Advances every member from ctx.t0 to ctx.t1 (in the coupling stage: after the bodies that
  // push them, and the figures).
  virtual void step(StepContext& ctx) = 0;
  virtual void snapshot(StateBlob& out) const = 0;
  virtual bool restore(const StateBlob& in) = 0;
};
using SystemBuilder = std::unique_ptr<BodySystem> (*)();

// A body kind as the World sees it: its scene name, its builder, and the stream tag of the seed
// from which its bodies draw their random numbers (a body's stream: the tag and how many bodies
// with that tag come before it in the scene).
// `system`: the builder of the system that steps the kind's bodies together, or nullptr when
// each body steps itself.
struct BodyKindRow {
  const char* type;
  BodyBuilder build;
  std::uint64_t seed_stream;
  SystemBuilder system = nullptr;
};

// A law of its own for the contacts of the points of a body of kind `first` with the triangles
// of one of kind `second` (a liquid on a sheet): `make` builds the contact layer's hook
// (sim/contact_layer.h) for every such pair of bodies, rows in order, pairs in scene order.
struct InteractionRow {
  const char* first;
  const char* second;
  std::unique_ptr<ContactHook> (*make)(Body& first, Body& second);
};

}  // namespace reel
