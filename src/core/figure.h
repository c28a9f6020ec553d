// Figures made by reel: a human of a given height and mass, as the links and joints of an
// articulated body (core/scene/articulated.h).
#pragma once

#include <vector>

#include "core/scene/articulated.h"

namespace reel {

// The 16-link human standing in its rest pose (arms hanging, facing +z, feet on y = 0 when the
// root is at humanRootHeight): pelvis (the root), abdomen, chest, head, upper arms, forearms,
// hands, thighs, shins, feet; 33 joint degrees of freedom (ball waist, chest, neck, shoulders and
// hips; hinge elbows and knees; universal wrists and ankles) with limits.
//
// Segment masses as fractions of the body's (Winter, "Biomechanics and Motor Control of Human
// Movement", 4th ed. 2009, Table 4.1, after Dempster 1955): hand 0.006, forearm 0.016, upper arm
// 0.028, foot 0.0145, leg 0.0465, thigh 0.100, head and neck 0.081, thorax 0.216, abdomen 0.139,
// pelvis 0.142 (they sum to 1). Joint heights and segment lengths as fractions of the height (the
// same book, Fig. 4.1, after Drillis & Contini 1966): shoulder 0.818, elbow 0.630, wrist 0.485,
// hip 0.530, knee 0.285, ankle 0.039; hand 0.108, foot 0.152 long and 0.055 wide, shoulders 0.259
// and hips 0.191 wide. Each link's inertia is its shape's (capsule limbs, box trunk and feet,
// sphere head) at the segment's mass. Servo gains, for a 70 kg, 1.75 m figure scaled by mass ×
// height, hold the standing pose; `strength` multiplies them (0: a rag doll).
std::vector<ArticulatedLinkDesc> humanFigure(double height, double mass, double strength);

// Where the pelvis's centre of mass sits above the soles when the figure stands, m.
double humanRootHeight(double height);

}  // namespace reel
