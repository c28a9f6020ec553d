#include "io/scene/urdf.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "core/math.h"
#include "io/scene/robot_xml.h"

namespace reel::io {
namespace {

// <origin xyz rpy>: rpy is roll, pitch, yaw about fixed x, y, z (R = Rz·Ry·Rx).
Frame originOf(const XmlElement* o) {
  Frame f;
  if (!o) return f;
  const auto xyz = numbers(*o, "xyz", 3, {0, 0, 0}), rpy = numbers(*o, "rpy", 3, {0, 0, 0});
  f.p = Vec3(xyz[0], xyz[1], xyz[2]);
  f.R = (Eigen::AngleAxisd(rpy[2], Vec3::UnitZ()) * Eigen::AngleAxisd(rpy[1], Vec3::UnitY()) *
         Eigen::AngleAxisd(rpy[0], Vec3::UnitX()))
            .toRotationMatrix();
  return f;
}

std::string nameOf(const XmlElement& e) {
  const std::string* n = e.attribute("name");
  if (!n || n->empty()) refuse(e, "<" + e.name + "> needs a name");
  if (n->find('/') != std::string::npos) refuse(e, "<" + e.name + "> name \"" + *n + "\" may not contain '/'");
  return *n;
}

// A link's shape from its <collision> (else <visual>) at frame `at` (root frame), about centre c.
LinkShape shapeOf(const XmlElement& link, const Frame& at, const Vec3& c, const MeshLoader& load) {
  const XmlElement* g = child(link, "collision");
  int collisions = 0;
  for (const XmlElement& e : link.children)
    if (e.name == "collision" && ++collisions == 2) refuse(e, "a second <collision> in one link is outside the supported subset (one shape per link)");
  if (!g) g = child(link, "visual");
  LinkShape s;
  if (!g) {  // no geometry: a small sphere at the centre of mass, so it is drawn and met
    s.kind = LinkShape::Kind::Sphere;
    s.radius = 0.005;
    return s;
  }
  onlyChildren(*g, {"origin", "geometry"}, {"material"});
  const Frame f = at * originOf(child(*g, "origin"));
  const XmlElement* geometry = child(*g, "geometry");
  if (!geometry || geometry->children.size() != 1) refuse(*g, "<" + g->name + "> needs a <geometry> with one shape");
  const XmlElement& shape = geometry->children.front();
  s.offset = f.p - c;
  s.rotation = f.R;
  // URDF's cylinders and capsules lie along z; reel's along y.
  const Mat3 z_from_y = Eigen::AngleAxisd(kPi / 2, Vec3::UnitX()).toRotationMatrix();
  auto positive = [&](const std::string& key) {
    const double v = number(shape, key);
    if (!(v > 0)) refuse(shape, "<" + shape.name + "> " + key + " must be > 0");
    return v;
  };
  if (shape.name == "box") {
    const auto sz = numbers(shape, "size", 3, {});
    for (double x : sz)
      if (!(x > 0)) refuse(shape, "<box> size must be > 0");
    s.kind = LinkShape::Kind::Box;
    s.size = Vec3(sz[0], sz[1], sz[2]);
  } else if (shape.name == "sphere") {
    s.kind = LinkShape::Kind::Sphere;
    s.radius = positive("radius");
  } else if (shape.name == "cylinder" || shape.name == "capsule") {
    s.kind = shape.name == "cylinder" ? LinkShape::Kind::Cylinder : LinkShape::Kind::Capsule;
    s.radius = positive("radius");
    s.length = positive("length");
    s.rotation = f.R * z_from_y;
  } else if (shape.name == "mesh") {
    const std::string* file = shape.attribute("filename");
    if (!file || file->empty()) refuse(shape, "<mesh> needs a filename");
    if (file->find("://") != std::string::npos) refuse(shape, "<mesh> \"" + *file + "\": only paths relative to the URDF are read (no package:// or file://)");
    const auto scale = numbers(shape, "scale", 3, {1, 1, 1});
    for (double x : scale)
      if (!(x > 0)) refuse(shape, "<mesh> scale must be > 0");
    auto m = load(*file);
    if (!m.ok()) refuse(shape, "<mesh> \"" + *file + "\": " + m.error().headline());
    s.kind = LinkShape::Kind::Mesh;
    s.mesh = m.value();
    s.scale = Vec3(scale[0], scale[1], scale[2]);
  } else {
    refuse(shape, "<" + shape.name + "> geometry is outside the supported URDF subset (box, sphere, cylinder, capsule, mesh)");
  }
  return s;
}

}  // namespace

Result<std::vector<ArticulatedLinkDesc>> urdfLinks(const XmlElement& robot, Vec3& root_offset, const MeshLoader& mesh) {
  try {
    if (robot.name != "robot") refuse(robot, "expected <robot>, found <" + robot.name + ">");
    std::map<std::string, const XmlElement*> links;
    std::vector<const XmlElement*> joints, link_order;
    for (const XmlElement& e : robot.children) {
      if (e.name == "link") {
        const std::string n = nameOf(e);
        if (!links.emplace(n, &e).second) refuse(e, "a second link named \"" + n + "\"");
        link_order.push_back(&e);
      } else if (e.name == "joint") {
        joints.push_back(&e);
      } else if (e.name != "material" && e.name != "gazebo" && e.name != "transmission") {
        refuse(e, "<" + e.name + "> is outside the supported URDF subset");
      }
    }
    if (links.empty()) refuse(robot, "the robot has no <link>");
    // Each joint: parent → child; a link is the child of one joint at most.
    std::map<std::string, const XmlElement*> joint_of;  // child link → joint
    std::map<std::string, std::vector<std::string>> children;
    for (const XmlElement* j : joints) {
      nameOf(*j);
      const XmlElement* p = child(*j, "parent");
      const XmlElement* c = child(*j, "child");
      if (!p || !p->attribute("link") || !c || !c->attribute("link")) refuse(*j, "<joint> needs <parent link> and <child link>");
      const std::string& pn = *p->attribute("link");
      const std::string& cn = *c->attribute("link");
      if (!links.count(pn)) refuse(*p, "no link \"" + pn + "\"");
      if (!links.count(cn)) refuse(*c, "no link \"" + cn + "\"");
      if (!joint_of.emplace(cn, j).second) refuse(*j, "link \"" + cn + "\" is the child of a second joint");
      children[pn].push_back(cn);
    }
    std::vector<std::string> roots;
    for (const XmlElement* l : link_order)
      if (!joint_of.count(*l->attribute("name"))) roots.push_back(*l->attribute("name"));
    if (roots.size() != 1)
      refuse(roots.empty() ? robot : *links[roots[1]],
             roots.empty() ? "no root link: the joints form a cycle" : "a second root link \"" + roots[1] + "\" (every link but one is a joint's child)");
    // Parents first, from the root; every link's frame and centre of mass at the zero pose.
    std::vector<std::string> order{roots[0]};
    for (std::size_t k = 0; k < order.size(); ++k)
      for (const std::string& c : children[order[k]]) order.push_back(c);
    if (order.size() != links.size())
      for (const XmlElement* l : link_order)
        if (std::find(order.begin(), order.end(), *l->attribute("name")) == order.end())
          refuse(*l, "link \"" + *l->attribute("name") + "\" is its own ancestor: the joints form a cycle");
    std::map<std::string, Frame> frame;
    std::map<std::string, Vec3> centre;
    std::map<std::string, int> index;
    std::vector<ArticulatedLinkDesc> out;
    for (const std::string& n : order) {
      const XmlElement& le = *links[n];
      onlyChildren(le, {"inertial", "visual", "collision"}, {});
      ArticulatedLinkDesc l;
      l.name = n;
      const XmlElement* je = joint_of.count(n) ? joint_of[n] : nullptr;
      if (je) {
        onlyChildren(*je, {"origin", "parent", "child", "axis", "limit", "dynamics"}, {"calibration", "safety_controller"});
        const std::string& parent = *child(*je, "parent")->attribute("link");
        frame[n] = frame[parent] * originOf(child(*je, "origin"));
        l.parent = index[parent];
      } else {
        frame[n] = Frame{};
      }
      const Frame& T = frame[n];
      // Mass and inertia, turned into the root's axes.
      if (const XmlElement* in = child(le, "inertial")) {
        onlyChildren(*in, {"origin", "mass", "inertia"}, {});
        const Frame f = T * originOf(child(*in, "origin"));
        const XmlElement* m = child(*in, "mass");
        const XmlElement* I = child(*in, "inertia");
        if (!m || !I) refuse(*in, "<inertial> needs <mass> and <inertia>");
        l.mass.mass = number(*m, "value");
        if (!(l.mass.mass > 0)) refuse(*m, "<mass> value must be > 0");
        Mat3 J;
        const double ixx = number(*I, "ixx"), ixy = number(*I, "ixy", 0.0), ixz = number(*I, "ixz", 0.0),
                     iyy = number(*I, "iyy"), iyz = number(*I, "iyz", 0.0), izz = number(*I, "izz");
        J << ixx, ixy, ixz, ixy, iyy, iyz, ixz, iyz, izz;
        const Eigen::SelfAdjointEigenSolver<Mat3> eig(J);
        if (!(eig.eigenvalues().minCoeff() > 0)) refuse(*I, "<inertia> must be positive definite");
        const Vec3 e = eig.eigenvalues();
        if (e[0] + e[1] < e[2] * (1 - 1e-9)) refuse(*I, "<inertia> breaks the triangle inequality (no body has it)");
        l.mass.inertia = f.R * J * f.R.transpose();
        requireUsableMass(*in, l.mass.mass, l.mass.inertia);
        centre[n] = f.p;
      } else {  // a massless frame: a gram, so that the joint-space inertia stays invertible
        l.mass.mass = 1e-3;
        l.mass.inertia = Mat3::Identity() * 1e-7;
        centre[n] = T.p;
      }
      l.shape = shapeOf(le, T, centre[n], mesh);
      // The joint: its point is the child frame's origin, its axis in the child frame.
      if (je) {
        const std::string type = je->attribute("type") ? *je->attribute("type") : "";
        const std::string& parent = *child(*je, "parent")->attribute("link");
        ArticulatedJointDesc& j = l.joint;
        if (type == "revolute" || type == "continuous") {
          j.type = JointType::Hinge;
          const XmlElement* ax = child(*je, "axis");
          const auto a = ax ? numbers(*ax, "xyz", 3, {1, 0, 0}) : std::vector<double>{1, 0, 0};
          const Vec3 axis(a[0], a[1], a[2]);
          if (!(axis.norm() > 1e-12)) refuse(ax ? *ax : *je, "an axis of zero length has no direction");
          j.axis = (T.R * axis).normalized();
          j.angles = {0.0};
          if (const XmlElement* d = child(*je, "dynamics")) j.damping = number(*d, "damping", 0.0);
          if (j.damping < 0) refuse(*child(*je, "dynamics"), "damping must be ≥ 0");
          if (type == "revolute") {
            const XmlElement* lim = child(*je, "limit");
            if (!lim) refuse(*je, "a revolute joint needs <limit>");
            const double lo = number(*lim, "lower", 0.0), hi = number(*lim, "upper", 0.0);
            if (lo > hi) refuse(*lim, "the lower limit is above the upper");
            j.lower = {lo};
            j.upper = {hi};
          }
        } else if (type == "fixed") {
          j.type = JointType::Fixed;
        } else {
          refuse(*je, "joint type \"" + type + "\" is outside the supported URDF subset (revolute, continuous, fixed)");
        }
        j.parent_anchor = T.p - centre[parent];
        j.anchor = T.p - centre[n];
      }
      index[n] = static_cast<int>(out.size());
      out.push_back(std::move(l));
    }
    root_offset = centre[order[0]];
    return out;
  } catch (const RobotError& e) {
    return e.error();
  }
}

}  // namespace reel::io
