#include "io/scene/mjcf.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <memory>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "core/mass_properties.h"
#include "core/math.h"
#include "core/mesh.h"
#include "core/scene/articulated.h"
#include "io/scene/robot_xml.h"

namespace reel::io {
namespace {

using Attributes = std::vector<std::pair<std::string, std::string>>;

// An <asset> <mesh>: its file (below meshdir) and scale; loaded when a geom first uses it.
struct MeshAsset {
  const XmlElement* element = nullptr;
  std::string file;
  Vec3 scale{1, 1, 1};
  std::shared_ptr<const TriMesh> mesh;
};

struct Model {
  double angle = kPi / 180.0;  // <compiler angle>: degrees unless "radian"
  std::vector<ArticulatedLinkDesc> links;
  std::vector<Vec3> centre;  // per link: its centre of mass, root frame
  bool free_root = false;
  int unnamed = 0;
  // <default> classes: per class, per element kind (joint, geom, mesh, ...), the attributes it sets.
  std::map<std::string, std::map<std::string, Attributes>> classes;
  std::map<std::string, MeshAsset> meshes;
  std::string meshdir;
  const MeshLoader* load = nullptr;
};

// The smallest size of a geom, m: below it no mass or contact means anything.
constexpr double kMinGeomSize = 1e-6;

// <default> (MJCF's cascade, after CSS): the top one is class "main"; a nested <default class>
// starts from its parent's settings and overrides them.
void readDefault(const XmlElement& d, const std::string& parent, Model& m) {
  const std::string name = parent.empty() ? "main" : d.attribute("class") ? *d.attribute("class") : "";
  if (name.empty()) refuse(d, "a nested <default> needs a class");
  if (m.classes.count(name)) refuse(d, "a second default class \"" + name + "\"");
  std::map<std::string, Attributes> kinds = parent.empty() ? std::map<std::string, Attributes>{} : m.classes[parent];
  for (const XmlElement& c : d.children) {
    if (c.name == "default") continue;
    Attributes& set = kinds[c.name];
    for (const auto& [k, v] : c.attributes) {
      if (k == "class" || k == "name") refuse(c, "a default <" + c.name + "> takes no " + k);
      auto at = std::find_if(set.begin(), set.end(), [&key = k](const auto& a) { return a.first == key; });
      if (at != set.end()) at->second = v;
      else set.emplace_back(k, v);
    }
  }
  m.classes[name] = std::move(kinds);
  for (const XmlElement& c : d.children)
    if (c.name == "default") readDefault(c, name, m);
}

// The element with its class's settings for its kind filled in (its own attributes win): its own
// `class`, else `active` (the nearest enclosing body's childclass, else "main").
XmlElement withDefaults(const XmlElement& e, const std::string& active, const Model& m) {
  const std::string* own = e.attribute("class");
  const std::string cls = own ? *own : active;
  const auto it = m.classes.find(cls);
  if (it == m.classes.end()) {
    if (own || cls != "main") refuse(e, "no default class \"" + cls + "\"");
    return e;
  }
  XmlElement out = e;
  const auto kind = it->second.find(e.name);
  if (kind != it->second.end())
    for (const auto& [k, v] : kind->second)
      if (!e.attribute(k)) out.attributes.emplace_back(k, v);
  return out;
}

// The mesh a geom names, loaded once, scaled.
const MeshAsset& meshNamed(const XmlElement& g, Model& m) {
  const std::string* name = g.attribute("mesh");
  if (!name) refuse(g, "a mesh geom needs mesh=\"...\"");
  const auto it = m.meshes.find(*name);
  if (it == m.meshes.end()) refuse(g, "no <mesh> named \"" + *name + "\" in <asset>");
  MeshAsset& a = it->second;
  if (!a.mesh) {
    auto loaded = (*m.load)(m.meshdir.empty() ? a.file : m.meshdir + "/" + a.file);
    if (!loaded.ok()) refuse(*a.element, "<mesh> \"" + a.file + "\": " + loaded.error().headline());
    a.mesh = loaded.value();
  }
  return a;
}

// A body's or geom's orientation: quat (w x y z), euler (intrinsic x, y, z), axisangle, zaxis.
Mat3 orientationOf(const XmlElement& e, const Model& m) {
  int given = 0;
  Mat3 R = Mat3::Identity();
  if (e.attribute("quat")) {
    const auto q = numbers(e, "quat", 4, {});
    const Eigen::Quaterniond Q(q[0], q[1], q[2], q[3]);
    if (!(Q.norm() > 1e-12)) refuse(e, "<" + e.name + "> quat of zero length");
    R = Q.normalized().toRotationMatrix();
    ++given;
  }
  if (e.attribute("euler")) {
    const auto a = numbers(e, "euler", 3, {});
    R = (Eigen::AngleAxisd(a[0] * m.angle, Vec3::UnitX()) * Eigen::AngleAxisd(a[1] * m.angle, Vec3::UnitY()) *
         Eigen::AngleAxisd(a[2] * m.angle, Vec3::UnitZ()))
            .toRotationMatrix();
    ++given;
  }
  if (e.attribute("axisangle")) {
    const auto a = numbers(e, "axisangle", 4, {});
    const Vec3 axis(a[0], a[1], a[2]);
    if (!(axis.norm() > 1e-12)) refuse(e, "<" + e.name + "> axisangle of a zero axis");
    R = Eigen::AngleAxisd(a[3] * m.angle, axis.normalized()).toRotationMatrix();
    ++given;
  }
  if (e.attribute("zaxis")) {
    const auto a = numbers(e, "zaxis", 3, {});
    const Vec3 z(a[0], a[1], a[2]);
    if (!(z.norm() > 1e-12)) refuse(e, "<" + e.name + "> zaxis of zero length");
    R = Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), z.normalized()).toRotationMatrix();
    ++given;
  }
  if (e.attribute("xyaxes")) refuse(e, "<" + e.name + "> xyaxes is outside the supported MJCF subset");
  if (given > 1) refuse(e, "<" + e.name + "> gives its orientation twice");
  return R;
}

Vec3 vec3(const XmlElement& e, const std::string& key, const Vec3& def) {
  const auto v = numbers(e, key, 3, {def.x(), def.y(), def.z()});
  return {v[0], v[1], v[2]};
}

// The geom as a link shape (its own frame in the body's) and, at its density, its mass properties
// in the body frame.
MassProperties geomShape(const XmlElement& g, Model& m, LinkShape& s) {
  onlyChildren(g, {}, {});
  const std::string type = g.attribute("type") ? *g.attribute("type") : "sphere";
  if (type != "sphere" && type != "box" && type != "capsule" && type != "cylinder" && type != "mesh")
    refuse(g, "geom type \"" + type + "\" is outside the supported MJCF subset (sphere, capsule, box, cylinder, mesh)");
  Mat3 R = orientationOf(g, m);
  Vec3 at = vec3(g, "pos", Vec3::Zero());
  const double density = number(g, "density", 1000.0);
  if (!(density > 0)) refuse(g, "<geom> density must be > 0");
  if (type == "mesh") {
    // The mesh's vertices in the geom's frame (MuJoCo's compiled geom frame undoes its own
    // recentring, so this is where the file puts them); its mass from its closed volume.
    const MeshAsset& a = meshNamed(g, m);
    s.kind = LinkShape::Kind::Mesh;
    s.mesh = a.mesh;
    s.scale = a.scale;
    s.offset = at;
    s.rotation = R;
    auto solid = solidMassProperties(placeMesh(*a.mesh, a.scale, R, at), density);
    if (!solid.ok()) refuse(g, "mesh \"" + *g.attribute("mesh") + "\": " + solid.error().headline());
    return solid.value();
  }
  const auto size = numberList(g, "size", 3);
  for (std::size_t k = 0; k < size.size(); ++k)
    if (!(size[k] >= kMinGeomSize) && !(k > 0 && g.attribute("fromto")))
      refuse(g, "<geom> size must be at least 1e-6 m (a micron)");
  // fromto: a capsule's or cylinder's axis between two points (its length from them).
  double half = size.size() > 1 ? size[1] : 0.0;
  if (g.attribute("fromto")) {
    if (type != "capsule" && type != "cylinder") refuse(g, "fromto is read for capsules and cylinders");
    const auto f = numbers(g, "fromto", 6, {});
    const Vec3 a(f[0], f[1], f[2]), b(f[3], f[4], f[5]);
    if (!((b - a).norm() > 1e-12)) refuse(g, "<geom> fromto of zero length");
    at = 0.5 * (a + b);
    half = 0.5 * (b - a).norm();
    R = Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), (b - a).normalized()).toRotationMatrix();
  }
  // reel's capsules and cylinders lie along y, MuJoCo's along z.
  const Mat3 z_from_y = Eigen::AngleAxisd(kPi / 2, Vec3::UnitX()).toRotationMatrix();
  s.offset = at;
  s.rotation = R;
  if (type == "sphere") {
    s.kind = LinkShape::Kind::Sphere;
    s.radius = size[0];
  } else if (type == "box") {
    if (size.size() != 3) refuse(g, "a box's size is its three half sizes");
    s.kind = LinkShape::Kind::Box;
    s.size = 2.0 * Vec3(size[0], size[1], size[2]);
  } else {  // a capsule or a cylinder (the type was checked above)
    if (!(half > 0)) refuse(g, "a " + type + " needs its half length (size or fromto)");
    s.kind = type == "capsule" ? LinkShape::Kind::Capsule : LinkShape::Kind::Cylinder;
    s.radius = size[0];
    s.length = 2.0 * half;
    s.rotation = R * z_from_y;
  }
  return linkMass(s, density);
}

// The geom's shape and mass properties: its `mass` if given, else from its density.
void readGeom(const XmlElement& g, Model& m, LinkShape& s, MassProperties& mass) {
  mass = geomShape(g, m, s);
  if (g.attribute("mass")) {
    const double kg = number(g, "mass");
    if (!(kg > 0)) refuse(g, "<geom> mass must be > 0");
    mass = withMass(mass, kg);
  }
}

void readBody(const XmlElement& b, Model& m, int parent, const Frame& parent_frame, std::string active) {
  ArticulatedLinkDesc l;
  l.name = b.attribute("name") ? *b.attribute("name") : "body" + std::to_string(m.unnamed++);
  if (l.name.find('/') != std::string::npos) refuse(b, "body name \"" + l.name + "\" may not contain '/'");
  for (const auto& o : m.links)
    if (o.name == l.name) refuse(b, "a second body named \"" + l.name + "\"");
  l.parent = parent;
  const Frame T = parent_frame * Frame{orientationOf(b, m), vec3(b, "pos", Vec3::Zero())};
  if (const std::string* cc = b.attribute("childclass")) {
    if (!m.classes.count(*cc)) refuse(b, "no default class \"" + *cc + "\"");
    active = *cc;
  }
  // Joints and geoms with their class's defaults filled in.
  std::vector<XmlElement> resolved;
  resolved.reserve(b.children.size());
  std::vector<const XmlElement*> joints, geoms, bodies;
  const XmlElement* inertial = nullptr;
  for (const XmlElement& c : b.children) {
    if (c.name == "joint" || c.name == "geom") resolved.push_back(withDefaults(c, active, m));
    if (c.name == "joint") joints.push_back(&resolved.back());
    else if (c.name == "freejoint") joints.push_back(&c);
    else if (c.name == "geom") geoms.push_back(&resolved.back());
    else if (c.name == "body") bodies.push_back(&c);
    else if (c.name == "inertial") inertial = &c;
    else if (c.name != "site" && c.name != "camera" && c.name != "light")
      refuse(c, "<" + c.name + "> in <body> is outside the supported MJCF subset");
  }
  if (geoms.size() > 1) refuse(*geoms[1], "a second <geom> in one body is outside the supported subset (one shape per link)");
  // Shape and mass (body frame), then turned into the root's axes.
  MassProperties mass;
  if (!geoms.empty()) readGeom(*geoms[0], m, l.shape, mass);
  else l.shape.kind = LinkShape::Kind::Sphere, l.shape.radius = 0.005;
  if (inertial) {
    onlyChildren(*inertial, {}, {});
    mass.mass = number(*inertial, "mass");
    if (!(mass.mass > 0)) refuse(*inertial, "<inertial> mass must be > 0");
    mass.center_of_mass = vec3(*inertial, "pos", Vec3::Zero());
    const Mat3 Ri = orientationOf(*inertial, m);
    Mat3 J = Mat3::Zero();
    if (inertial->attribute("diaginertia")) {
      const auto d = numbers(*inertial, "diaginertia", 3, {});
      J.diagonal() = Vec3(d[0], d[1], d[2]);
    } else if (inertial->attribute("fullinertia")) {
      const auto f = numbers(*inertial, "fullinertia", 6, {});  // Ixx Iyy Izz Ixy Ixz Iyz
      J << f[0], f[3], f[4], f[3], f[1], f[5], f[4], f[5], f[2];
    } else {
      refuse(*inertial, "<inertial> needs diaginertia or fullinertia");
    }
    const Eigen::SelfAdjointEigenSolver<Mat3> eig(J);
    if (!(eig.eigenvalues().minCoeff() > 0)) refuse(*inertial, "<inertial> inertia must be positive definite");
    mass.inertia = Ri * J * Ri.transpose();
  } else if (geoms.empty()) {
    mass.mass = 1e-3;
    mass.inertia = Mat3::Identity() * 1e-7;
  }
  if (inertial || !geoms.empty()) requireUsableMass(inertial ? *inertial : *geoms[0], mass.mass, mass.inertia);
  const Vec3 c = T.p + T.R * mass.center_of_mass;
  l.mass.mass = mass.mass;
  l.mass.inertia = T.R * mass.inertia * T.R.transpose();
  // The shape about the centre of mass, in the root's axes.
  l.shape.offset = T.R * l.shape.offset + T.p - c;
  l.shape.rotation = T.R * l.shape.rotation;
  // The joint.
  ArticulatedJointDesc& j = l.joint;
  Vec3 point = T.p;
  std::vector<Vec3> axes;
  std::vector<std::pair<double, double>> ranges;
  bool ranged = false;
  for (const XmlElement* je : joints) {
    onlyChildren(*je, {}, {});
    const std::string type = je->name == "freejoint" ? "free" : je->attribute("type") ? *je->attribute("type") : "hinge";
    if (type == "free") {
      if (parent >= 0) refuse(*je, "a free joint below the root is outside the supported subset");
      if (joints.size() > 1) refuse(*je, "a free joint with other joints in one body");
      m.free_root = true;
      continue;
    }
    if (parent < 0) refuse(*je, "the root body moves only by a free joint (or is welded)");
    if (type != "hinge" && type != "ball") refuse(*je, "joint type \"" + type + "\" is outside the supported MJCF subset (hinge, ball, free)");
    const Vec3 pos = T.p + T.R * vec3(*je, "pos", Vec3::Zero());
    if (!axes.empty() && (pos - point).norm() > 1e-9) refuse(*je, "two hinges in one body must share their point");
    point = pos;
    if (type == "ball") {
      if (joints.size() > 1) refuse(*je, "a ball joint with other joints in one body");
      j.type = JointType::Ball;
    } else {
      const Vec3 a = vec3(*je, "axis", Vec3(0, 0, 1));
      if (!(a.norm() > 1e-12)) refuse(*je, "an axis of zero length has no direction");
      axes.push_back((T.R * a).normalized());
      if (axes.size() > 2) refuse(*je, "three hinges in one body are outside the supported subset");
    }
    for (const char* key : {"stiffness", "frictionloss", "ref", "springref", "springdamper"})
      if (je->attribute(key)) {
        const auto v = numberList(*je, key, 2);
        for (double x : v)
          if (x != 0.0) refuse(*je, std::string("joint ") + key + " is outside the supported MJCF subset");
      }
    const double damping = number(*je, "damping", 0.0);
    if (damping < 0) refuse(*je, "damping must be ≥ 0");
    j.damping = std::max(j.damping, damping);
    const double armature = number(*je, "armature", 0.0);
    if (!(armature >= 0 && armature <= 1e6)) refuse(*je, "armature must be in [0, 1e6]");
    j.armature = std::max(j.armature, armature);
    if (je->attribute("range") && !(je->attribute("limited") && *je->attribute("limited") == "false")) {
      const auto r = numbers(*je, "range", 2, {});
      if (r[0] > r[1]) refuse(*je, "the range's lower end is above its upper");
      ranges.emplace_back(r[0] * m.angle, r[1] * m.angle);
      ranged = true;
    } else {
      ranges.emplace_back(0.0, 0.0);
    }
  }
  if (parent >= 0) {
    if (j.type == JointType::Ball) {
      if (ranged) j.cone = ranges[0].second;
      j.angles = {0, 0, 0};
    } else if (axes.size() == 1) {
      j.type = JointType::Hinge;
      j.axis = axes[0];
      j.angles = {0};
    } else if (axes.size() == 2) {
      if (std::abs(axes[0].dot(axes[1])) > 1 - 1e-9) refuse(*joints[1], "two hinges in one body must not be parallel");
      j.type = JointType::Universal;
      j.axis = axes[0];
      j.axis2 = axes[1];
      j.angles = {0, 0};
    } else {
      j.type = JointType::Fixed;
    }
    if (ranged && (j.type == JointType::Hinge || j.type == JointType::Universal)) {
      bool all = true;
      for (const auto& [lo, hi] : ranges) all = all && (lo != 0.0 || hi != 0.0);
      if (all)
        for (const auto& [lo, hi] : ranges) j.lower.push_back(lo), j.upper.push_back(hi);
    }
    j.parent_anchor = point - m.centre[static_cast<std::size_t>(parent)];
    j.anchor = point - c;
  }
  const int index = static_cast<int>(m.links.size());
  m.links.push_back(std::move(l));
  m.centre.push_back(c);
  for (const XmlElement* child_body : bodies) readBody(*child_body, m, index, T, active);
}

}  // namespace

Result<std::vector<ArticulatedLinkDesc>> mjcfLinks(const XmlElement& mujoco, Vec3& root_offset, bool& free_root,
                                                   const MeshLoader& load) {
  try {
    if (mujoco.name != "mujoco") refuse(mujoco, "expected <mujoco>, found <" + mujoco.name + ">");
    Model m;
    m.load = &load;
    // Defaults first: assets may take them too.
    for (const XmlElement& e : mujoco.children)
      if (e.name == "default") {
        if (m.classes.count("main")) refuse(e, "a second top-level <default>");
        readDefault(e, "", m);
      }
    std::string assetdir;
    const XmlElement* world = nullptr;
    for (const XmlElement& e : mujoco.children) {
      if (e.name == "compiler") {
        for (const auto& [k, v] : e.attributes) {
          if (k == "angle") {
            if (v != "degree" && v != "radian") refuse(e, "angle must be degree or radian");
            m.angle = v == "radian" ? 1.0 : kPi / 180.0;
          } else if (k == "coordinate" && v != "local") {
            refuse(e, "coordinate=\"" + v + "\" is outside the supported MJCF subset");
          } else if (k == "eulerseq" && v != "xyz") {
            refuse(e, "eulerseq=\"" + v + "\" is outside the supported MJCF subset");
          } else if (k == "meshdir") {
            m.meshdir = v;
          } else if (k == "assetdir") {
            assetdir = v;
          }
        }
      } else if (e.name == "asset") {
        for (const XmlElement& a : e.children) {
          if (a.name != "mesh") continue;  // textures and materials: only drawing, passed over
          const XmlElement mesh = withDefaults(a, "main", m);
          onlyChildren(a, {}, {});
          const std::string* file = mesh.attribute("file");
          if (!file || file->empty()) refuse(a, "<mesh> needs a file (vertex lists are outside the supported subset)");
          if (file->find("://") != std::string::npos) refuse(a, "<mesh> \"" + *file + "\": only paths relative to the model are read");
          const std::string* given = mesh.attribute("name");
          const std::string name = given ? *given : std::filesystem::path(*file).stem().string();
          if (m.meshes.count(name)) refuse(a, "a second <mesh> named \"" + name + "\"");
          const auto scale = numbers(mesh, "scale", 3, {1, 1, 1});
          for (double x : scale)
            if (!(x > 0)) refuse(a, "<mesh> scale must be > 0");
          m.meshes[name] = MeshAsset{&a, *file, Vec3(scale[0], scale[1], scale[2]), nullptr};
        }
      } else if (e.name == "worldbody") {
        if (world) refuse(e, "a second <worldbody>");
        world = &e;
      } else if (e.name != "option" && e.name != "visual" && e.name != "statistic" && e.name != "size" &&
                 e.name != "default" && e.name != "actuator" && e.name != "sensor" && e.name != "keyframe" &&
                 e.name != "contact") {
        refuse(e, "<" + e.name + "> is outside the supported MJCF subset");
      }
    }
    if (!world) refuse(mujoco, "the model has no <worldbody>");
    if (m.meshdir.empty()) m.meshdir = assetdir;
    const XmlElement* root = nullptr;
    for (const XmlElement& e : world->children) {
      if (e.name == "body") {
        if (root) refuse(e, "a second body under <worldbody> (one figure per file)");
        root = &e;
      } else if (e.name != "geom" && e.name != "site" && e.name != "camera" && e.name != "light") {
        refuse(e, "<" + e.name + "> in <worldbody> is outside the supported MJCF subset");
      }
    }
    if (!root) refuse(*world, "<worldbody> has no <body>");
    readBody(*root, m, -1, Frame{}, "main");
    root_offset = m.centre[0];
    free_root = m.free_root;
    return m.links;
  } catch (const RobotError& e) {
    return e.error();
  }
}

}  // namespace reel::io
