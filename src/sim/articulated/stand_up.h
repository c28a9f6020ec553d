// The human figure's stand-up from lying on its back, a controller of the composable set (Faloutsos,
// van de Panne & Terzopoulos, "Composable Controllers for Physics-Based Character Animation",
// SIGGRAPH 2001, whose supine-to-stand sits up, tucks and rises over the feet).
//
// A state machine of poses in a few symmetric handles (hip and knee flexion, ankle, spine, neck,
// shoulder, elbow), each phase blending from the last phase's pose to its own:
//   curl → sit (a crunch, then hip flexion: a sit-up) → tuck (the heels pulled to the seat, the arms
//   back) → rock (trunk and arms thrown forward until the seat leaves the ground over the feet) →
//   squat (held, the centre of mass brought over the feet) → rise (the squat blended to standing) →
//   stand (the standing pose under this feedback).
// Lying face down, it first rolls onto its back (the paper's roll-over): the right arm sweeps up and
// across, the trunk and head twist and the right leg crosses over, then all return to rest; lying
// still on its back, it gets up as above (still face down, it rolls again).
// The squat, rise and stand phases close the loop on the centre of mass's offset d from the feet's
// centre along the pelvis's heading and its velocity ḋ: the ankles lean against it as balance does,
// and the hips fold the trunk forward when it lags behind (the hip strategy). Phases end on
// conditions, not clocks alone: a rock that does not lift the seat, or a squat that sits back down
// or does not settle, tries again (from the tuck while it sits, from the curl when it lies back).
#pragma once

#include <vector>

#include "core/scene/articulated.h"
#include "core/types.h"
#include "sim/articulated/articulated.h"
#include "sim/articulated/controllers.h"

namespace reel {

enum class StandUpPhase { Idle = 0, Curl, Sit, Tuck, Rock, Squat, Rise, Stand, Roll };
constexpr int kStandUpLastPhase = static_cast<int>(StandUpPhase::Roll);
constexpr int kStandUpHandles = 7;  // hip, knee, ankle, spine, neck, shoulder, elbow

// The controller's memory, part of the figure's snapshot.
struct StandUpState {
  int phase = 0;           // StandUpPhase
  double since = 0.0;      // s: when the phase began
  double still_since = -1; // s: since when the figure has lain still on its back (−1: it has not)
  double from[kStandUpHandles] = {};  // the handles' pose the phase blends from (deg)
};

// Advances the state machine and, while it acts, writes every joint's servo target; returns
// whether it acted. Risen, it keeps the figure standing (the rest pose under its feedback, in both
// directions, over any pose keys) until it falls: then it idles, and protect takes the fall.
bool standUp(const HumanRoles& roles, const ControllersDesc& c, const ControlInput& in, StandUpState& s,
             std::vector<std::vector<double>>& targets);

}  // namespace reel
