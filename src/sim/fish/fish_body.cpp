#include "sim/fish/fish_body.h"

#include <algorithm>
#include <cmath>

#include "core/format.h"
#include "core/math.h"
#include "core/parallel.h"
#include "core/patterns.h"
#include "core/random.h"
#include "sim/contact_layer.h"
#include "sim/water.h"

namespace reel {
namespace {

using Index = std::ptrdiff_t;
constexpr std::uint64_t kStartStream = 0xF150;
constexpr double kMeal = 0.35;  // hunger a particle of food takes away

// The pectoral fins sit at ring 2's sides (nodes 5, 8 on the left; 6, 7 on the right), each of
// this area in lengths².
constexpr double kFinArea = 0.04;

// Streamlining: the forward part of the normal of a face that looks ahead is scaled by this. A
// streamlined body's flow stays attached and its pressure recovers behind the widest girth, so
// its pressure drag is a small part of what its front faces would feel as plates (Hoerner 1965,
// "Fluid-Dynamic Drag", ch. 6); eq. (3) per face leaves the recovery out, and with it a fish
// swam 0.42–0.47 lengths a beat. Faces looking 60° or less off ahead take the whole scaling
// (their drag along the axis 0.35² of the plate's), faces across the flow none, smoothly
// between, and every face keeps its push across the flow. A fish's steady stride is then
// 0.64–0.70 lengths a beat from 0.5 to 4 beats a second (0.3 m and 1 m), inside the 0.6–0.8
// that fish keep (Bainbridge 1958; Videler 1993, "Fish Swimming", ch. 8).
// docs/fish.md has the plot.
constexpr double kFrontDrag = 0.35;

}  // namespace

FishBody::FishBody(std::string name, const FishDesc& desc, const Material& material, std::uint64_t seed, int hook,
                   double water_density)
    : SpringNetworkBody(std::move(name), "fish"),
      desc_(desc),
      tmpl_(makeFishTemplate(desc.length, water_density)),
      material_(material),
      seed_(seed),
      hook_(hook),
      skin_(std::make_shared<const Image>(makeFishSkin(desc.pattern, material.color, desc.pattern_color, 256))) {
  const auto n = static_cast<std::size_t>(desc.count);
  motor_.resize(n);
  mind_.resize(n);
  command_.resize(n);
  caught_.assign(n, 0);
  hook_point_.assign(n, Vec3::Zero());
  percept_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    FishMind& m = mind_[i];
    m.hunger = desc.hunger, m.libido = desc.libido, m.fear = desc.fear;
    motor_[i].phase = 2 * kPi * uniformAt(seed, kStartStream, 8 * i + 5);
  }
}

FishFrame FishBody::frame(std::size_t i) const {
  return fishFrame(&net_.state.x[kFishNodes * i], &net_.state.v[kFishNodes * i]);
}

MotorCommand FishBody::driveCommand(double t, FishMotor& m) const {
  const FishDriveDesc& d = desc_.drive;
  MotorCommand c;
  c.speed = -1.0;  // frequency and amplitude given
  if (t >= d.swim_start && t < d.swim_stop) c.frequency = d.swim_frequency, c.amplitude = d.swim_amplitude;
  if (d.turn_side != 0 && t >= d.turn_start && t < d.turn_stop)
    c.bend = d.turn_angle_deg > 0 ? turnByAngle(m, d.turn_side, d.turn_angle_deg * kPi / 180.0, d.turn_amount) : d.turn_side * d.turn_amount;
  c.pitch = d.pitch_deg * kPi / 180.0;
  c.yaw = d.yaw_deg * kPi / 180.0;
  return c;
}

void FishBody::addPatterns(double t, FishMotor& m) const {
  for (const MusclePatternDesc& p : desc_.drive.muscles) {
    if (t < p.start || t >= p.stop) continue;
    const double c = p.frequency > 0 ? p.contraction * std::max(0.0, std::sin(2 * kPi * p.frequency * (t - p.start) + p.phase_deg * kPi / 180.0))
                                     : p.contraction;
    for (int k : p.muscles) m.contraction[static_cast<std::size_t>(k)] = std::clamp(m.contraction[static_cast<std::size_t>(k)] + c, 0.0, 1.0);
  }
}

// Perception and behaviour of every fish, from what every body published at its last step.
void FishBody::decide(StepContext& ctx, int self) {
  everyone_.clear();
  std::vector<FishWorldView::Food> food;
  for (const SharedView::Fish& f : ctx.shown->fish) everyone_.insert(everyone_.end(), f.sightings->begin(), f.sightings->end());
  // The grid's cells as large as the farthest sight: the vision radius times the largest fish's
  // object-size factor (up to 2; a school of one size sees only its radius), and a length more,
  // since a fish looks from its mouth and searches the cells around its centre. (They were twice
  // the radius: the 27 cells around a fish of a school held about 6 times the candidates.)
  double longest = 0.0;
  for (const FishSighting& f : everyone_) longest = std::max(longest, f.length);
  const double reach = desc_.vision_radius * std::clamp(longest / desc_.length, 0.5, 2.0) + desc_.length;
  for (const SharedView::Food& fd : ctx.shown->food) food.push_back({fd.body, fd.x, fd.id});
  std::vector<Vec3> lo(everyone_.size()), hi(everyone_.size());
  for (std::size_t k = 0; k < everyone_.size(); ++k) lo[k] = hi[k] = everyone_[k].center;
  grid_.build(lo, hi, reach);
  obstacles_.clear();
  for (std::size_t c = 0; c < ctx.colliders->size(); ++c)
    if (static_cast<int>(c) != hook_ && !ignored_[c]) obstacles_.push_back((*ctx.colliders)[c]);
  FishWorldView w;
  w.fish = &everyone_;
  w.fish_grid = &grid_;
  w.food = food;
  w.hook = hook_ >= 0 ? &(*ctx.colliders)[static_cast<std::size_t>(hook_)] : nullptr;
  w.obstacles = &obstacles_;
  const std::int64_t decision = decisions_++;
  parallelFor(static_cast<Index>(count()), [&](Index i) {
    const FishFrame f = frame(static_cast<std::size_t>(i));
    FishMind& m = mind_[i];
    if (caught_[i]) {
      // On the line: struggling, thrashing from side to side.
      m.intention = static_cast<int>(Intention::Caught);
      command_[i] = MotorCommand{desc_.max_speed * desc_.length, 0, 0, std::sin(3.0 * ctx.t1 + static_cast<double>(i)), 0.0, 0.0};
      return;
    }
    perceive(desc_, f, self, static_cast<int>(i), w, percept_[i]);
    updateMind(desc_, percept_[i], kFishDecision, m);
    command_[i] = behave(desc_, f, percept_[i], kFishDecision, seed_, decision, static_cast<std::size_t>(i), m);
  });
  // A fish eating at the hook bites it when its mouth reaches it.
  if (w.hook) {
    const double bite = 0.1 * desc_.length;
    for (std::size_t i = 0; i < count(); ++i) {
      if (caught_[i] || mind_[i].intention != static_cast<int>(Intention::Eat)) continue;
      const Vec3 mouth = net_.state.x[kFishNodes * i];
      double dist;
      Vec3 n;
      if (w.hook->distance(mouth, dist, n) && dist < bite) {
        caught_[i] = 1;
        hook_point_[i] = w.hook->toAuthored(mouth);
        mind_[i].intention = static_cast<int>(Intention::Caught);
      }
    }
  }
}

// The paper's fins also keep the fish upright: a couple on the flanks against roll, as a
// critically damped rotational spring of 2 Hz (in water only: the fins push on it). (At 1 Hz a
// fish braking with one fin at full speed rolled onto its side within 4 s.)
void FishBody::rollBalance() {
  const auto& x = net_.state.x;
  const auto& v = net_.state.v;
  external_.resize(x.size());
  const double arm = 0.06 * desc_.length, inertia = tmpl_.total_mass * arm * arm, w = 4 * kPi;
  parallelFor(static_cast<Index>(count()), [&](Index fi) {
    const auto i = static_cast<std::size_t>(fi);
    const FishFrame& f = frames_[i];  // of this state, from the motor pass
    const std::size_t o = kFishNodes * i;
    std::fill_n(external_.begin() + static_cast<std::ptrdiff_t>(o), kFishNodes, Vec3::Zero());
    const double roll = std::asin(std::clamp(f.left.y(), -1.0, 1.0));  // left side up: > 0
    const double rate = ((v[o + 5] + v[o + 8] + v[o + 9] + v[o + 12]) - (v[o + 6] + v[o + 7] + v[o + 10] + v[o + 11])).dot(f.up) /
                        (4 * 2 * arm);
    const double torque = -(inertia * w * w * roll + 2 * inertia * w * rate);
    const Vec3 force = (torque / (2 * arm) / 4) * f.up;
    for (int k : {5, 8, 9, 12}) external_[o + static_cast<std::size_t>(k)] += force;
    for (int k : {6, 7, 10, 11}) external_[o + static_cast<std::size_t>(k)] -= force;
  });
}

// Tu & Terzopoulos 1994, eq. (3): each surface face moving into the water feels
// f = −ρ A (n·v) n (A its area, n its outward normal, v its velocity relative to the water),
// shared equally by its corners (24 faces: the nose's 4 triangles, 16 body quads, the tail's 2
// wedges and 2 flanks; n streamlined for faces that look ahead, kFrontDrag); the pectoral fins
// are plates that feel it on either side, their normal pitched from the body's up. Node i
// gathers D_i = Σ ρ (A/corners) n nᵀ and feels D_i (u − v): a linear drag the step's solve takes
// with the springs (MassSpringSystem::setNodeDrag). Which faces lead is read at the start of the
// step. In the solve, the stiff drag of a light tail
// node can neither overshoot nor be split from the springs that drive it.
void FishBody::waterDrag(const StepContext& ctx) {
  const double rho = ctx.water->density();
  const auto& x = net_.state.x;
  const auto& v = net_.state.v;
  const double L = desc_.length;
  drag_.resize(x.size());
  flow_.resize(x.size());
  const std::vector<Collider>& cs = *ctx.colliders;
  parallelFor(static_cast<Index>(count()), [&](Index fi) {
    const std::size_t o = kFishNodes * static_cast<std::size_t>(fi);
    Mat3* D = &drag_[o];
    Vec3* Du = &flow_[o];
    for (int k = 0; k < kFishNodes; ++k) D[k].setZero(), Du[k].setZero();
    const FishFrame& f = frames_[static_cast<std::size_t>(fi)];  // of this state, from the motor pass
    for (const auto& fc : tmpl_.faces) {
      const int count = fc[3] < 0 ? 3 : 4;
      const auto at = [&](int c) -> const Vec3& { return x[o + static_cast<std::size_t>(fc[static_cast<std::size_t>(c)])]; };
      const Vec3 area2 = (at(2) - at(0)).cross(at(count == 4 ? 3 : 0) - at(1));  // twice the area vector
      const double len = area2.norm();
      if (!(len > 1e-300)) continue;
      const Vec3 n = area2 / len;
      Vec3 centroid = Vec3::Zero(), vel = Vec3::Zero();
      for (int c = 0; c < count; ++c) centroid += at(c), vel += v[o + static_cast<std::size_t>(fc[static_cast<std::size_t>(c)])];
      centroid /= count, vel /= count;
      const Vec3 u = ctx.water->at(centroid, ctx.t1, cs);
      if (n.dot(vel - u) <= 0) continue;  // leaving the water behind it: no push
      // Streamlined: the forward part of a face's normal shrunk (the drag along the body's axis
      // on a face that looks ahead), its push across the flow kept.
      const double ahead = std::clamp(2.0 * n.dot(f.forward), 0.0, 1.0);  // 0 on the flanks, 1 facing 60° or less off ahead
      const Vec3 ns = n - (1.0 - kFrontDrag) * (ahead * ahead * (3.0 - 2.0 * ahead)) * n.dot(f.forward) * f.forward;
      const Mat3 Dt = (rho * 0.5 * len / count) * (ns * ns.transpose());
      const Vec3 Dtu = Dt * u;
      for (int c = 0; c < count; ++c) D[fc[static_cast<std::size_t>(c)]] += Dt, Du[fc[static_cast<std::size_t>(c)]] += Dtu;
    }
    // Each fin: a plate whose normal is the body's up pitched by the fin angle; opened toward the
    // flow (the left for a positive yaw, both as brakes) by an angle a, it is taken as that plate
    // with cos²a of its push and a plate facing ahead with sin²a: a brake on its side that does
    // not lift it. (A single plate turned from the pitched normal toward the flow lifts as it
    // brakes: a braking fish climbed, and one braking on one side rolled.)
    const double p = motor_[fi].pitch, yaw = motor_[fi].yaw;
    const Vec3 pitched = std::cos(p) * f.up - std::sin(p) * f.forward;
    for (int side = 0; side < 2; ++side) {
      const double open = std::min((side == 0 ? std::max(yaw, 0.0) : std::max(-yaw, 0.0)) + motor_[fi].brake, kPi / 2);
      const double c = std::cos(open), sn = std::sin(open);
      const Mat3 Df = (rho * kFinArea * L * L / 2) * (c * c * (pitched * pitched.transpose()) + sn * sn * (f.forward * f.forward.transpose()));
      for (int k : side == 0 ? std::array<int, 2>{5, 8} : std::array<int, 2>{6, 7}) {
        const Vec3 u = ctx.water->at(x[o + static_cast<std::size_t>(k)], ctx.t1, cs);
        D[k] += Df, Du[k] += Df * u;
      }
    }
  });
}

void FishBody::publishSightings(int self) {
  sightings_.resize(count());
  parallelFor(static_cast<Index>(count()), [&](Index fi) {
    const auto i = static_cast<std::size_t>(fi);
    const FishFrame f = frame(i);
    FishSighting& s = sightings_[i];
    s.center = f.center, s.mouth = f.mouth, s.velocity = f.velocity, s.forward = f.forward;
    s.length = desc_.length, s.body = self, s.index = static_cast<int>(i), s.species = desc_.species;
    s.hunts = desc_.habits.hunts, s.mates = desc_.habits.mates, s.caught = caught_[i] != 0;
    s.biting = mind_[i].intention == static_cast<int>(Intention::Eat);
  });
}

void FishBody::show(SharedView& out, int self) {
  self_ = self;
  out.fish.push_back({self, &sightings_});
}

void FishBody::step(StepContext& ctx) {
  const int self = self_;
  if (sightings_.size() != count()) publishSightings(self);
  // Meals the food bodies listed for this body's fish.
  for (const SharedView::Food& food : ctx.shown->food)
    for (const FoodMeal& meal : *food.meals)
      if (meal.body == self && meal.fish >= 0 && static_cast<std::size_t>(meal.fish) < count()) {
        FishMind& m = mind_[static_cast<std::size_t>(meal.fish)];
        m.hunger = std::max(0.0, m.hunger - kMeal);
        ++meals_;
      }
  const bool decision = std::floor(ctx.t1 / kFishDecision) > std::floor(ctx.t0 / kFishDecision) || decisions_ == 0;
  if (desc_.behaviour && decision) decide(ctx, self);

  // Motor controllers, then the muscles' rest lengths.
  Springs& sp = net_.model.springs;
  frames_.resize(count());
  parallelFor(static_cast<Index>(count()), [&](Index i) {
    const FishFrame& f = frames_[i] = frame(static_cast<std::size_t>(i));
    trackHeading(motor_[i], f.forward, ctx.h);
    const MotorCommand cmd = desc_.behaviour ? command_[i] : driveCommand(ctx.t0, motor_[i]);
    motorControl(cmd, f.velocity.dot(f.forward), desc_.length, ctx.h, motor_[i]);
    addPatterns(ctx.t0, motor_[i]);
    const std::size_t so = kFishSprings * static_cast<std::size_t>(i);
    for (int k = 0; k < kFishMuscles; ++k) {
      const int s = tmpl_.muscle[static_cast<std::size_t>(k)];
      sp.rest[so + static_cast<std::size_t>(s)] = tmpl_.springs.rest[static_cast<std::size_t>(s)] * (1.0 - kMaxContraction * motor_[i].contraction[static_cast<std::size_t>(k)]);
    }
  });
  const bool water = ctx.water && ctx.water->density() > 0;
  if (water) {
    rollBalance();
    waterDrag(ctx);
    net_.system->setExternalForces(external_.data());
    net_.system->setNodeDrag(drag_.data(), flow_.data());
  } else {
    net_.system->setExternalForces(nullptr);
    net_.system->setNodeDrag(nullptr, nullptr);
  }
  net_.integrate(ctx);
  net_.contacts(ctx);
  // Caught fish hang from the hook by the mouth.
  if (hook_ >= 0) {
    const Collider& c = (*ctx.colliders)[static_cast<std::size_t>(hook_)];
    for (std::size_t i = 0; i < count(); ++i)
      if (caught_[i]) {
        const Vec3 p = c.fromAuthored(hook_point_[i]);
        net_.state.x[kFishNodes * i] = p;
        net_.state.v[kFishNodes * i] = c.velocityAt(p);
      }
  }
  publishSightings(self);
}

void FishBody::exportContacts(ContactExport& out) const {
  contact_inv_mass_ = net_.model.inv_mass;
  for (std::size_t i = 0; i < count(); ++i)
    if (caught_[i]) contact_inv_mass_[kFishNodes * i] = 0.0;
  out.points(net_.state.x, net_.state.v, contact_inv_mass_, net_.radius, piece_);
  exportSurface(out);
}

void FishBody::importContacts(std::span<const Vec3> x, std::span<const Vec3> v) {
  SpringNetworkBody::importContacts(x, v);
  publishSightings(self_);
}

bool FishBody::view(BodyView& out) const {
  SpringNetworkBody::view(out);
  out.masses = net_.model.mass;
  ViewField muscles{"muscles", kFishMuscles, {}}, mental{"mental", 3, {}}, intention{"intention", 1, {}};
  for (std::size_t i = 0; i < count(); ++i) {
    for (double c : motor_[i].contraction) muscles.values.push_back(c);
    mental.values.insert(mental.values.end(), {mind_[i].hunger, mind_[i].libido, mind_[i].fear});
    intention.values.push_back(mind_[i].intention);
  }
  out.fields = {std::move(muscles), std::move(mental), std::move(intention)};
  return true;
}

void FishBody::statistics(std::vector<Statistic>& out) const {
  double hunger = 0, fear = 0, libido = 0, speed = 0;
  const double n = static_cast<double>(count());
  for (std::size_t i = 0; i < count(); ++i) {
    hunger += mind_[i].hunger, fear += mind_[i].fear, libido += mind_[i].libido;
    const FishFrame f = frame(i);
    speed += f.velocity.dot(f.forward);
  }
  out.push_back({"hunger", hunger / n});
  out.push_back({"libido", libido / n});
  out.push_back({"fear", fear / n});
  out.push_back({"speed", speed / n});
  out.push_back({"meals", static_cast<double>(meals_)});
}

std::vector<std::string> FishBody::notes(double) const {
  const double mass = tmpl_.total_mass;
  return {"fish '" + name() + "': " + std::to_string(count()) + " " + kFishSpeciesNames[static_cast<std::size_t>(desc_.species)] +
          " fish of " + formatNumber(desc_.length, 3) + " m and " + formatNumber(mass, 3) + " kg, " +
          (desc_.behaviour ? "deciding every " + formatNumber(kFishDecision, 3) + " s" : "driven")};
}

void FishBody::snapshotMore(StateWriter& w) const {
  w.put(motor_);
  w.put(mind_);
  w.put(command_);
  w.put(caught_);
  w.put(hook_point_);
  w.put(decisions_);
  w.put(meals_);
  w.put(static_cast<int>(sightings_.empty() ? -1 : self_));  // −1: nothing published yet
}

bool FishBody::restoreMore(StateReader& r) {
  const std::size_t n = count();
  std::vector<FishMotor> motor;
  std::vector<FishMind> mind;
  std::vector<MotorCommand> command;
  std::vector<std::uint8_t> caught;
  std::vector<Vec3> hook;
  std::int64_t decisions = 0, meals = 0;
  int self = -1;
  r.get(motor), r.get(mind), r.get(command), r.get(caught), r.get(hook), r.get(decisions), r.get(meals), r.get(self);
  // The network was read first: its sizes are checked here too, before anything reads its nodes.
  if (motor.size() != n || mind.size() != n || command.size() != n || caught.size() != n || hook.size() != n ||
      decisions < 0 || meals < 0 || self < -1 || net_.state.x.size() != kFishNodes * n || net_.state.v.size() != kFishNodes * n ||
      !allWithin(hook, kRunawayDistance))
    return false;
  auto finite = [](std::initializer_list<double> xs) {
    for (double x : xs)
      if (!std::isfinite(x)) return false;
    return true;
  };
  auto unit = [](const std::array<double, 3>& a) { return std::abs(Vec3(a[0], a[1], a[2]).norm() - 1) < 1e-6; };
  for (std::size_t i = 0; i < n; ++i) {
    const FishMind& m = mind[i];
    const FishMotor& mo = motor[i];
    const MotorCommand& c = command[i];
    if (!(m.hunger >= 0 && m.hunger <= 1 && m.libido >= 0 && m.libido <= 1 && m.fear >= 0 && m.fear <= 1) ||
        m.intention < 0 || m.intention >= static_cast<int>(kIntentionNames.size()) || m.previous < 0 ||
        m.previous >= static_cast<int>(kIntentionNames.size()) || !finite({m.since, m.courting}) || !unit(m.wander) ||
        !finite({mo.phase, mo.frequency, mo.amplitude, mo.speed_error, mo.bend, mo.pitch, mo.yaw, mo.brake, mo.turned, mo.turn_from[0],
                 mo.turn_from[2]}) ||
        !unit(mo.heading) || (mo.turn_done != 0 && mo.turn_done != 1) || !finite({c.speed, c.frequency, c.amplitude, c.bend, c.pitch, c.yaw}))
      return false;
    for (double x : mo.contraction)
      if (!(x >= 0 && x <= 1)) return false;
  }
  motor_ = std::move(motor), mind_ = std::move(mind), command_ = std::move(command), caught_ = std::move(caught);
  hook_point_ = std::move(hook), decisions_ = decisions, meals_ = meals;
  // What the others see is the state just restored, as the last step published it.
  if (self >= 0) publishSightings(self_);
  else sightings_.clear();
  return true;
}

void FishBody::hash(Hasher& h) const {
  SpringNetworkBody::hash(h);
  h.add(std::span<const FishMotor>(motor_));
  for (const FishMind& m : mind_) {
    const double v[] = {m.hunger, m.libido, m.fear, static_cast<double>(m.intention)};
    h.add(std::span<const double>(v));
  }
}

Result<std::unique_ptr<Body>> buildFishBody(const BodyDesc& desc, const BuildContext& ctx) {
  auto buildFish = [&](const FishDesc& d) -> Result<std::unique_ptr<Body>> {
    const int hook = d.hook.empty() ? -1 : objectIndex(*ctx.scene, d.hook);
    auto body = std::make_unique<FishBody>(desc.name, d, desc.material, ctx.seed, hook, ctx.scene->water.density);
    body->ignored_.assign(ctx.colliders->size(), 0);  // rigid bodies' colliders come after the scene's objects
    for (std::size_t c = 0; c < ctx.scene->objects.size(); ++c)
      body->ignored_[c] = std::find(d.ignore.begin(), d.ignore.end(), ctx.scene->objects[c].name) != d.ignore.end();
    const FishTemplate& t = body->fishTemplate();
    // Every fish: the template turned to its heading and moved so its centre of mass is at its
    // start point.
    MassSpringDesc ms;
    const auto n = static_cast<std::size_t>(d.count);
    for (std::size_t i = 0; i < n; ++i) {
      auto u = [&](int k) { return uniformAt(ctx.seed, kStartStream, 8 * i + static_cast<std::size_t>(k)); };
      const bool one = !d.start_given;
      const Vec3 at = one ? d.position : d.start.point(u(0), u(1), u(2));
      Vec3 heading = one ? d.heading.value_or(Vec3::UnitZ()) : d.start.heading.value_or(Vec3::Zero());
      if (heading.squaredNorm() == 0) {
        const double a = 2 * kPi * u(3);
        heading = Vec3(std::sin(a), 0.0, std::cos(a));  // random, level
      }
      const Vec3 fwd = heading.normalized();
      body->mind_[i].wander = {fwd.x(), fwd.y(), fwd.z()};
      body->motor_[i].heading = {fwd.x(), fwd.y(), fwd.z()};
      const Vec3 left = unitOr(Vec3::UnitY().cross(fwd), Vec3::UnitX());
      const Vec3 up = fwd.cross(left);
      Mat3 R;
      R.col(0) = left, R.col(1) = up, R.col(2) = fwd;
      const std::size_t base = ms.nodes.size();
      for (int k = 0; k < kFishNodes; ++k) {
        NodeDesc nd;
        nd.position = at + R * (t.x[static_cast<std::size_t>(k)] - t.center_of_mass);
        nd.mass = t.mass[static_cast<std::size_t>(k)];
        nd.velocity = Vec3::Zero();
        ms.nodes.push_back(nd);
      }
      for (std::size_t s = 0; s < t.springs.size(); ++s) {
        SpringDesc sd;
        sd.a = static_cast<int>(base) + t.springs.a[s];
        sd.b = static_cast<int>(base) + t.springs.b[s];
        sd.stiffness = t.springs.stiffness[s];
        sd.damping = t.springs.damping[s];
        sd.rest_length = t.springs.rest[s];
        ms.springs.push_back(sd);
      }
    }
    // Each fish is a piece of its own: its skin meets the other fish, kelp, liquids and sheets.
    std::vector<std::array<int, 3>> skin;
    std::vector<int> piece;
    for (std::size_t i = 0; i < n; ++i) {
      const int base = static_cast<int>(i) * kFishNodes;
      for (const auto& tri : t.surface) skin.push_back({base + tri[0], base + tri[1], base + tri[2]});
      piece.insert(piece.end(), kFishNodes, static_cast<int>(i));
    }
    body->setSurface(std::move(skin), std::move(piece));
    // Fish are neutrally buoyant (their weight and the water's lift cancel): no gravity.
    SpringNetwork& net = body->network();
    net.build(ms, Vec3::Zero(), ctx.scene->integrator, d.contactRadius(0));
    net.tolerance = 1e-4;  // a fish's thrust comes from small differences of its body wave
    net.system->setPredictor(true);  // its speed the same at any step (MassSpringSystem::setPredictor)
    if (std::string e = net.unstableMethod(desc.name, ctx.scene->integrator); !e.empty())
      return Error(ErrorKind::BadInput, ctx.scene->file + ": " + e);
    return std::unique_ptr<Body>(std::move(body));
  };
  const auto& d = desc.as<FishDesc>();
  const SceneDesc& scene = *ctx.scene;
  // Every fish of a body is the same template: a step one of them cannot take, none can, and the
  // World refuses the scene. One fish is built to say so (a body of 100,000 took 10 s and 1.1 GB
  // to be refused); otherwise all of them.
  if (d.count > 1 && !scene.auto_substeps) {
    FishDesc one = d;
    one.count = 1;
    auto probe = buildFish(one);
    if (!probe.ok()) return probe;
    const double h = 1.0 / (static_cast<double>(scene.fps) * scene.substeps);
    if (h > probe.value()->stepLimit(scene.integrator).bound.h_max) return probe;
  }
  return buildFish(d);
}

}  // namespace reel
