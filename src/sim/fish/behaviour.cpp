#include "sim/fish/behaviour.h"

#include <algorithm>
#include <cmath>

#include "core/math.h"
#include "core/random.h"

namespace reel {
namespace {

constexpr std::uint64_t kWanderStream = 0xF15A;
constexpr std::size_t kMaxFood = 4;  // nearest food particles a fish keeps in mind

bool nearer(const Seen& a, const Seen& b) {
  if (a.distance != b.distance) return a.distance < b.distance;
  if (a.body != b.body) return a.body < b.body;
  return a.index < b.index;
}

// The sight line from a to b stops `short_by` before b: what touches the thing seen (the seabed
// under it, a hook's line) does not hide it.
Vec3 shortOf(const Vec3& a, const Vec3& b, double short_by) {
  const Vec3 d = b - a;
  const double len = d.norm();
  return len > short_by ? Vec3(b - (short_by / len) * d) : a;
}

}  // namespace

// Tu & Terzopoulos 1994 §4: the eyes see within a 300° solid angle and a radius, and an object is
// seen only if no object of the scene stands between (a ray test); how far a thing is seen grows
// with its size relative to the viewer's. Food is smelt within its own radius, through anything.
void perceive(const FishDesc& d, const FishFrame& self, int self_body, int self_index, const FishWorldView& w,
              Percept& out) {
  out.seen.clear();
  out.surroundings = Steering{};
  out.bounds = Steering{};
  const Vec3 eye = self.mouth;
  const double cos_half = std::cos(0.5 * d.field_of_view_deg * kPi / 180.0);
  auto inCone = [&](const Vec3& p, double& dist) {
    const Vec3 r = p - eye;
    dist = r.norm();
    return dist > 1e-9 && r.dot(self.forward) >= cos_half * dist;
  };
  std::vector<Seen> fish;
  if (w.fish && w.fish_grid) {
    w.fish_grid->forEachNear(self.center, [&](std::int32_t k) {
      const FishSighting& f = (*w.fish)[static_cast<std::size_t>(k)];
      if (f.body == self_body && f.index == self_index) return;
      const double size = std::clamp(f.length / d.length, 0.5, 2.0);  // the object-size factor
      // (Most of the grid's candidates are far past the reach: refused on the squared distance,
      // with a margin that leaves the exact test below to decide near the edge.)
      const double reach = d.vision_radius * size;
      if ((f.center - eye).squaredNorm() > 1.000001 * reach * reach) return;
      double dist;
      if (!inCone(f.center, dist)) return;
      if (dist > reach) return;
      Seen s;
      s.kind = Seen::Kind::Fish;
      s.body = f.body, s.index = f.index, s.x = f.center, s.v = f.velocity, s.distance = dist, s.length = f.length;
      s.kin = f.body == self_body;
      s.predator = !s.kin && f.hunts && f.length > 1.2 * d.length;
      s.prey = !s.kin && d.habits.hunts && f.length < 0.8 * d.length && !f.caught;
      s.mate = d.habits.mates && f.mates && f.species == d.species && !f.caught;
      fish.push_back(s);
    });
  }
  // The nearest first: only as many are ordered as the loop below may take (a school's fish see a
  // hundred others and keep 11); should hidden ones leave room, the rest are ordered then.
  // (`nearer` is a total order: the same sequence as sorting them all.)
  const double step = 0.25 * d.length;
  const std::size_t keep = kMaxSeen - kMaxFood - 1;
  std::size_t sorted = std::min(fish.size(), keep);
  std::partial_sort(fish.begin(), fish.begin() + static_cast<std::ptrdiff_t>(sorted), fish.end(), nearer);
  for (std::size_t k = 0; k < fish.size() && out.seen.size() < keep; ++k) {
    if (k == sorted) {
      std::sort(fish.begin() + static_cast<std::ptrdiff_t>(sorted), fish.end(), nearer);
      sorted = fish.size();
    }
    const Seen& s = fish[k];
    if (!w.obstacles || !segmentBlocked(*w.obstacles, eye, shortOf(eye, s.x, 0.5 * s.length), step)) out.seen.push_back(s);
  }
  std::vector<Seen> food;
  for (const FishWorldView::Food& f : w.food)
    for (std::size_t k = 0; k < f.x->size(); ++k) {
      const double dist = ((*f.x)[k] - eye).norm();
      if (dist > d.smell_radius) continue;
      Seen s;
      s.kind = Seen::Kind::Food, s.body = f.body, s.index = static_cast<int>((*f.id)[k]), s.x = (*f.x)[k], s.distance = dist;
      food.push_back(s);
    }
  std::sort(food.begin(), food.end(), nearer);
  for (std::size_t k = 0; k < std::min(food.size(), kMaxFood); ++k) out.seen.push_back(food[k]);
  if (w.hook) {
    double dist;
    const Vec3 p = w.hook->pose.pos;
    if (inCone(p, dist) && dist <= d.vision_radius && !(w.obstacles && segmentBlocked(*w.obstacles, eye, shortOf(eye, p, 0.1 * d.length), step))) {
      Seen s;
      s.kind = Seen::Kind::Hook, s.x = p, s.v = w.hook->velocityAt(p), s.distance = dist;
      out.seen.push_back(s);
    }
  }
  std::sort(out.seen.begin(), out.seen.end(), nearer);
  // Objects ahead within a margin of 1½ lengths, looking a second and a length ahead.
  if (w.obstacles) {
    const double speed = std::max(self.velocity.dot(self.forward), 0.0);
    avoidObstacles(*w.obstacles, eye, (speed + d.length) * self.forward, 1.5 * d.length, out.surroundings);
  }
  if (d.bounds) containBounds(*d.bounds, self.center + d.length * self.forward, out.bounds);
}

void updateMind(const FishDesc& d, const Percept& p, double dt, FishMind& m) {
  m.hunger = std::min(1.0, m.hunger + d.digestion * dt);
  m.libido = std::min(1.0, m.libido + d.urge * dt * (1.0 - m.hunger));
  // F = min(Σᵢ Fⁱ, 1), Fⁱ = min(D₀/dⁱ, 1) over the predators in view; D₀ grows with timidity.
  const double d0 = d.habits.timidity * 0.5 * d.vision_radius;
  double fear = 0.0;
  for (const Seen& s : p.seen)
    if (s.kind == Seen::Kind::Fish && s.predator) fear += std::min(d0 / std::max(s.distance, 1e-9), 1.0);
  m.fear = std::min(fear, 1.0);
}

namespace {

const Seen* find(const Percept& p, bool (*test)(const Seen&)) {
  for (const Seen& s : p.seen)
    if (test(s)) return &s;  // the nearest such
  return nullptr;
}

const Seen* target(const Percept& p, const FishMind& m, Seen::Kind kind) {
  for (const Seen& s : p.seen)
    if (s.kind == kind && s.body == m.target_body && s.index == m.target_index) return &s;
  return nullptr;
}

// The intention generator (Tu & Terzopoulos 1994 §5.2, Fig. 7), in its priority order: avoid
// collisions; then, afraid, escape (a schooling fish escapes with its school); then, hungry, eat
// (or chase prey, for a hunter); then, with libido, mate; then school; else wander. A target held
// stays while it is still perceived (the focusser); an avoidance remembers what it interrupted
// and resumes it.
Intention choose(const FishDesc& d, const Percept& p, FishMind& m, const Seen*& focus) {
  focus = nullptr;
  const auto cur = static_cast<Intention>(m.intention);
  const bool avoiding = cur == Intention::AvoidObstacle || cur == Intention::AvoidFish;
  if (p.surroundings.avoid > 0.25) return Intention::AvoidObstacle;  // imminent; nearer walls only bias
  for (const Seen& s : p.seen)
    if (s.kind == Seen::Kind::Fish && s.distance < 0.6 * std::max(d.length, s.length) &&
        !(cur == Intention::Chase && s.body == m.target_body && s.index == m.target_index) &&
        !(cur == Intention::Mate && s.mate)) {
      focus = &s;
      return Intention::AvoidFish;
    }
  const Intention resume = avoiding ? static_cast<Intention>(m.previous) : cur;
  if (m.fear > 0.5) return Intention::Escape;
  if (m.hunger > 0.5 || ((resume == Intention::Eat || resume == Intention::Chase) && m.hunger > 0.2)) {
    if (d.habits.hunts) {
      if ((focus = target(p, m, Seen::Kind::Fish)) && focus->prey) return Intention::Chase;
      if ((focus = find(p, [](const Seen& s) { return s.kind == Seen::Kind::Fish && s.prey; }))) return Intention::Chase;
    } else {
      if ((focus = target(p, m, Seen::Kind::Food))) return Intention::Eat;
      if ((focus = find(p, [](const Seen& s) { return s.kind == Seen::Kind::Food || s.kind == Seen::Kind::Hook; })))
        return Intention::Eat;
    }
  }
  if (m.libido > 0.6 && d.habits.mates) {
    if ((focus = target(p, m, Seen::Kind::Fish)) && focus->mate) return Intention::Mate;
    if ((focus = find(p, [](const Seen& s) { return s.kind == Seen::Kind::Fish && s.mate; }))) return Intention::Mate;
  }
  focus = nullptr;
  if (d.habits.schools && find(p, [](const Seen& s) { return s.kind == Seen::Kind::Fish && s.kin; })) return Intention::School;
  return Intention::Wander;
}

// Unit direction of the kin in view by Couzin's zones, one body length apart (the school module's
// rules): repulsion within ⅔ length, alignment to 5 lengths, attraction to 8 (a wide zone of
// orientation: Couzin et al. 2002's parallel group).
Vec3 schoolDirection(const FishDesc& d, const FishFrame& self, const Percept& p) {
  std::vector<Vec3> nx, nv;
  for (const Seen& s : p.seen)
    if (s.kind == Seen::Kind::Fish && s.kin && s.v.squaredNorm() > 1e-12) nx.push_back(s.x), nv.push_back(s.v);
  CouzinDesc c;
  c.r_repulsion = 0.67 * d.length, c.r_orientation = 5.0 * d.length, c.r_attraction = 8.0 * d.length;
  return unitOr(couzinDirection(c, d.field_of_view_deg, self.center, self.forward, nx, nv), self.forward);
}

}  // namespace

MotorCommand behave(const FishDesc& d, const FishFrame& self, const Percept& p, double dt, std::uint64_t seed,
                    std::int64_t decision, std::size_t fish, FishMind& m) {
  const Seen* focus = nullptr;
  const Intention next = choose(d, p, m, focus);
  const auto cur = static_cast<Intention>(m.intention);
  if (next != cur) {
    const bool avoid_next = next == Intention::AvoidObstacle || next == Intention::AvoidFish;
    const bool avoiding = cur == Intention::AvoidObstacle || cur == Intention::AvoidFish;
    if (avoid_next && !avoiding) m.previous = m.intention;
    m.intention = static_cast<int>(next);
    m.since = 0.0;
    if (next != Intention::Mate) m.courting = 0.0;
  } else {
    m.since += dt;
  }
  m.target_body = focus ? focus->body : -1;
  m.target_index = focus ? focus->index : -1;

  const double cruise = d.cruise_speed * d.length, fast = d.max_speed * d.length;
  Vec3 dir = self.forward;
  double speed = cruise;
  switch (next) {
    case Intention::AvoidObstacle:
      dir = unitOr(self.forward + 3.0 * p.surroundings.avoid * unitOr(p.surroundings.push, Vec3::Zero()), self.forward);
      break;
    case Intention::AvoidFish: {
      const Vec3 away = self.center - focus->x;
      dir = unitOr(away - 0.5 * away.dot(self.forward) * self.forward, self.left);
      break;
    }
    case Intention::Escape: {
      // Away from every predator in view, more from the nearer; sideways from its path (the
      // fountain escape, as in the school module); with the school for a schooling fish.
      Vec3 away{0, 0, 0};
      for (const Seen& s : p.seen)
        if (s.kind == Seen::Kind::Fish && s.predator) {
          const Vec3 r = unitOr(self.center - s.x, self.left);
          const Vec3 h = unitOr(s.v, Vec3::Zero());
          away += (r - (2.0 / 3.0) * r.dot(h) * h) / std::max(s.distance, 0.1 * d.length);
        }
      dir = unitOr(away, self.forward);
      if (d.habits.schools) dir = unitOr(2.0 * dir + schoolDirection(d, self, p), dir);
      speed = fast;
      break;
    }
    case Intention::Chase: {
      const double lead = focus->distance / std::max(fast, 1e-9);
      dir = unitOr(focus->x + lead * focus->v - self.mouth, self.forward);
      speed = fast;
      break;
    }
    case Intention::Eat:
      dir = unitOr(focus->x - self.mouth, self.forward);
      speed = cruise * std::clamp(focus->distance / (2 * d.length), 0.4, 1.0);
      break;
    case Intention::Mate: {
      // Courtship: circling the mate about a body length out.
      const Vec3 r = focus->x - self.center;
      const Vec3 around = unitOr(Vec3::UnitY().cross(r), self.left);
      dir = unitOr(around + ((r.norm() - d.length) / d.length) * unitOr(r, Vec3::Zero()), self.forward);
      speed = 0.7 * cruise;
      m.courting += dt;
      if (m.courting > 5.0) m.libido = 0.0, m.courting = 0.0;  // mated
      break;
    }
    case Intention::School:
      dir = schoolDirection(d, self, p);
      break;
    case Intention::Wander:
    case Intention::Caught: {
      // A slow random walk of the heading, kept near the horizontal.
      const std::uint64_t stream = kWanderStream ^ (static_cast<std::uint64_t>(decision) << 16);
      const double a = 0.35 * (uniformAt(seed, stream, 2 * fish) - 0.5), b = 0.15 * (uniformAt(seed, stream, 2 * fish + 1) - 0.5);
      Vec3 w(m.wander[0], m.wander[1], m.wander[2]);
      w = unitOr(w + a * Vec3::UnitY().cross(w) + b * Vec3::UnitY(), w);
      w.y() *= 0.9;
      w = unitOr(w, Vec3::UnitZ());
      m.wander = {w.x(), w.y(), w.z()};
      dir = w;
      if (next == Intention::Caught) speed = fast;  // struggling on the line
      break;
    }
  }
  // Objects still within reach, and the bounds' walls, push whatever the intention.
  if (next != Intention::AvoidObstacle && p.surroundings.avoid > 0)
    dir = unitOr(dir + 2.0 * p.surroundings.avoid * unitOr(p.surroundings.push, Vec3::Zero()), dir);
  if (p.bounds.avoid > 0) dir = unitOr(dir + 2.0 * p.bounds.avoid * unitOr(p.bounds.push, Vec3::Zero()), dir);

  // The turn-MC bends toward the side of the desired direction, the fins pitch toward its
  // elevation and the inner fin opens as a brake on that side.
  MotorCommand cmd;
  const double yaw = std::atan2(dir.dot(self.left), dir.dot(self.forward));
  cmd.speed = speed;
  cmd.bend = std::clamp(yaw / (kPi / 2), -1.0, 1.0);
  const double elevation = std::asin(std::clamp(dir.y(), -1.0, 1.0)) - std::asin(std::clamp(self.forward.y(), -1.0, 1.0));
  cmd.pitch = std::clamp(1.5 * elevation, -0.5, 0.5);
  cmd.yaw = cmd.bend * (kPi / 4);  // the fin on the inner side brakes, helping the turn
  return cmd;
}

}  // namespace reel
