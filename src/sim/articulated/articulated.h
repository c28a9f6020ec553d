// Articulated bodies in reduced coordinates: a tree of rigid links whose state is the joints'
// coordinates q and velocities v, so the joints hold by construction.
//
// Dynamics (Featherstone, "Rigid Body Dynamics Algorithms", Springer 2008): spatial vectors in
// world coordinates about the world origin (ch. 2; motion [ω; v_O], force [n_O; f]); the bias
// forces C(q, v) by the recursive Newton–Euler algorithm (ch. 5.3) with gravity as a base
// acceleration; the joint-space inertia M(q) by the composite-rigid-body algorithm (ch. 6.2),
// factorised by Cholesky, as MuJoCo and RBDL do. Joint velocities: a hinge's and a universal's
// angle rates, a ball's angular velocity in the child's frame, the free root's spatial velocity
// (so its motion subspace is the identity).
//
// A step (semi-implicit, "stable PD": Tan, Liu & Turk, "Stable Proportional-Derivative
// Controllers", IEEE CG&A 31(4), 2011): servos and joint damping act at the end of the step, so
// (M + h·(D + K_d) + h²·K_p)·a = τ − C − K_p·(e + h·v) − (K_d + D)·v stays stable at any gain and
// step. Then contacts (with Coulomb friction) and joint limits as velocity constraints solved by
// projected Gauss–Seidel on the same matrix (impulses J^T·λ through M̃⁻¹J^T: Stewart & Trinkle,
// IJNME 39, 1996; Anitescu & Potra 1997), and the coordinates move with the new velocities.
// With the scene's `rk4` integrator the smooth dynamics take a classical Runge–Kutta step instead
// (servos explicit), for accuracy tests; constraints act after it.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/scene/articulated.h"
#include "core/scene/material.h"
#include "core/types.h"
#include "sim/rigid/contact.h"

namespace reel {

using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;
using VecX = Eigen::VectorXd;
using MatX = Eigen::MatrixXd;

struct ArtJoint {
  JointType type = JointType::Fixed;
  int parent = -1;      // link index
  int qi = 0, nq = 0;   // its coordinates in q (free: x, quaternion w x y z; ball: quaternion)
  int vi = 0, nv = 0;   // its velocities in v
  Vec3 axis{0, 0, 1}, axis2{1, 0, 0}, anchor{0, 0, 0}, parent_anchor{0, 0, 0};
  std::vector<double> lower, upper;  // rad per velocity coordinate (hinge, universal); empty: none
  double cone = 0.0;                 // ball: largest angle, rad (0: none)
  double damping = 0.0;              // N·m·s/rad
  double armature = 0.0;             // kg·m² on the mass matrix's diagonal, per velocity
  ServoDesc servo;
  std::vector<double> target;        // rad per velocity coordinate (ball: rotation vector)
  Mat3 R_fixed = Mat3::Identity();   // a fixed root's pose
  Vec3 x_fixed{0, 0, 0};
};

struct ArtLink {
  std::string name;
  double mass = 1.0;                  // kg
  Mat3 inertia = Mat3::Identity();    // about the centre of mass, link frame, kg·m²
  ConvexShape shape;                  // link frame
  double extent = 0.0;                // farthest surface point from the centre of mass, m
  Surface surface;
  std::size_t collider = 0;
  Vec3 pivot{0, 0, 0};                // the collider's reference point, link frame
  Mat3 axes0 = Mat3::Identity();      // the collider's authored frame (the link's start frame)
};

struct ArticulatedModel {
  std::vector<ArtJoint> joints;  // per link: its joint to its parent
  std::vector<ArtLink> links;
  int nq = 0, nv = 0;
  int iterations = 30;
  std::vector<PoseKey> poses;
  std::vector<PushDesc> pushes;
  bool gravity_compensation = false;
  ControllersDesc controllers;
};

struct ArticulatedState {
  VecX q, v;
};

// What the dynamics compute from a state (scratch).
struct ArtKinematics {
  std::vector<Mat3> R;   // link frames
  std::vector<Vec3> x;   // centres of mass
  std::vector<Vec3> p;   // joint points (world)
  Eigen::Matrix<double, 6, Eigen::Dynamic> S;  // motion subspace, world, one column per velocity
  std::vector<Vec6> vel, bias;  // link spatial velocities; Ṡ·v of each joint
  std::vector<Mat6> I;          // spatial inertias (world, about the origin)
};

// Link poses, joint points and motion subspace at q.
void forwardKinematics(const ArticulatedModel& m, const VecX& q, ArtKinematics& k);
// Link velocities and the joints' Ṡ·v at v (after forwardKinematics).
void linkVelocities(const ArticulatedModel& m, const VecX& v, ArtKinematics& k);
// M(q) by the composite-rigid-body algorithm.
void massMatrix(const ArticulatedModel& m, const ArtKinematics& k, MatX& M);
// C(q, v): the generalised forces that give zero acceleration (gravity, Coriolis, centrifugal),
// less the external spatial forces f_ext per link (world, about the origin).
void biasForces(const ArticulatedModel& m, const ArtKinematics& k, const Vec3& gravity, const std::vector<Vec6>& f_ext,
                VecX& C);

// q moved by velocities v over h (quaternions by the exponential map), normalised.
void integrateCoordinates(const ArticulatedModel& m, VecX& q, const VecX& v, double h);

// The servo error of every velocity coordinate: θ − θ̄ (a ball's: the rotation vector from its target).
void servoErrors(const ArticulatedModel& m, const VecX& q, const std::vector<std::vector<double>>& targets, VecX& e);

// A joint's angles (hinge 1, universal 2, ball 3: its rotation vector in the child's frame; free:
// none) from q.
std::vector<double> jointAngles(const ArticulatedModel& m, const VecX& q, int link);

// Spatial velocity of a point of link i (world): the velocity of the point now at `at`.
inline Vec3 pointVelocity(const Vec6& vel, const Vec3& at) { return vel.tail<3>() + vel.head<3>().cross(at); }

// Kinetic and potential (gravity) energy, J.
double kineticEnergy(const ArticulatedModel& m, const ArtKinematics& k);
double potentialEnergy(const ArticulatedModel& m, const ArtKinematics& k, const Vec3& gravity);

// The servo targets at time t: each joint's rest target, then the pose keys.
void servoTargets(const ArticulatedModel& m, double t, std::vector<std::vector<double>>& targets);

// One step of the smooth dynamics and servos, leaving v* and the matrix the constraints use:
// fills `Mt` (M + the implicit terms, Cholesky-factorised in `llt`) and v_star. `rk4`: the smooth
// part by Runge–Kutta (q advanced too; returns true), else semi-implicit (q not moved; false).
struct ArtScratch {
  ArtKinematics k;
  MatX M, Mt, W, J;
  VecX C, rhs, e, diag;
  Eigen::LLT<MatX> llt;
  std::vector<Vec6> f_ext;
  std::vector<std::vector<double>> targets;
};

}  // namespace reel
