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
static_assert(kHandles == kStandUpHandles);
using Handles = std::array<double, kHandles>;

// The phases' poses and times, found by a search over simulated get-ups (seven figures of strength
// 0.8 to 1.2 on friction 0.6 to 1, 1.6 to 1.9 m tall, arms and legs spread; then four more) and
// checked on 39 lying figures, 35 of them unseen by the search (docs/articulated.md).
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
  double squat_blend_s = 0.3, squat_max_s = 3.0;
  double rise_s = 0.6;
  double ankle_kp = 229, ankle_kv = 86;  // deg per m, per m/s (balance's 4 rad/m and 1.5 rad·s/m)
  double hip_kp = 168, hip_kv = 19;
  double lift = 0.2;      // m: the pelvis this far above the feet has left the ground
  double sat = 0.12;      // m: this close, it sits again
  double settle = 0.05;   // m: the squat's offset before it rises
};

const Params kParams;
const Handles kStanding{0, 0, 0, 0, 0, 0, 0};

void set(std::vector<std::vector<double>>& targets, int link, std::vector<double> v) {
  if (link >= 0) targets[static_cast<std::size_t>(link)] = std::move(v);
}

// The roll onto the back: each joint's target (deg; a ball's rotation vector), reached linearly
// over roll_s, held for hold_s and let go over back_s (found by the same search: 99 of 108 prone
// figures of strength 0.7 to 1.3, friction 0.5 to 1.2, 1.55 to 2 m lie on their backs after one
// roll; the rest are weak on high friction and roll again).
struct RollPose {
  double abdomen_twist = -37.3, chest_twist = 11.5, head_twist = -35.7;
  Vec3 upper_arm_r{-101, 0, 120}, upper_arm_l{4.8, 0, 18.1}, thigh_r{-67.8, 0, -16.5}, thigh_l{-90, 0, 0};
  double shin_r = 11.6;
  double roll_s = 0.7, hold_s = 0.2, back_s = 0.5;
};
const RollPose kRoll;

void applyRoll(const HumanRoles& l, double w, std::vector<std::vector<double>>& targets) {
  const RollPose& R = kRoll;
  const double d = w * kPi / 180.0;
  auto ball = [&](int link, const Vec3& v) { set(targets, link, {d * v.x(), d * v.y(), d * v.z()}); };
  for (int link : {l.abdomen, l.chest, l.head, l.upper_arm_l, l.upper_arm_r, l.thigh_l, l.thigh_r})
    ball(link, Vec3::Zero());
  for (int link : {l.shin_l, l.forearm_l, l.forearm_r}) set(targets, link, {0.0});
  for (int link : {l.foot_l, l.foot_r}) set(targets, link, {0.0, 0.0});
  ball(l.abdomen, Vec3(0, R.abdomen_twist, 0));
  ball(l.chest, Vec3(0, R.chest_twist, 0));
  ball(l.head, Vec3(0, R.head_twist, 0));
  ball(l.upper_arm_r, R.upper_arm_r);
  ball(l.upper_arm_l, R.upper_arm_l);
  ball(l.thigh_r, R.thigh_r);
  ball(l.thigh_l, R.thigh_l);
  set(targets, l.shin_r, {d * R.shin_r});
}

Handles blend(const Handles& a, const Handles& b, double s) {
  s = std::clamp(s, 0.0, 1.0);
  s = s * s * (3 - 2 * s);
  Handles r;
  for (int i = 0; i < kHandles; ++i) r[static_cast<std::size_t>(i)] = (1 - s) * a[static_cast<std::size_t>(i)] + s * b[static_cast<std::size_t>(i)];
  return r;
}

// Every joint's target from the handles (both sides alike), and the ankles' roll (deg, both feet).
void apply(const HumanRoles& l, const Handles& p, double roll, std::vector<std::vector<double>>& targets) {
  const double d = kPi / 180.0;
  const double spine = p[Spine] * d;
  set(targets, l.abdomen, {spine * 35.0 / 65.0, 0, 0});
  set(targets, l.chest, {spine * 30.0 / 65.0, 0, 0});
  set(targets, l.head, {p[Neck] * d, 0, 0});
  for (int thigh : {l.thigh_l, l.thigh_r}) set(targets, thigh, {-p[Hip] * d, 0, 0});
  for (int shin : {l.shin_l, l.shin_r}) set(targets, shin, {p[Knee] * d});
  for (int foot : {l.foot_l, l.foot_r}) set(targets, foot, {p[Ankle] * d, roll * d});
  for (int arm : {l.upper_arm_l, l.upper_arm_r}) set(targets, arm, {-p[Shoulder] * d, 0, 0});
  for (int fore : {l.forearm_l, l.forearm_r}) set(targets, fore, {-p[Elbow] * d});
}

}  // namespace

bool standUp(const HumanRoles& l, const ControllersDesc& c, const ControlInput& in, StandUpState& s,
             std::vector<std::vector<double>>& targets) {
  if (!c.stand_up || !l.complete()) return false;
  const Params& P = kParams;
  const ArtKinematics& k = *in.k;
  const Vec3 up = in.up();
  auto at = [&](int link) { return k.x[static_cast<std::size_t>(link)]; };
  const Vec3 &com = in.com, &vcom = in.vcom;
  const Vec3 feet = 0.5 * (at(l.foot_l) + at(l.foot_r));
  const double pelvis_h = (at(l.pelvis) - feet).dot(up);
  // The centre of mass's offset from the feet's centre and its velocity, along the pelvis's heading
  // (d, dv) and to its left (e, ev).
  const Vec3 forward = heading(k.R[static_cast<std::size_t>(l.pelvis)], up), side = up.cross(forward);
  const double d = (com - feet).dot(forward), dv = vcom.dot(forward);
  const double e = (com - feet).dot(side), ev = vcom.dot(side);
  auto enter = [&](StandUpPhase next, const Handles& from) {
    s.phase = static_cast<int>(next);
    s.since = in.t;
    std::copy(from.begin(), from.end(), s.from);
  };
  auto phaseIs = [&](StandUpPhase p) { return s.phase == static_cast<int>(p); };
  auto idle = [&] {
    s.phase = static_cast<int>(StandUpPhase::Idle);
    s.still_since = -1;
    return false;
  };

  if (phaseIs(StandUpPhase::Idle)) {
    // Pre-condition: lying (the chest level with the pelvis) on its back or front (the chest facing
    // up or down), still.
    const double facing = k.R[static_cast<std::size_t>(l.chest)].col(2).dot(up);
    const bool lying = std::abs((at(l.chest) - at(l.pelvis)).dot(up)) < 0.2 && std::abs(facing) > 0.5;
    if (!lying || vcom.norm() > 0.25) return idle();
    if (s.still_since < 0) s.still_since = in.t;
    if (in.t - s.still_since < c.stand_up_wait) return false;
    enter(facing > 0 ? StandUpPhase::Curl : StandUpPhase::Roll, kStanding);
  }
  if (phaseIs(StandUpPhase::Roll)) {
    const RollPose& R = kRoll;
    const double tau = in.t - s.since;
    if (tau >= R.roll_s + R.hold_s + R.back_s) return idle();
    const double w = tau < R.roll_s ? tau / R.roll_s : tau < R.roll_s + R.hold_s ? 1.0 : 1.0 - (tau - R.roll_s - R.hold_s) / R.back_s;
    applyRoll(l, w, targets);
    return true;
  }
  // Risen (squat, rise, stand) and fallen: the centre of mass low over the feet or far off them.
  const bool risen = phaseIs(StandUpPhase::Squat) || phaseIs(StandUpPhase::Rise) || phaseIs(StandUpPhase::Stand);
  if (risen && ((com - feet).dot(up) < 0.25 || std::hypot(d, e) > 0.3)) return idle();
  Handles from;
  std::copy(s.from, s.from + kHandles, from.begin());
  const double tau = in.t - s.since;
  // The phase's pose (base), then with the feedback of the risen phases (pose), faded in over the
  // squat's blend so it does not jump the targets.
  Handles base = kStanding;
  switch (static_cast<StandUpPhase>(s.phase)) {
    case StandUpPhase::Curl: base = blend(from, P.curl, tau / P.curl_s); break;
    case StandUpPhase::Sit: base = blend(from, P.sit, tau / P.sit_s); break;
    case StandUpPhase::Tuck: base = blend(from, P.tuck, tau / P.tuck_s); break;
    case StandUpPhase::Rock: base = blend(from, P.rock, tau / P.rock_blend_s); break;
    case StandUpPhase::Squat: base = blend(from, P.squat, tau / P.squat_blend_s); break;
    case StandUpPhase::Rise: base = blend(from, kStanding, tau / P.rise_s); break;
    default: break;
  }
  Handles pose = base;
  double roll = 0.0;
  if (risen) {
    const double gain = phaseIs(StandUpPhase::Squat) ? std::clamp(tau / P.squat_blend_s, 0.0, 1.0) : 1.0;
    pose[Ankle] += gain * (P.ankle_kp * d + P.ankle_kv * dv);
    pose[Hip] -= gain * (P.hip_kp * d + P.hip_kv * dv);
    roll = -gain * (P.ankle_kp * e + P.ankle_kv * ev);
  }
  // Another try: from the tuck while it still sits up, from the curl when it lies back.
  auto retry = [&] {
    const bool sitting = (at(l.chest) - at(l.pelvis)).dot(up) > 0.2;
    enter(sitting ? StandUpPhase::Tuck : StandUpPhase::Curl, pose);
  };
  switch (static_cast<StandUpPhase>(s.phase)) {
    case StandUpPhase::Curl:
      if (tau >= P.curl_s) enter(StandUpPhase::Sit, base);
      break;
    case StandUpPhase::Sit:
      if (tau >= P.sit_s) enter(StandUpPhase::Tuck, base);
      break;
    case StandUpPhase::Tuck:
      if (tau >= P.tuck_s) enter(StandUpPhase::Rock, base);
      break;
    case StandUpPhase::Rock:
      if (pelvis_h > P.lift && in.left_down && in.right_down) enter(StandUpPhase::Squat, base);
      else if (tau >= P.rock_max_s) retry();
      break;
    case StandUpPhase::Squat:
      if (pelvis_h < P.sat || tau >= P.squat_max_s) retry();
      else if (tau > P.squat_blend_s && std::abs(d) < P.settle && std::abs(dv) < 0.2) enter(StandUpPhase::Rise, base);
      break;
    case StandUpPhase::Rise:
      if (pelvis_h < P.sat) retry();
      else if (tau >= P.rise_s) enter(StandUpPhase::Stand, kStanding);
      break;
    default:
      break;
  }
  apply(l, pose, roll, targets);
  return true;
}

}  // namespace reel
