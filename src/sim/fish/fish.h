// The artificial fish of Tu & Terzopoulos ("Artificial Fishes: Physics, Locomotion, Perception,
// Behavior", SIGGRAPH 1994; X. Tu, "Artificial Animals for Computer Animation", PhD thesis,
// University of Toronto, 1996): the biomechanical body, its hydrodynamics and its motor
// controllers. Perception and behaviour are in behaviour.h.
//
// The body: 23 point masses and 91 spring-damper units (thesis §4.1). Node 0 is the nose; nodes
// 1–20 are five rings of four (upper-left, upper-right, lower-right, lower-left, seen from behind
// with left = +x of a fish heading +z, up +y); nodes 21 and 22 are the upper and lower tips of the
// tail. Units: each ring's four edges and two cross struts (6 × 5), between consecutive rings the
// four lengthwise units and the two diagonals of each side face (12 × 4), the nose to ring 1 (4),
// ring 5 to both tail tips (8) and the tail's edge (1). The lengthwise units between rings 2–3,
// 3–4 and 4–5 are the twelve muscles: three segments, each a pair on either side. The two rear
// segments swim, the two front ones turn (thesis §4.1).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/scene/fish.h"
#include "core/types.h"
#include "sim/mass_spring.h"

namespace reel {

inline constexpr int kFishNodes = 23, kFishSprings = 91, kFishTriangles = 42, kFishFaces = 24;

// One fish of length `length` at rest, in its own frame: nose at the origin, heading +z (the tail
// toward −z), up +y, left +x.
struct FishTemplate {
  std::array<Vec3, kFishNodes> x;
  std::array<double, kFishNodes> mass;  // kg
  double total_mass = 0.0;              // kg, the fish's
  Vec3 center_of_mass{0, 0, 0};
  Springs springs;                                  // 91 units
  std::array<int, kFishMuscles> muscle;             // the muscles' unit indices (core/scene/fish.h order)
  std::array<std::array<int, 3>, kFishTriangles> surface;  // counter-clockwise from outside
  // The same surface as the water pushes it: the nose's 4 triangles, 16 quads along the body, the
  // tail's top and bottom wedges and its two flanks (quads), each counter-clockwise from outside;
  // a triangle's fourth corner is −1. A quad's area vector, ½ (p₂ − p₀) × (p₃ − p₁), does not depend
  // on the diagonal that splits it into `surface`'s triangles.
  std::array<std::array<int, 4>, kFishFaces> faces;
};

// Masses from a neutrally buoyant body of the water's density (1000 kg/m³ without water);
// stiffness so that the body's lowest modes lie well above its tail beat (scaling with length as
// mass × frequency², frequencies as 1/length).
FishTemplate makeFishTemplate(double length, double density);

// The largest shortening of a muscle: fully contracted it is this fraction shorter than at rest.
inline constexpr double kMaxContraction = 0.5;

// Motor state of one fish (what a snapshot keeps).
struct FishMotor {
  double phase = 0.0;      // swim oscillator, rad
  double frequency = 0.0;  // tail beats per second now, Hz
  double amplitude = 0.0;  // 0..1
  double speed_error = 0.0;  // ∫(target − actual speed) dt, m (the swim controller's integral)
  double bend = 0.0;       // turn: −1 (full right) .. 1 (full left)
  double pitch = 0.0;      // pectoral fins, rad: + rises
  double yaw = 0.0;        // pectoral fins, rad: the left fin opens (> 0, yaws left) or the right (< 0)
  double brake = 0.0;      // pectoral fins, rad: both opened, when the fish is faster than asked
  std::array<double, kFishMuscles> contraction{};  // 0..1 each
  std::array<double, 3> heading{0, 0, 1};  // the course: the forward axis smoothed over a beat, unit
  std::array<double, 3> turn_from{0, 0, 0};  // a turn by angle: the level course at the last step (0: not begun)
  double turned = 0.0;     // rad turned so far about +y (left +), step by step
  std::int64_t turn_done = 0;  // 1 once a turn by angle is done (a whole word: no padding in snapshots)
};

// What the behaviour (or the drive) asks of the motor controllers.
struct MotorCommand {
  double speed = 0.0;          // m/s (swim-MC); < 0: use frequency and amplitude directly
  double frequency = 0.0, amplitude = 0.0;
  double bend = 0.0;           // turn-MC: −1..1 (left +)
  double pitch = 0.0;          // pectoral fins, rad
  double yaw = 0.0;            // pectoral fins, rad (left +): one fin opened as a brake
};

// The swim and turn motor controllers (thesis §4.4): set the muscles' contractions of one fish
// from its command, advancing its oscillator by h. Swimming: the middle and rear segments contract
// left and right in antiphase, the rear lagging the middle by a quarter beat, so a wave runs to
// the tail; turning: the front and middle segments contract on the side turned to.
void motorControl(const MotorCommand& cmd, double forward_speed, double length, double h, FishMotor& m);

// The course (the forward axis smoothed over about a third of a second, so the swim's wiggle
// does not read as turning), advanced by h.
void trackHeading(FishMotor& m, const Vec3& forward, double h);

// The turn-MC asked to turn by `angle` (rad) to `side` (+1 left): the bend that brings the course
// round, in proportion to what is left of the angle (full at 30° or more), and 0 once turned.
double turnByAngle(FishMotor& m, int side, double angle, double amount);

// Frame of a fish from its nodes: centre (mean of ring centres), forward (unit, tail → nose), up.
struct FishFrame {
  Vec3 center{0, 0, 0}, forward{0, 0, 1}, up{0, 1, 0}, left{1, 0, 0};
  Vec3 mouth{0, 0, 0};
  Vec3 velocity{0, 0, 0};  // mean of the ring nodes
};
FishFrame fishFrame(const Vec3* x, const Vec3* v);

}  // namespace reel
