// A human figure's controllers, chosen each step by a supervisor as in Faloutsos, van de Panne &
// Terzopoulos, "Composable Controllers for Physics-Based Character Animation", SIGGRAPH 2001: each
// controller has a pre-condition (the states it can handle); the first in the list whose
// pre-condition holds acts (its post-condition is that of the next: balance hands over to protect
// when the centre of mass leaves the feet), and the fallback is the pose keys (or the rest pose).
// The stand-up (stand_up.h) comes first in the list: while it acts, the others wait.
//
//  - balance: while both feet touch and the centre of mass is over the support polygon (with a
//    margin), the ankles' servo targets lean against the centre of mass's offset from the support's
//    centre and its velocity, θ̄_ankle += k_p·d + k_v·ḋ in the pelvis's heading frame (the ankle
//    strategy; Yin, Loken & van de Panne, "SIMBICON", SIGGRAPH 2007, use the same feedback for
//    foot placement).
//  - protect: while the figure falls (its centre of mass outside the support, or no foot touching,
//    and the chest still high), the arms reach toward the fall and the elbows give, to take the
//    impact on the hands (the stuntman paper's protective reaction).
#pragma once

#include <vector>

#include "core/scene/articulated.h"
#include "core/types.h"
#include "sim/articulated/articulated.h"

namespace reel {

// The human figure's links the controllers move (indices, −1: not a human figure).
struct HumanRoles {
  int pelvis = -1, abdomen = -1, chest = -1, head = -1, foot_l = -1, foot_r = -1, upper_arm_l = -1, upper_arm_r = -1,
      forearm_l = -1, forearm_r = -1, thigh_l = -1, thigh_r = -1, shin_l = -1, shin_r = -1;
  bool valid() const { return pelvis >= 0 && chest >= 0 && foot_l >= 0 && foot_r >= 0; }
  // Every link the stand-up moves.
  bool complete() const {
    for (int i : {pelvis, abdomen, chest, head, foot_l, foot_r, upper_arm_l, upper_arm_r, forearm_l, forearm_r, thigh_l,
                  thigh_r, shin_l, shin_r})
      if (i < 0) return false;
    return true;
  }
};

HumanRoles humanRoles(const ArticulatedModel& m);

enum class ControllerKind { None = 0, Balance = 1, Protect = 2, StandUp = 3 };

// What the controllers see: the state's kinematics, its centre of mass and the feet's contact
// points last step.
struct ControlInput {
  const ArtKinematics* k = nullptr;
  Vec3 com{0, 0, 0}, vcom{0, 0, 0};                // the whole figure's (centreOfMass)
  const std::vector<Vec3>* foot_points = nullptr;  // world, both feet
  bool left_down = false, right_down = false;
  Vec3 gravity{0, -9.78, 0};
  double t = 0.0;  // the step's end time
  Vec3 up() const { return gravity.norm() > 0 ? Vec3(-gravity.normalized()) : Vec3::UnitY(); }
};

// Picks the controller and adjusts the servo targets; returns the one that acted.
ControllerKind supervise(const ArticulatedModel& m, const HumanRoles& roles, const ControllersDesc& c,
                         const ControlInput& in, std::vector<std::vector<double>>& targets);

// A link's heading on the ground: its forward axis (z) made horizontal, or, where that points
// nearly straight up or down (lying on its back or front), its y axis's opposite made horizontal.
Vec3 heading(const Mat3& R, const Vec3& up);

// The whole figure's centre of mass and its velocity.
void centreOfMass(const ArticulatedModel& m, const ArtKinematics& k, Vec3& c, Vec3& v);

}  // namespace reel
