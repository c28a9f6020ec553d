#include "core/figure.h"

#include <cmath>

#include <Eigen/Geometry>

#include "core/math.h"
#include "core/mesh.h"

namespace reel {

Mat3 jointRotation(const ArticulatedJointDesc& j, std::span<const double> a) {
  switch (j.type) {
    case JointType::Hinge:
      return Eigen::AngleAxisd(a[0], j.axis).toRotationMatrix();
    case JointType::Universal:
      return Eigen::AngleAxisd(a[0], j.axis).toRotationMatrix() * Eigen::AngleAxisd(a[1], j.axis2).toRotationMatrix();
    case JointType::Ball: {
      const Vec3 r(a[0], a[1], a[2]);
      const double angle = r.norm();
      return angle > 0 ? Mat3(Eigen::AngleAxisd(angle, r / angle).toRotationMatrix()) : Mat3::Identity();
    }
    case JointType::Free:
    case JointType::Fixed:
      break;
  }
  return Mat3::Identity();
}

void startPoses(const ArticulatedDesc& d, std::vector<Mat3>& R, std::vector<Vec3>& x) {
  R.assign(d.links.size(), Mat3::Identity());
  x.assign(d.links.size(), Vec3::Zero());
  for (std::size_t i = 0; i < d.links.size(); ++i) {
    const ArticulatedLinkDesc& l = d.links[i];
    if (l.parent < 0) {
      R[i] = d.rotation;
      x[i] = d.position;
      continue;
    }
    const auto p = static_cast<std::size_t>(l.parent);
    R[i] = R[p] * jointRotation(l.joint, l.joint.angles);
    x[i] = x[p] + R[p] * l.joint.parent_anchor - R[i] * l.joint.anchor;
  }
}

ObjectDesc linkObject(const ArticulatedLinkDesc& l, const Mat3& R, const Vec3& x, const std::string& body) {
  ObjectDesc o;
  o.name = body + "/" + l.name;
  o.free_body = true;
  o.material = l.material;
  const Mat3 Rs = R * l.shape.rotation;
  const Vec3 c = x + R * l.shape.offset;
  switch (l.shape.kind) {
    case LinkShape::Kind::Sphere:
      o.shape = SphereShape{c, l.shape.radius};
      break;
    case LinkShape::Kind::Box:
      o.shape = BoxShape{c, l.shape.size, eulerDegFromRotation(Rs)};
      break;
    case LinkShape::Kind::Capsule: {
      const Vec3 half = Rs * Vec3(0, 0.5 * l.shape.length, 0);
      o.shape = CapsuleShape{c - half, c + half, l.shape.radius};
      break;
    }
    case LinkShape::Kind::Cylinder:
      o.shape = MeshObjectShape{"cylinder", std::make_shared<TriMesh>(makeCylinder(l.shape.radius, l.shape.length, 32)), c,
                                Vec3(1, 1, 1), eulerDegFromRotation(Rs)};
      break;
    case LinkShape::Kind::Mesh:
      o.shape = MeshObjectShape{"mesh", l.shape.mesh, c, l.shape.scale, eulerDegFromRotation(Rs)};
      break;
  }
  return o;
}

MassProperties linkMass(const LinkShape& s, double density) {
  MassProperties m;
  switch (s.kind) {
    case LinkShape::Kind::Sphere: m = sphereMass(s.radius, density); break;
    case LinkShape::Kind::Box: m = boxMass(s.size, density); break;
    case LinkShape::Kind::Capsule: m = capsuleMass(s.length, s.radius, density); break;
    case LinkShape::Kind::Cylinder: m = cylinderMass(s.radius, s.length, density); break;
    case LinkShape::Kind::Mesh: return {};
  }
  return placed(m, s.rotation, s.offset);
}

namespace {

constexpr double kDeg = kPi / 180.0;

}  // namespace

double humanRootHeight(double height) { return 0.575 * height; }

std::vector<ArticulatedLinkDesc> humanFigure(double H, double M, double strength) {
  std::vector<ArticulatedLinkDesc> links;
  // Gains of a 70 kg, 1.75 m figure, scaled by mass × height (a torque against gravity).
  const double gain = strength * (M / 70.0) * (H / 1.75);
  // Heights above the soles of each link's centre (rest pose), for the joints' anchors.
  std::vector<Vec3> centre;
  auto add = [&](const char* name, int parent, LinkShape shape, double fraction, const Vec3& at, JointType type,
                 const Vec3& joint_at, double kp, double max_torque) {
    ArticulatedLinkDesc l;
    l.name = name;
    l.parent = parent;
    l.shape = shape;
    l.mass = withMass(linkMass(shape, 1000.0), fraction * M);
    l.joint.type = type;
    if (parent >= 0) {
      l.joint.anchor = joint_at - at;
      l.joint.parent_anchor = joint_at - centre[static_cast<std::size_t>(parent)];
      l.joint.angles.assign(static_cast<std::size_t>(jointDofs(type)), 0.0);
      l.joint.servo.kp = gain * kp;
      l.joint.servo.kd = 0.1 * gain * kp;
      l.joint.servo.max_torque = strength > 0 ? gain * max_torque : 0.0;
      l.joint.damping = 0.02 * kp * (M / 70.0) * (H / 1.75);  // the tissue's, even in a rag doll
    }
    centre.push_back(at);
    links.push_back(l);
    return static_cast<int>(links.size()) - 1;
  };
  auto box = [&](double x, double y, double z) {
    LinkShape s;
    s.kind = LinkShape::Kind::Box;
    s.size = H * Vec3(x, y, z);
    return s;
  };
  // A capsule between two joints `length` apart (fractions of H), of radius r: its caps end at the joints.
  auto limb = [&](double length, double r) {
    LinkShape s;
    s.kind = LinkShape::Kind::Capsule;
    s.radius = r * H;
    s.length = std::max(0.0, (length - 2.0 * r) * H);
    return s;
  };
  auto hinge = [&](int link, const Vec3& axis, double lo_deg, double hi_deg) {
    ArticulatedJointDesc& j = links[static_cast<std::size_t>(link)].joint;
    j.axis = axis;
    j.lower = {lo_deg * kDeg};
    j.upper = {hi_deg * kDeg};
  };
  auto universal = [&](int link, double lo1, double hi1, double lo2, double hi2) {
    ArticulatedJointDesc& j = links[static_cast<std::size_t>(link)].joint;
    j.axis = Vec3::UnitX();
    j.axis2 = Vec3::UnitZ();
    j.lower = {lo1 * kDeg, lo2 * kDeg};
    j.upper = {hi1 * kDeg, hi2 * kDeg};
  };
  auto cone = [&](int link, double deg) { links[static_cast<std::size_t>(link)].joint.cone = deg * kDeg; };
  const auto Y = [&](double x, double y, double z) { return Vec3(x * H, y * H, z * H); };
  LinkShape head;
  head.kind = LinkShape::Kind::Sphere;
  head.radius = 0.062 * H;

  const int pelvis = add("pelvis", -1, box(0.17, 0.09, 0.10), 0.142, Y(0, 0.575, 0), JointType::Free, Vec3::Zero(), 0, 0);
  const int abdomen = add("abdomen", pelvis, box(0.16, 0.08, 0.09), 0.139, Y(0, 0.66, 0), JointType::Ball, Y(0, 0.62, 0), 600, 400);
  cone(abdomen, 35);
  const int chest = add("chest", abdomen, box(0.19, 0.12, 0.10), 0.216, Y(0, 0.76, 0), JointType::Ball, Y(0, 0.70, 0), 600, 400);
  cone(chest, 30);
  const int neck = add("head", chest, head, 0.081, Y(0, 0.905, 0), JointType::Ball, Y(0, 0.835, 0), 60, 50);
  cone(neck, 50);
  for (int side : {1, -1}) {
    const double s = side;
    const bool left = side > 0;
    const double ax = s * 0.118;
    const int upper = add(left ? "upper_arm_l" : "upper_arm_r", chest, limb(0.188, 0.024), 0.028, Y(ax, 0.724, 0),
                          JointType::Ball, Y(ax, 0.808, 0), 120, 120);
    cone(upper, 150);
    const int fore = add(left ? "forearm_l" : "forearm_r", upper, limb(0.145, 0.019), 0.016, Y(ax, 0.5575, 0),
                         JointType::Hinge, Y(ax, 0.630, 0), 60, 60);
    hinge(fore, Vec3::UnitX(), -150, 0);  // bends forward: the hand toward +z
    const int hand = add(left ? "hand_l" : "hand_r", fore, box(0.028, 0.09, 0.05), 0.006, Y(ax, 0.44, 0),
                         JointType::Universal, Y(ax, 0.485, 0), 10, 10);
    universal(hand, -70, 70, -30, 30);
  }
  for (int side : {1, -1}) {
    const double s = side;
    const bool left = side > 0;
    const double lx = s * 0.052;
    const int thigh = add(left ? "thigh_l" : "thigh_r", pelvis, limb(0.245, 0.036), 0.100, Y(lx, 0.4075, 0),
                          JointType::Ball, Y(lx, 0.530, 0), 600, 400);
    cone(thigh, 120);
    const int shin = add(left ? "shin_l" : "shin_r", thigh, limb(0.246, 0.028), 0.0465, Y(lx, 0.162, 0),
                         JointType::Hinge, Y(lx, 0.285, 0), 500, 400);
    hinge(shin, Vec3::UnitX(), 0, 150);  // bends backward: the foot toward −z
    const int foot = add(left ? "foot_l" : "foot_r", shin, box(0.055, 0.039, 0.152), 0.0145, Y(lx, 0.0195, 0.036),
                         JointType::Universal, Y(lx, 0.039, 0), 300, 200);
    universal(foot, -45, 30, -20, 20);
  }
  return links;
}

}  // namespace reel
