// Rigid bodies: model (what a body is: mass, inertia, shape), state (pose and motion) and the
// free motion between contacts.
//
// The state is the centre of mass x, the unit quaternion q (body frame → world), the velocity v
// and the angular velocity ω (world). A step is symplectic Euler for the translation and, for the
// rotation, the splitting of the free rigid body's Hamiltonian H = Σ L_i²/(2 I_i) into rotations
// about the principal axes, each solved exactly (Dullweber, Leimkuhler & McLachlan, "Symplectic
// splitting methods for rigid body molecular dynamics", J. Chem. Phys. 107, 1997; Strang order
// 1-2-3-2-1): it keeps |L| exactly and the energy to O(h²) without drift, so a torque-free body
// tumbles for ever and the intermediate axis flips (Dzhanibekov) while the others stay stable.
#pragma once

#include <string>

#include <Eigen/Geometry>

#include "core/scene/material.h"
#include "core/types.h"
#include "sim/rigid/contact.h"

namespace reel {

struct RigidModel {
  std::string name;
  std::size_t collider = 0;  // its object's collider (posed from the state)
  bool kinematic = false;    // fixed or keyed: posed by its collider, infinite mass
  double mass = 1.0, inv_mass = 1.0;   // kg, 1/kg (0 kinematic)
  Mat3 inertia = Mat3::Identity();     // about the centre of mass, body frame, kg·m²
  Mat3 principal = Mat3::Identity();   // columns: the principal axes in the body frame
  Vec3 moments{1, 1, 1};               // principal moments, kg·m²
  Mat3 axes0 = Mat3::Identity();       // the body frame at t = 0 (world)
  Vec3 center0{0, 0, 0};               // the centre of mass at t = 0 (world), m
  Vec3 pivot{0, 0, 0};                 // the collider's pivot in the body frame, m
  ConvexShape shape;                   // body frame, about the centre of mass
  double extent = 0.0;                 // farthest surface point from the centre of mass, m
  Surface surface;
  Vec3 force{0, 0, 0}, torque{0, 0, 0};  // constant external force (N) and torque (N·m), world
  double linear_damping = 0.0, angular_damping = 0.0;  // 1/s
  double sleep_time = 0.5;  // s at rest before it may sleep; 0: never
};

struct RigidState {
  Vec3 x{0, 0, 0};  // centre of mass, m
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();  // body frame → world, unit
  Vec3 v{0, 0, 0};  // m/s
  Vec3 w{0, 0, 0};  // rad/s, world
  double rest = 0.0;  // s it has been slow (sleeping)
  bool asleep = false;
};

// A polytope carried by x ↦ R·x + t.
ConvexPolytope transformedPolytope(const ConvexPolytope& p, const Mat3& R, const Vec3& t);

// World-frame inverse inertia (zero for a kinematic body).
inline Mat3 inverseInertia(const RigidModel& m, const RigidState& s) {
  if (m.kinematic) return Mat3::Zero();
  const Mat3 P = s.q.toRotationMatrix() * m.principal;
  return P * m.moments.cwiseInverse().asDiagonal() * P.transpose();
}

// The free rotation over h (see above): q and ω change, L = I·ω (world) is kept.
void rotateFree(const RigidModel& m, RigidState& s, double h);

// Kinetic energy, J, and angular momentum about the centre of mass (world), kg·m²/s.
double kineticEnergy(const RigidModel& m, const RigidState& s);
Vec3 angularMomentum(const RigidModel& m, const RigidState& s);

}  // namespace reel
