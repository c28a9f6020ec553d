#include "sim/articulated/stand_up.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "core/math.h"
#include "sim/articulated/controllers.h"

namespace reel {
namespace {

// A pose in the handles, degrees: hip flexion (the knee forward), knee flexion, ankle (+: toes down),
// spine flexion (abdomen and chest together, forward), neck flexion, shoulder flexion (the arm
// forward), elbow flexion.
enum Handle { Hip, Knee, Ankle, Spine, Neck, Shoulder, Elbow, kHandles };
using Handles = std::array<double, kHandles>;

// The phases' poses and times, found by a search over simulated get-ups (seven figures of strength
// 0.8 to 1.2 on friction 0.6 to 1, 1.6 to 1.9 m tall, arms and legs spread; then four more) and
// checked on 39 others it had not seen (docs/articulated.md).
struct Params {
  Handles curl{-10, 0, 0, 65, 40, 60, 0};
  double curl_s = 0.35;
  Handles sit{90, 0, 0, 65, 20, 90, 0};
  double sit_s = 0.55;
  Handles tuck{103, 146, -42, 44, 3, -150, 55};
  double tuck_s = 0.82;
  Handles rock{125, 150, -6, 50, 21, 83, 18};
  double rock_blend_s = 0.25, rock_max_s = 2.3;
  Handles squat{85, 150, -41, 57, -10, 100, 25};
  double rise_s = 0.6;
  double ankle_kp = 229, ankle_kv = 86;  // deg per m, per m/s (balance's 4 rad/m and 1.5 rad·s/m)
  double hip_kp = 168, hip_kv = 19;
  double lift = 0.2;      // m: the pelvis this far above the feet has left the ground
  double sat = 0.12;      // m: this close, it sits again
  double settle = 0.05;   // m: the squat's offset before it rises
};

const Handles kStanding{0, 0, 0, 0, 0, 0, 0};

Handles blend(const Handles& a, const Handles& b, double s) {
  s = std::clamp(s, 0.0, 1.0);
  s = s * s * (3 - 2 * s);
  Handles r;
  for (int i = 0; i < kHandles; ++i) r[static_cast<std::size_t>(i)] = (1 - s) * a[static_cast<std::size_t>(i)] + s * b[static_cast<std::size_t>(i)];
  return r;
}

void set(std::vector<std::vector<double>>& targets, int link, std::vector<double> v) {
  if (link >= 0) targets[static_cast<std::size_t>(link)] = std::move(v);
}

// Every joint's target from the handles (both sides alike).
void apply(const StandUpLinks& l, const Handles& p, std::vector<std::vector<double>>& targets) {
  const double d = kPi / 180.0;
  const double spine = p[Spine] * d;
  set(targets, l.abdomen, {spine * 35.0 / 65.0, 0, 0});
  set(targets, l.chest, {spine * 30.0 / 65.0, 0, 0});
  set(targets, l.head, {p[Neck] * d, 0, 0});
  for (int side = 0; side < 2; ++side) {
    set(targets, l.thigh[side], {-p[Hip] * d, 0, 0});
    set(targets, l.shin[side], {p[Knee] * d});
    set(targets, l.foot[side], {p[Ankle] * d, 0});
    set(targets, l.upper_arm[side], {-p[Shoulder] * d, 0, 0});
    set(targets, l.forearm[side], {-p[Elbow] * d});
  }
}

}  // namespace

bool StandUpLinks::valid() const {
  for (int i : {pelvis, abdomen, chest, head, upper_arm[0], upper_arm[1], forearm[0], forearm[1], thigh[0], thigh[1],
                shin[0], shin[1], foot[0], foot[1]})
    if (i < 0) return false;
  return true;
}

StandUpLinks standUpLinks(const ArticulatedModel& m) {
  StandUpLinks r;
  for (std::size_t i = 0; i < m.links.size(); ++i) {
    const std::string& n = m.links[i].name;
    const int k = static_cast<int>(i);
    const int side = n.ends_with("_r") ? 1 : 0;
    const std::string base = n.ends_with("_l") || n.ends_with("_r") ? n.substr(0, n.size() - 2) : n;
    if (n == "pelvis") r.pelvis = k;
    else if (n == "abdomen") r.abdomen = k;
    else if (n == "chest") r.chest = k;
    else if (n == "head") r.head = k;
    else if (base == "upper_arm") r.upper_arm[side] = k;
    else if (base == "forearm") r.forearm[side] = k;
    else if (base == "thigh") r.thigh[side] = k;
    else if (base == "shin") r.shin[side] = k;
    else if (base == "foot") r.foot[side] = k;
  }
  return r;
}

bool standUp(const StandUpLinks& l, const ControllersDesc& c, const StandUpInput& in, StandUpState& s,
             std::vector<std::vector<double>>& targets) {
  if (!c.stand_up || !l.valid()) return false;
  const Params P;
  const ArtKinematics& k = *in.k;
  const Vec3& up = in.up;
  auto at = [&](int link) { return k.x[static_cast<std::size_t>(link)]; };
  const Vec3 feet = 0.5 * (at(l.foot[0]) + at(l.foot[1]));
  const double pelvis_h = (at(l.pelvis) - feet).dot(up);
  const Vec3 forward = heading(k.R[static_cast<std::size_t>(l.pelvis)], up);
  const double d = (in.com - feet).dot(forward), dv = in.vcom.dot(forward);
  auto enter = [&](StandUpPhase next, const Handles& from) {
    s.phase = static_cast<int>(next);
    s.since = in.t;
    std::copy(from.begin(), from.end(), s.from);
  };
  // Another try: from the tuck while it still sits up, from the curl when it lies back.
  auto retry = [&](const Handles& now) {
    const bool sitting = (at(l.chest) - at(l.pelvis)).dot(up) > 0.2;
    enter(sitting ? StandUpPhase::Tuck : StandUpPhase::Curl, now);
  };
  Handles from;
  std::copy(s.from, s.from + kHandles, from.begin());
  auto phaseIs = [&](StandUpPhase p) { return s.phase == static_cast<int>(p); };

  if (phaseIs(StandUpPhase::Idle)) {
    // Pre-condition: on its back (the chest facing up, level with the pelvis), still.
    const Mat3& Rc = k.R[static_cast<std::size_t>(l.chest)];
    const bool supine = Rc.col(2).dot(up) > 0.5 && std::abs((at(l.chest) - at(l.pelvis)).dot(up)) < 0.2;
    if (!supine || in.vcom.norm() > 0.25) {
      s.still_since = -1;
      return false;
    }
    if (s.still_since < 0) s.still_since = in.t;
    if (in.t - s.still_since < c.stand_up_wait) return false;
    enter(StandUpPhase::Curl, kStanding);
    from = kStanding;
  }
  const double tau = in.t - s.since;
  Handles pose = kStanding;
  switch (static_cast<StandUpPhase>(s.phase)) {
    case StandUpPhase::Curl:
      pose = blend(from, P.curl, tau / P.curl_s);
      if (tau >= P.curl_s) enter(StandUpPhase::Sit, P.curl);
      break;
    case StandUpPhase::Sit:
      pose = blend(from, P.sit, tau / P.sit_s);
      if (tau >= P.sit_s) enter(StandUpPhase::Tuck, P.sit);
      break;
    case StandUpPhase::Tuck:
      pose = blend(from, P.tuck, tau / P.tuck_s);
      if (tau >= P.tuck_s) enter(StandUpPhase::Rock, P.tuck);
      break;
    case StandUpPhase::Rock:
      pose = blend(from, P.rock, tau / P.rock_blend_s);
      if (pelvis_h > P.lift && in.feet_down) enter(StandUpPhase::Squat, pose);
      else if (tau >= P.rock_max_s) retry(pose);
      break;
    case StandUpPhase::Squat:
      pose = blend(from, P.squat, tau / 0.3);
      if (pelvis_h < P.sat) retry(pose);
      else if (tau > 0.3 && std::abs(d) < P.settle && std::abs(dv) < 0.2)
        enter(StandUpPhase::Rise, P.squat);
      break;
    case StandUpPhase::Rise:
      pose = blend(from, kStanding, tau / P.rise_s);
      if (pelvis_h < P.sat) retry(pose);
      else if (tau >= P.rise_s)
        enter(StandUpPhase::Stand, kStanding);
      break;
    case StandUpPhase::Stand:
      pose = kStanding;
      break;
    default:
      break;
  }
  // Fallen (the centre of mass low over the feet or far off them, after rising): idle again.
  const bool risen = phaseIs(StandUpPhase::Squat) || phaseIs(StandUpPhase::Rise) || phaseIs(StandUpPhase::Stand);
  if (risen && ((in.com - feet).dot(up) < 0.25 || std::abs(d) > 0.3)) {
    s.phase = static_cast<int>(StandUpPhase::Idle);
    s.still_since = -1;
    return false;
  }
  if (risen) {
    pose[Ankle] += P.ankle_kp * d + P.ankle_kv * dv;
    pose[Hip] -= P.hip_kp * d + P.hip_kv * dv;
  }
  apply(l, pose, targets);
  return true;
}

}  // namespace reel
