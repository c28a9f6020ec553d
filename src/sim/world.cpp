#include "sim/world.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <exception>
#include <cmath>
#include <map>

#include "core/format.h"
#include "core/parallel.h"
#include "core/profile.h"
#include "core/random.h"
#include "sim/object_draw.h"

namespace reel {
namespace {

// Mesh colliders find points up to their thickness plus the largest contact radius of any body,
// plus, for a surface with adhesion, the largest adhesion range (a liquid's cutoff).
void bodyReach(const SceneDesc& scene, double& radius, double& adhesion_range) {
  radius = adhesion_range = 0.0;
  for (const BodyDesc& bd : scene.bodies) {
    radius = std::max(radius, bd.params->contactRadius(bd.node_radius));
    adhesion_range = std::max(adhesion_range, bd.params->adhesionRange());
  }
}

// What a camera frames of a body: the centre of its nodes, particles or parts and the radius that
// holds 95% of them (a few drops flung away do not pull the picture wide), at least 0.25 m (a
// single rigid part is a point here). False for a body with nothing to show.
bool bodyExtent(const Body& b, Vec3& centre, double& radius) {
  BodyView v;
  if (!b.view(v) || v.positions.empty()) return false;
  centre = Vec3::Zero();
  for (const Vec3& p : v.positions) centre += p;
  centre /= static_cast<double>(v.positions.size());
  std::vector<double> d2(v.positions.size());
  for (std::size_t i = 0; i < d2.size(); ++i) d2[i] = (v.positions[i] - centre).squaredNorm();
  const std::size_t k = (d2.size() * 95 + 99) / 100 - 1;  // the smallest count holding 95%, as an index
  std::nth_element(d2.begin(), d2.begin() + static_cast<std::ptrdiff_t>(k), d2.end());
  radius = std::max(0.25, std::sqrt(d2[k]));
  return true;
}

}  // namespace

Result<World> World::create(const SceneDesc& scene, std::span<const BodyKindRow> kinds,
                            std::span<const InteractionRow> interactions, bool check_only) {
  World w;
  w.integrator_ = scene.integrator;
  w.implicit_ = scene.implicit;
  w.fps_ = scene.fps;
  w.substeps_ = scene.substeps;
  double radius = 0.0, adhesion_range = 0.0;
  bodyReach(scene, radius, adhesion_range);
  const double h_max = 1.0 / (static_cast<double>(scene.fps) * scene.substeps);
  // A collider of each object, built once with its drawn mesh; then the objects bodies are
  // (rigid bodies), after the scene's.
  auto addObject = [&](const ObjectDesc& o) {
    // A moving mesh also reaches as far as its fastest key moves it in one step.
    double speed = 0.0;
    for (std::size_t k = 1; k < o.motion.size(); ++k)
      speed = std::max(speed, (o.motion[k].position - o.motion[k - 1].position).norm() / (o.motion[k].time - o.motion[k - 1].time));
    if (!o.motion.empty()) w.moving_objects_.push_back(w.colliders_.size());
    if (!o.motion.empty() || o.free_body) w.posed_objects_.push_back(w.colliders_.size());
    bool sticky = o.surface.adhesion > 0;
    for (const auto& [name, sf] : o.species_surface) sticky = sticky || sf.adhesion > 0;
    // A 2 cm margin for a step's motion.
    w.colliders_.push_back(makeCollider(o, radius + (sticky ? adhesion_range : 0.0) + 0.02 + speed * h_max));
    w.object_meshes_.push_back(objectMesh(o));
    w.object_pivots_.push_back(o.referencePoint());
  };
  for (const ObjectDesc& o : scene.objects) addObject(o);
  std::vector<std::size_t> first_object;  // per body: its first own object's collider
  for (const BodyDesc& bd : scene.bodies) {
    first_object.push_back(w.colliders_.size());
    for (const ObjectDesc& o : bd.params->ownObjects()) addObject(o);
    w.own_objects_.push_back({first_object.back(), w.colliders_.size()});
  }
  w.wind_ = Wind(scene.wind, scene.seed);
  w.water_ = Water(scene.water);
  w.gravity_ = scene.gravity;
  if (Status st = w.buildBodies(scene, kinds, first_object, check_only); !st) return st.error();
  for (const InteractionRow& row : interactions)
    for (std::size_t a = 0; a < scene.bodies.size(); ++a)
      for (std::size_t b = 0; b < scene.bodies.size(); ++b)
        if (a != b && scene.bodies[a].type == row.first && scene.bodies[b].type == row.second)
          w.hooks_.push_back({a, b, row.make(*w.bodies_[a], *w.bodies_[b])});
  for (std::size_t k = 0; k < w.bodies_.size(); ++k) w.bodies_[k]->show(w.shown_, static_cast<int>(k));
  // Bodies that steer around the others (a school) see every body's points within their reach.
  for (const auto& b : w.bodies_) w.body_points_.reach = std::max(w.body_points_.reach, b->watchRadius());
  if (w.body_points_.reach > 0.0)
    for (std::size_t k = 0; k < w.bodies_.size(); ++k)
      if (w.bodies_[k]->exportsContacts()) w.watched_.push_back(k);
  // The contact layer takes every pair of bodies, the hooked ones by their hook's law.
  std::vector<HookedPair> hooked;
  for (const Hooked& hk : w.hooks_) hooked.push_back({hk.points, hk.surface, hk.hook.get()});
  w.contacts_.setup(w.bodies_, hooked, w.colliders_);
  w.coupling_.reset(w.colliders_.size());
  // A system per kind that has one and bodies in the scene, stepping them together.
  w.in_system_.assign(w.bodies_.size(), 0);
  w.step_time_.assign(w.bodies_.size(), 0.0);
  for (const BodyKindRow& row : kinds) {
    if (!row.system) continue;
    System sys;
    std::vector<Body*> members;
    for (std::size_t k = 0; k < scene.bodies.size(); ++k)
      if (scene.bodies[k].type == row.type) sys.members.push_back(k), members.push_back(w.bodies_[k].get());
    if (members.empty()) continue;
    for (std::size_t k : sys.members) w.in_system_[k] = 1;
    sys.solver = row.system();
    sys.solver->adopt(std::move(members));
    w.systems_.push_back(std::move(sys));
  }
  for (std::size_t k = 0; k < w.bodies_.size(); ++k)
    if (!w.in_system_[k] && w.bodies_[k]->coupled() && w.bodies_[k]->stepsAlone()) w.alone_.push_back(k);
  w.camera_desc_ = scene.camera.rig;
  for (std::size_t k = 0; k < w.bodies_.size(); ++k)
    if (w.camera_desc_.mode != CameraRigDesc::Mode::None && w.bodies_[k]->name() == w.camera_desc_.body)
      w.camera_body_ = static_cast<int>(k);
  w.advanceCamera();  // starts the rig on the body, when it has anything to frame yet
  return w;
}

// The followed body's centre and radius at the end of the frame, into the rig (started at rest
// on the body the first time it has any).
void World::advanceCamera() {
  if (camera_body_ < 0) return;
  Vec3 c;
  double r;
  if (!bodyExtent(*bodies_[static_cast<std::size_t>(camera_body_)], c, r)) return;
  if (!camera_.active) {
    camera_ = startRig(c, r);
    return;
  }
  advanceRig(camera_, c, r, 1.0 / fps_, camera_desc_.lag);
}

// Each body from its kind's builder, drawing random numbers from its own stream of the scene
// seed. A step above a body's stable bound is subdivided under auto_substeps; otherwise it is an
// error naming what sets the bound and what else would do. All errors are reported at once.
Status World::buildBodies(const SceneDesc& scene, std::span<const BodyKindRow> kinds,
                          const std::vector<std::size_t>& first_object, bool check_only) {
  const double h = 1.0 / (static_cast<double>(scene.fps) * scene.substeps);
  auto num = [](double x) { return formatNumber(x, 3); };
  std::vector<std::string> errors;
  std::map<std::uint64_t, std::uint64_t> ordinal;  // bodies so far per seed stream
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    const BodyDesc& bd = scene.bodies[i];
    const auto row = std::find_if(kinds.begin(), kinds.end(), [&](const BodyKindRow& k) { return bd.type == k.type; });
    REEL_CHECK(row != kinds.end(), "no builder for body type " + bd.type);
    BuildContext ctx;
    ctx.scene = &scene;
    ctx.colliders = &colliders_;
    ctx.first_object = first_object[i];
    ctx.seed = splitmix64(scene.seed ^ (row->seed_stream << 32) ^ ordinal[row->seed_stream]++);
    auto made = row->build(bd, ctx);
    if (!made.ok()) {
      for (const std::string& m : made.error().messages) errors.push_back(m);
      continue;
    }
    const StepLimit lim = made.value()->stepLimit(scene.integrator);
    const StepBound& bound = lim.bound;
    if (h > bound.h_max) {
      const double need = std::ceil(h / (0.9 * bound.h_max));
      if (scene.auto_substeps && need * scene.substeps <= kMaxStepsPerFrame) {
        subdivision_ = std::max(subdivision_, static_cast<int>(need));
      } else {
        // The advice offers only what can work: no auto_substeps when it is on already or when
        // the steps it would take pass the cap.
        const double min_sub = std::ceil(1.0 / (scene.fps * 0.9 * bound.h_max));
        const std::string advice =
            min_sub > kMaxStepsPerFrame
                ? "that takes " + num(min_sub) + " steps a frame, more than the limit of " + num(kMaxStepsPerFrame) + "; use " + lim.instead
                : "use \"substeps\": " + num(min_sub) + " or more" + (scene.auto_substeps ? "" : ", \"auto_substeps\": true,") +
                      " or " + lim.instead;
        errors.push_back(scene.file + ": /substeps: step h = 1/(fps·substeps) = " + num(h) +
                         " s is above the stability bound " + num(bound.h_max) + " s " + lim.what + ": ω ≈ " +
                         num(bound.omega) + " rad/s, β ≈ " + num(bound.beta) + " 1/s); " + advice);
      }
    }
    bodies_.push_back(std::move(made.value()));
  }
  if (!errors.empty()) return Error(ErrorKind::BadInput, std::move(errors));
  if (!check_only)
    for (auto& b : bodies_) b->prepare();
  return {};
}

// The watched bodies' points as the contact layer would take them, in a grid of cells as large as
// the watchers' reach and the largest radius: the points within reach of a place lie in the 27
// cells around it.
void World::gatherBodyPoints() {
  ContactProxies& p = watch_proxies_;
  p.clear();
  for (std::size_t k : watched_) p.add(*bodies_[k], k);
  BodyPoints& b = body_points_;
  b.x.swap(p.x);
  b.r.swap(p.r);
  double rmax = 0.0;
  for (double r : b.r) rmax = std::max(rmax, r);
  b.grid.build(b.x, b.x, b.reach + rmax);
}

// Whether two bodies that step alone may meet this step: the spheres around their own objects,
// grown by 0.25 m and by how far each moved over its last step, overlap.
bool World::aloneNear() const {
  if (alone_.size() < 2) return false;
  std::vector<Vec3> lo, hi;
  for (std::size_t k : alone_) {
    Vec3 a = Vec3::Constant(1e300), b = Vec3::Constant(-1e300);
    for (std::size_t c = own_objects_[k][0]; c < own_objects_[k][1]; ++c) {
      const Collider& col = colliders_[c];
      const Vec3 centre0 = col.fromAuthored(col.shape->bound_center);
      const double moved = col.velocityAt(centre0).norm() * col.pose.dt + col.angularVelocity().norm() * col.pose.dt * col.shape->bound_radius;
      const double r = col.shape->bound_radius + 0.25 + (std::isfinite(moved) ? moved : 1e300);
      if (!(r < 1e300)) return true;
      a = a.cwiseMin(centre0 - Vec3::Constant(r));
      b = b.cwiseMax(centre0 + Vec3::Constant(r));
    }
    lo.push_back(a);
    hi.push_back(b);
  }
  for (std::size_t i = 0; i < lo.size(); ++i)
    for (std::size_t j = i + 1; j < lo.size(); ++j)
      if ((lo[i].array() <= hi[j].array()).all() && (lo[j].array() <= hi[i].array()).all()) return true;
  return false;
}

// The coupled bodies that step alone (articulated figures: each reads the objects and the others'
// last step, and writes only its own state). Apart, all together in parallel, each then
// publishing its new state in order. When two may meet, one after another in scene order, each
// publishing before the next steps: the first meets the later ones' links and hands them the
// opposite (Coupling), which they take in the same step, leaving those contacts to it.
Status World::stepAlone(StepContext& ctx) {
  if (aloneNear()) {
    solved_.assign(colliders_.size(), 0);
    ctx.solved = &solved_;
    for (std::size_t k : alone_) {
      bodies_[k]->step(ctx);
      bodies_[k]->publish(ctx);
      for (std::size_t c = own_objects_[k][0]; c < own_objects_[k][1]; ++c) solved_[c] = 1;
    }
    ctx.solved = nullptr;
  } else {
    // (each is tens of microseconds of work: two are worth a parallel region)
    const auto n = static_cast<std::ptrdiff_t>(alone_.size());
    parallelBlocks(
        n, 1, [&](std::ptrdiff_t i0, std::ptrdiff_t) { bodies_[alone_[static_cast<std::size_t>(i0)]]->step(ctx); },
        n > 1 ? n * parallelMin() : 0);
    for (std::size_t k : alone_) bodies_[k]->publish(ctx);
  }
  for (std::size_t k : alone_)
    if (Status st = bodies_[k]->checkState(ctx); !st) return st;
  return {};
}

// Bodies of this many elements or more step over all threads on their own (their loops keep the
// cores busy); smaller ones may step side by side, each on one thread.
constexpr std::ptrdiff_t kTogetherMax = 16384;

// The run of bodies in together_, each touching only its own state (Body::togetherWork). A body
// that is large, or whose last step took more than its share of the run's (its time times the
// threads above the run's total: side by side it would leave the other threads idle, a poured
// stream that rebuilds its neighbour lists every step beside sheets that do little), steps first
// over all threads; the rest then step side by side, each on one thread (its loops serial), the
// slowest first. Each writes its solver's statistics apart, taken in scene order afterwards as one
// after another would have left them, and is checked in scene order. The times choose only who
// runs where: what a body computes depends on no other body and on no thread count (DESIGN 6),
// so the bits are those of stepping them one after another, and so is the first error (a bad
// state, or an exception a step threw).
Status World::stepTogether(StepContext& ctx) {
  profile::Scope stage(profile::Stage::Integration);  // (the side-by-side steps' own scopes are muted)
  using Clock = std::chrono::steady_clock;
  const std::size_t n = together_.size();
  together_stats_.assign(n, SolverStats{});
  for (SolverStats& s : together_stats_) s.last.cg_iterations = -1;  // (still −1 after: no solve)
  // (an exception may not leave a parallel region: each body's is kept, and the first in scene
  // order thrown where one after another would have met it, among the bodies' checks)
  std::vector<std::exception_ptr> thrown(n);
  auto stepOn = [&](std::size_t i) {
    StepContext own = ctx;
    own.solver = &together_stats_[i];
    const std::size_t k = together_[i];
    const Clock::time_point t0 = Clock::now();
    try {
      bodies_[k]->step(own);
    } catch (...) {
      thrown[i] = std::current_exception();
    }
    step_time_[k] = std::chrono::duration<double>(Clock::now() - t0).count();
  };
  const double threads = threadCount();
  std::vector<std::size_t> side;  // slots of the small bodies, the slowest first
  double total = 0.0;             // their last steps' time, s
  for (std::size_t i = 0; i < n; ++i) {
    const Body& b = *bodies_[together_[i]];
    if (b.togetherWork() >= kTogetherMax) {
      const ParallelScope all(b.parallelWork());
      stepOn(i);
    } else {
      side.push_back(i);
      total += step_time_[together_[i]];
    }
  }
  std::stable_sort(side.begin(), side.end(),
                   [&](std::size_t a, std::size_t b) { return step_time_[together_[a]] > step_time_[together_[b]]; });
  // The slowest over all threads while it would hold up the rest (and a last one alone).
  std::size_t first = 0;
  for (; first < side.size(); ++first) {
    const double t = step_time_[together_[side[first]]];
    if (side.size() - first >= 2 && !(t * threads > total)) break;
    total -= t;
    const ParallelScope all(bodies_[together_[side[first]]]->parallelWork());
    stepOn(side[first]);
  }
  const auto m = static_cast<std::ptrdiff_t>(side.size() - first);
  side_by_side_ += m;
#pragma omp parallel for schedule(dynamic, 1) if (m >= 2)
  for (std::ptrdiff_t q = 0; q < m; ++q) {
    const profile::Mute mute;
    const ParallelScope one(0);
    stepOn(side[first + static_cast<std::size_t>(q)]);
  }
  for (std::size_t i = 0; i < n; ++i) {
    const SolverStats& s = together_stats_[i];
    if (s.last.cg_iterations >= 0) solver_.last = s.last;
    solver_.unconverged += s.unconverged;
    solver_.worst_residual = std::max(solver_.worst_residual, s.worst_residual);
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (thrown[i]) std::rethrow_exception(thrown[i]);
    if (Status st = bodies_[together_[i]]->checkState(ctx); !st) return st;
  }
  return {};
}

Status World::advanceFrame() {
  const int steps = stepsPerFrame();
  const double per_step = 1.0 / (static_cast<double>(fps_) * steps);
  StepContext ctx;
  ctx.h = stepSize();
  ctx.frame = frame_ + 1;
  ctx.integrator = integrator_;
  ctx.implicit = &implicit_;
  ctx.gravity = gravity_;
  ctx.wind = &wind_;
  ctx.water = &water_;
  ctx.colliders = &colliders_;
  ctx.coupling = &coupling_;
  ctx.solver = &solver_;
  ctx.shown = &shown_;
  shown_.points = watched_.empty() ? nullptr : &body_points_;  // (this World's, wherever it was moved)
  for (int s = 0; s < steps; ++s) {
    ctx.t0 = static_cast<double>(step_) * per_step;
    ++step_;
    ctx.t1 = static_cast<double>(step_) * per_step;
    // Moving objects take their pose at the end of the step; contacts see their velocity.
    for (std::size_t o : moving_objects_) colliders_[o].moveTo(ctx.t1, ctx.h);
    coupling_.reset(colliders_.size());
    if (!watched_.empty()) gatherBodyPoints();
    // The bodies, in scene order, each checked for a bad state; a run of two or more that may step
    // side by side (Body::togetherWork; the coupled and the systems' bodies, which step later, do
    // not break a run) steps together.
    for (std::size_t k = 0; k < bodies_.size();) {
      Body* b = bodies_[k].get();
      if (b->coupled() || in_system_[k]) {
        ++k;
        continue;
      }
      together_.clear();
      std::size_t end = k;
      for (; end < bodies_.size(); ++end) {
        if (bodies_[end]->coupled() || in_system_[end]) continue;
        if (bodies_[end]->togetherWork() < 0) break;
        together_.push_back(end);
      }
      if (together_.size() >= 2 && threadCount() > 1) {
        if (Status st = stepTogether(ctx); !st) return st;
        k = end;
        continue;
      }
      profile::Scope stage(profile::Stage::Integration);  // what the body's own scopes do not claim
      const ParallelScope threads(b->parallelWork());
      b->step(ctx);
      if (Status st = b->checkState(ctx); !st) return st;
      ++k;
    }
    // The coupling stage: the contact layer, every body's points and triangles against every
    // other's (the hooked pairs by their own law, which then ends its step); then the free objects
    // take what the bodies handed them, in order.
    profile::Scope coupling(profile::Stage::Coupling);
    if (contacts_.active()) {
      contacts_.step(bodies_, ctx.h, colliders_, coupling_);
      for (std::size_t k : contacts_.touchedBodies())
        if (Status st = bodies_[k]->checkState(ctx); !st) return st;
    }
    for (const Hooked& hk : hooks_) {
      hk.hook->end(ctx);
      for (std::size_t k : {hk.points, hk.surface})
        if (Status st = bodies_[k]->checkState(ctx); !st) return st;
    }
    // The coupled bodies that step alone first (stepAlone: figures); then the other coupled
    // bodies, and the systems (the rigid bodies, which take what the figures handed them).
    if (!alone_.empty())
      if (Status st = stepAlone(ctx); !st) return st;
    for (std::size_t k = 0; k < bodies_.size(); ++k) {
      Body* b = bodies_[k].get();
      if (!b->coupled() || b->stepsAlone() || in_system_[k]) continue;
      b->step(ctx);
      if (Status st = b->checkState(ctx); !st) return st;
    }
    for (System& sys : systems_) {
      sys.solver->step(ctx);
      for (std::size_t k : sys.members)
        if (Status st = bodies_[k]->checkState(ctx); !st) return st;
    }
  }
  ++frame_;
  advanceCamera();
  return {};
}

void World::view(FrameView& out) const {
  out.frame = frame_;
  out.time = time();
  out.bodies.clear();
  for (const auto& b : bodies_) {
    BodyView v;
    if (b->view(v)) out.bodies.push_back(std::move(v));
  }
}

void World::draw(DrawList& out) const {
  profile::Scope stage(profile::Stage::DrawList);
  out.clearGeometry();
  out.frame_time = 1.0 / static_cast<double>(fps_);
  out.meshes = object_meshes_;
  // Moving objects: their authored mesh carried to the current pose.
  for (std::size_t o : posed_objects_) {
    const Collider& c = colliders_[o];
    TriMesh m = *object_meshes_[o].mesh;
    const Vec3 shift = c.pose.pos - c.pose.rot * object_pivots_[o];
    m.transform(c.pose.rot, shift);
    out.meshes[o].mesh = std::make_shared<const TriMesh>(std::move(m));
    out.meshes[o].per_frame = true;
  }
  for (std::size_t k = 0; k < bodies_.size(); ++k) {
    const std::array<std::size_t, 4> from{out.meshes.size(), out.spheres.size(), out.tubes.size(), out.instances.size()};
    bodies_[k]->draw(out);
    const int source = static_cast<int>(k);
    for (std::size_t i = from[0]; i < out.meshes.size(); ++i) out.meshes[i].source = source;
    for (std::size_t i = from[1]; i < out.spheres.size(); ++i) out.spheres[i].source = source;
    for (std::size_t i = from[2]; i < out.tubes.size(); ++i) out.tubes[i].source = source;
    for (std::size_t i = from[3]; i < out.instances.size(); ++i) out.instances[i].source = source;
  }
}

std::uint64_t World::stateHash() const {
  Hasher h;
  for (const auto& b : bodies_) b->hash(h);
  return h.h;
}

WorldSnapshot World::snapshot() const {
  WorldSnapshot s;
  s.frame = frame_;
  s.step = step_;
  for (const Collider& c : colliders_)
    s.colliders.push_back(c.pose);
  s.bodies.resize(bodies_.size());
  for (std::size_t k = 0; k < bodies_.size(); ++k) bodies_[k]->snapshot(s.bodies[k]);
  s.systems.resize(systems_.size());
  for (std::size_t k = 0; k < systems_.size(); ++k) systems_[k].solver->snapshot(s.systems[k]);
  s.solver = solver_;
  s.camera = camera_;
  return s;
}

Status World::restore(const WorldSnapshot& s) {
  if (s.colliders.size() != colliders_.size() || s.bodies.size() != bodies_.size() || s.systems.size() != systems_.size())
    return Error(ErrorKind::BadInput, "snapshot of another scene: " + std::to_string(s.bodies.size()) + " bodies and " +
                                          std::to_string(s.colliders.size()) + " objects, this scene has " +
                                          std::to_string(bodies_.size()) + " and " + std::to_string(colliders_.size()));
  if (s.frame < 0 || s.step != static_cast<long long>(s.frame) * stepsPerFrame())
    return Error(ErrorKind::BadInput, "snapshot of another scene: frame " + std::to_string(s.frame) + " at step " +
                                          std::to_string(s.step) + ", this scene takes " +
                                          std::to_string(stepsPerFrame()) + " steps a frame");
  // All or nothing: a body that refuses its part leaves the world as it was.
  const WorldSnapshot before = snapshot();
  for (std::size_t k = 0; k < bodies_.size(); ++k)
    if (!bodies_[k]->restore(s.bodies[k])) {
      for (std::size_t j = 0; j <= k; ++j) REEL_CHECK(bodies_[j]->restore(before.bodies[j]), "a body refused its own snapshot");
      return Error(ErrorKind::BadInput, "snapshot of another scene: body '" + bodies_[k]->name() + "' does not match");
    }
  for (std::size_t k = 0; k < systems_.size(); ++k)
    if (!systems_[k].solver->restore(s.systems[k])) {
      for (std::size_t j = 0; j < k; ++j) REEL_CHECK(systems_[j].solver->restore(before.systems[j]), "a system refused its own snapshot");
      for (std::size_t j = 0; j < bodies_.size(); ++j) REEL_CHECK(bodies_[j]->restore(before.bodies[j]), "a body refused its own snapshot");
      return Error(ErrorKind::BadInput, "snapshot of another scene: the state of the bodies solved together does not match");
    }
  for (std::size_t k = 0; k < colliders_.size(); ++k) {
    colliders_[k].pose = s.colliders[k];
  }
  frame_ = s.frame;
  step_ = s.step;
  solver_ = s.solver;
  camera_ = s.camera;
  return {};
}

}  // namespace reel
