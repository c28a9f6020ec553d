// The reader of the kind `articulated`: links and joints given in the scene, or a generated
// figure (`"figure": "human"`), its start pose, servos and pose keys (docs/articulated.md).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>

#include <nlohmann/json.hpp>

#include "core/figure.h"
#include "core/format.h"
#include "core/math.h"
#include "core/scene/articulated.h"
#include "io/files.h"
#include "io/mesh_import.h"
#include "io/mesh_scan.h"
#include "io/scene/reader.h"
#include "io/scene/readers.h"
#include "io/scene/mjcf.h"
#include "io/scene/urdf.h"
#include "io/xml.h"

namespace reel::io {
namespace {

constexpr double kDeg = kPi / 180.0;
constexpr std::size_t kMaxRobotBytes = 16 << 20;  // a URDF or MJCF file
constexpr std::size_t kMaxLinks = 500;             // links of one articulated body (its matrices are dense)

// `key`: n angles in degrees (a number when n is 1, else a list of n), in rad.
std::optional<std::vector<double>> anglesOf(const Json* j, const std::string& p, Diagnostics& diag, std::size_t n) {
  std::vector<double> out;
  if (j->is_number() && n == 1) {
    out.push_back(j->get<double>());
  } else if (j->is_array() && j->size() == n) {
    for (const Json& x : *j) {
      if (!x.is_number()) {
        diag.error(p, "expected numbers (degrees)");
        return std::nullopt;
      }
      out.push_back(x.get<double>());
    }
  } else {
    diag.error(p, n == 1 ? "expected an angle in degrees" : "expected a list of " + std::to_string(n) + " angles in degrees");
    return std::nullopt;
  }
  for (double& a : out) {
    if (!std::isfinite(a)) {
      diag.error(p, "an angle must be finite");
      return std::nullopt;
    }
    if (std::abs(a) > 1e6) {
      diag.error(p, "an angle of " + formatNumber(a, 6) + " degrees is beyond the limit of ±1e6");
      return std::nullopt;
    }
    a *= kDeg;
  }
  return out;
}

std::optional<std::vector<double>> readAngles(Obj& o, const std::string& key, std::size_t n) {
  const Json* j = o.raw(key);
  if (!j) return std::nullopt;
  return anglesOf(j, childPath(o.path(), key), o.diag(), n);
}

JointType jointTypeOf(const std::string& s) {
  if (s == "hinge") return JointType::Hinge;
  if (s == "universal") return JointType::Universal;
  if (s == "ball") return JointType::Ball;
  return JointType::Fixed;
}

// A unit axis `key` (an error at its path when of zero length).
Vec3 readAxis(Obj& o, const std::string& key, const Vec3& def) {
  const Vec3 a = o.vec3(key, def, Range::closed(-1e6, 1e6));
  if (!(a.norm() > 1e-12)) {
    o.diag().error(childPath(o.path(), key), "an axis of zero length has no direction");
    return def;
  }
  return a.normalized();
}

// The servo keys of a joint (kp, kd, max_torque) over `s`.
void readServo(Obj& o, ServoDesc& s) {
  s.kp = o.number("kp", s.kp, Range::closed(0.0, 1e9));
  s.kd = o.number("kd", s.kd, Range::closed(0.0, 1e9));
  s.max_torque = o.number("max_torque", s.max_torque, Range::closed(0.0, std::numeric_limits<double>::infinity()));
}

// Angles and servo keys any joint takes, given explicitly or on a generated figure's joint.
void readJointState(Obj& j, ArticulatedJointDesc& joint) {
  const std::size_t n = static_cast<std::size_t>(jointDofs(joint.type));
  if (n == 0) return;
  if (auto a = readAngles(j, "angle_deg", n)) joint.angles = *a;
  if (auto a = readAngles(j, "target_deg", n)) joint.target = *a;
  joint.damping = j.number("damping", joint.damping, Range::closed(0.0, 1e9));
  joint.armature = j.number("armature", joint.armature, Range::closed(0.0, 1e6));
  readServo(j, joint.servo);
}

// The joint of an explicit link (its type, frame and limits).
void readJoint(Obj& j, ArticulatedJointDesc& joint) {
  joint.type = jointTypeOf(j.choice("type", "hinge", {"hinge", "universal", "ball", "fixed"}));
  joint.axis = readAxis(j, "axis", Vec3(0, 0, 1));
  if (joint.type == JointType::Universal) {
    joint.axis2 = readAxis(j, "axis2", Vec3(1, 0, 0));
    if (std::abs(joint.axis.dot(joint.axis2)) > 1.0 - 1e-9)
      j.diag().error(childPath(j.path(), "axis2"), "a universal joint's two axes must not be parallel");
  }
  joint.anchor = j.vec3("anchor", Vec3::Zero(), Range::closed(-1e4, 1e4));
  joint.parent_anchor = j.vec3("parent_anchor", Vec3::Zero(), Range::closed(-1e4, 1e4));
  const std::size_t n = static_cast<std::size_t>(jointDofs(joint.type));
  joint.angles.assign(n, 0.0);
  readJointState(j, joint);
  if (joint.type == JointType::Hinge || joint.type == JointType::Universal) {
    auto lo = readAngles(j, "lower_deg", n), hi = readAngles(j, "upper_deg", n);
    if (lo.has_value() != hi.has_value()) {
      j.diag().error(childPath(j.path(), lo ? "upper_deg" : "lower_deg"), "give lower_deg and upper_deg together");
    } else if (lo) {
      for (std::size_t d = 0; d < n; ++d)
        if ((*lo)[d] > (*hi)[d])
          j.diag().error(childPath(j.path(), "lower_deg"), "the lower limit " + formatNumber((*lo)[d] / kDeg, 4) +
                                                                "° is above the upper limit " + formatNumber((*hi)[d] / kDeg, 4) + "°");
      joint.lower = *lo;
      joint.upper = *hi;
    }
  } else if (j.has("lower_deg") || j.has("upper_deg")) {
    j.diag().error(childPath(j.path(), j.has("lower_deg") ? "lower_deg" : "upper_deg"),
                   "only hinge and universal joints take lower_deg and upper_deg (a ball takes cone_deg)");
  }
  if (joint.type == JointType::Ball) joint.cone = j.number("cone_deg", 0.0, Range::closed(0.0, 180.0)) * kDeg;
  else if (j.has("cone_deg")) j.diag().error(childPath(j.path(), "cone_deg"), "only a ball joint takes cone_deg");
}

LinkShape readLinkShape(Obj& o) {
  LinkShape s;
  const std::string shape = o.choice("shape", "box", {"sphere", "box", "capsule"});
  if (shape == "sphere") {
    s.kind = LinkShape::Kind::Sphere;
    s.radius = o.number("radius", 0.05, kLength);
  } else if (shape == "capsule") {
    s.kind = LinkShape::Kind::Capsule;
    s.radius = o.number("radius", 0.05, kLength);
    s.length = o.number("length", 0.3, Range::closed(0.0, 1e4));
  } else {
    s.size = o.vec3("size", Vec3(0.1, 0.1, 0.1), kLength);
  }
  return s;
}

// Orders links so that every parent comes before its children (the scene may list them in any
// order); false (with an error) on a cycle.
bool orderLinks(Obj& o, std::vector<ArticulatedLinkDesc>& links, const std::vector<std::string>& paths) {
  const std::size_t n = links.size();
  std::vector<int> order;
  std::vector<char> placed(n, 0);
  while (order.size() < n) {
    bool progress = false;
    for (std::size_t i = 0; i < n; ++i) {
      if (placed[i]) continue;
      const int p = links[i].parent;
      if (p < 0 || placed[static_cast<std::size_t>(p)]) {
        order.push_back(static_cast<int>(i));
        placed[i] = 1;
        progress = true;
      }
    }
    if (!progress) {
      for (std::size_t i = 0; i < n; ++i)
        if (!placed[i]) {
          o.diag().error(childPath(paths[i], "parent"), "link '" + links[i].name + "' is its own ancestor: the parents form a cycle");
          return false;
        }
    }
  }
  std::vector<int> where(n);
  for (std::size_t k = 0; k < n; ++k) where[static_cast<std::size_t>(order[k])] = static_cast<int>(k);
  std::vector<ArticulatedLinkDesc> sorted;
  for (int i : order) {
    ArticulatedLinkDesc l = links[static_cast<std::size_t>(i)];
    if (l.parent >= 0) l.parent = where[static_cast<std::size_t>(l.parent)];
    sorted.push_back(std::move(l));
  }
  links = std::move(sorted);
  return true;
}

int findLink(const std::vector<ArticulatedLinkDesc>& links, const std::string& name) {
  for (std::size_t i = 0; i < links.size(); ++i)
    if (links[i].name == name) return static_cast<int>(i);
  return -1;
}

std::vector<std::string> linkNames(const std::vector<ArticulatedLinkDesc>& links) {
  std::vector<std::string> names;
  for (const auto& l : links) names.push_back(l.name);
  return names;
}

// `pose`/`joints` entries name links: the link, or an error with the nearest name.
int namedLink(Obj& o, const std::vector<ArticulatedLinkDesc>& links, const std::string& name, const std::string& path) {
  const int i = findLink(links, name);
  if (i < 0) {
    o.diag().error(path, "no link '" + name + "' (nearest: '" + nearest(name, linkNames(links)) + "')");
    return -1;
  }
  if (links[static_cast<std::size_t>(i)].parent < 0) {
    o.diag().error(path, "link '" + name + "' is the root: it has no joint");
    return -1;
  }
  return i;
}

// `joints`: per joint of a generated figure or a robot, angles, targets and servo keys over its own.
void jointOverrides(Obj& o, ArticulatedDesc& r) {
  const Json* j = o.raw("joints");
  if (!j) return;
  const std::string jp = childPath(o.path(), "joints");
  if (!j->is_object()) {
    o.diag().error(jp, "expected an object of link names");
    return;
  }
  for (const auto& [name, value] : j->items()) {
    const int i = namedLink(o, r.links, name, childPath(jp, name));
    if (i < 0) continue;
    Obj jo(value, childPath(jp, name), o.diag());
    readJointState(jo, r.links[static_cast<std::size_t>(i)].joint);
    jo.finish();
  }
}

}  // namespace

std::shared_ptr<const BodyParams> readArticulatedBody(Obj& o, BodyDesc& body, const SceneDesc&) {
  auto r = std::make_shared<ArticulatedDesc>();
  Diagnostics& d = o.diag();
  const std::string& p = o.path();
  readMaterial(o, body.material);
  Surface surface;
  SpeciesSurfaces species;
  readSurfaces(o, surface, species);
  r->rotation = rotationFromEulerDeg(o.vec3("rotation_deg", Vec3::Zero()));
  r->velocity = o.vec3("velocity", Vec3::Zero(), Range::closed(-1e4, 1e4));
  r->angular_velocity = o.vec3("angular_velocity", Vec3::Zero(), Range::closed(-1e4, 1e4));
  r->fixed_base = o.boolean("fixed_base", false);
  r->iterations = o.integer("iterations", r->iterations, 1, 1000);
  const Vec3 position = o.vec3("position", Vec3::Zero(), Range::closed(-1e5, 1e5));
  if (o.has("figure")) {
    const std::string figure = o.choice("figure", "human", {"human"});
    (void)figure;
    if (o.has("links")) d.error(childPath(p, "links"), "give a figure or links, not both");
    const double height = o.number("height", 1.75, Range::closed(0.1, 10.0));
    const double mass = o.number("mass", 70.0, Range::closed(0.1, 1e4));
    const double strength = o.number("strength", 1.0, Range::closed(0.0, 100.0));
    r->links = humanFigure(height, mass, strength);
    // Dressed: skin, shirt, trousers and shoes (`outfit`), unless `color` makes it one colour.
    Vec3 skin(0.78, 0.55, 0.42), shirt(0.18, 0.32, 0.58), trousers(0.16, 0.16, 0.2), shoes(0.08, 0.06, 0.05);
    readObjectKey(o, "outfit", [&](Obj& oo) {
      skin = oo.vec3("skin", skin, kUnit);
      shirt = oo.vec3("shirt", shirt, kUnit);
      trousers = oo.vec3("trousers", trousers, kUnit);
      shoes = oo.vec3("shoes", shoes, kUnit);
    });
    const bool one_colour = o.has("color");
    for (auto& l : r->links) {
      l.material = body.material;
      if (one_colour) continue;
      const std::string& n = l.name;
      l.material.color = n == "head" || n.starts_with("hand") || n.starts_with("forearm") ? skin
                         : n == "chest" || n == "abdomen" || n.starts_with("upper_arm")   ? shirt
                         : n.starts_with("foot")                                           ? shoes
                                                                                          : trousers;
    }
    // `position`: the point on the ground between its feet.
    r->position = position + r->rotation * Vec3(0, humanRootHeight(height), 0);
    jointOverrides(o, *r);
  } else if (o.has("urdf") || o.has("mjcf")) {
    const char* key = o.has("urdf") ? "urdf" : "mjcf";
    if (o.has("urdf") && o.has("mjcf")) d.error(childPath(p, "mjcf"), "give a urdf or an mjcf file, not both");
    if (o.has("links")) d.error(childPath(p, "links"), std::string("give ") + key + " or links, not both");
    const std::string file = o.string(key).value_or("");
    auto path = resolveAsset(d.file(), file, {key == std::string("urdf") ? ".urdf" : ".mjcf", ".xml"}, kMaxRobotBytes);
    auto text = path.ok() ? readFile(path.value(), kMaxRobotBytes) : Result<std::string>(path.error());
    auto xml = text.ok() ? parseXml(text.value()) : Result<XmlElement>(text.error());
    Vec3 root_offset = Vec3::Zero();
    bool free_root = true;
    // A robot's meshes: paths relative to its file, inside the scene's asset roots.
    const std::string folder = std::filesystem::path(file).parent_path().string();
    const MeshLoader loadRobotMesh = [&](const std::string& name) -> Result<std::shared_ptr<const TriMesh>> {
      const std::string rel = folder.empty() ? name : (std::filesystem::path(folder) / name).string();
      auto where = resolveAsset(d.file(), rel, {std::begin(kMeshExtensions), std::end(kMeshExtensions)}, kMaxMeshBytes);
      if (!where.ok()) return where.error();
      auto m = importMesh(where.value(), assetRoots(d.file()));
      if (!m.ok()) return m.error();
      return std::shared_ptr<const TriMesh>(std::make_shared<TriMesh>(std::move(m.value())));
    };
    auto links = !xml.ok() ? Result<std::vector<ArticulatedLinkDesc>>(xml.error())
                 : key == std::string("urdf") ? urdfLinks(xml.value(), root_offset, loadRobotMesh)
                                              : mjcfLinks(xml.value(), root_offset, free_root, loadRobotMesh);
    if (!links.ok()) {
      d.error(childPath(p, key), "\"" + file + "\": " + links.error().headline());
      return r;
    }
    r->fixed_base = r->fixed_base || !free_root;  // an MJCF root without a free joint is welded
    r->links = std::move(links.value());
    // `position` and `rotation_deg` place the robot's frame (a URDF's root link, an MJCF's world);
    // `servo` acts on every joint.
    r->position = position + r->rotation * root_offset;
    ServoDesc servo;
    readObjectKey(o, "servo", [&](Obj& so) { readServo(so, servo); });
    for (auto& l : r->links) {
      l.material = body.material;
      l.joint.servo = servo;
    }
    jointOverrides(o, *r);
  } else {
    r->position = position;
    ServoDesc servo;
    readObjectKey(o, "servo", [&](Obj& so) { readServo(so, servo); });
    std::vector<std::string> parents, paths;
    readList(
        o, "links",
        [&](Obj& lo) {
          ArticulatedLinkDesc l;
          paths.push_back(lo.path());
          l.name = lo.string("name", true).value_or("");
          if (!l.name.empty() && findLink(r->links, l.name) >= 0) d.error(childPath(lo.path(), "name"), "a second link named '" + l.name + "'");
          if (l.name.find('/') != std::string::npos) d.error(childPath(lo.path(), "name"), "a link's name may not contain '/'");
          l.shape = readLinkShape(lo);
          const double density = lo.number("density", 1000.0, Range{0.0, 1e5, true, false});
          const std::optional<double> mass = lo.number("mass", Range{0.0, 1e6, true, false});
          if (mass && lo.has("density")) d.error(childPath(lo.path(), "mass"), "give density or mass, not both");
          l.mass = linkMass(l.shape, density);
          if (mass) l.mass = withMass(l.mass, *mass);
          l.material = body.material;
          if (auto c = lo.vec3("color", kUnit)) l.material.color = *c;
          parents.push_back(lo.string("parent").value_or(""));
          l.joint.servo = servo;
          if (!parents.back().empty()) {
            bool given = false;
            readObjectKey(lo, "joint", [&](Obj& jo) {
              given = true;
              readJoint(jo, l.joint);
            });
            if (!given) d.error(childPath(lo.path(), "joint"), "a link with a parent needs its joint");
          } else if (lo.has("joint")) {
            d.error(childPath(lo.path(), "joint"), "the root link (no parent) has no joint: it is free, or fixed with fixed_base");
          }
          r->links.push_back(std::move(l));
        },
        true);
    if (r->links.empty()) {
      if (o.ok() && o.raw("links")) d.error(childPath(p, "links"), "an articulated body needs at least one link");
      return r;
    }
    int roots = 0;
    for (std::size_t i = 0; i < r->links.size(); ++i) {
      if (parents[i].empty()) {
        r->links[i].parent = -1;
        if (++roots > 1) d.error(childPath(paths[i], "parent"), "a second root: every link but one needs a parent");
        continue;
      }
      const int pi = findLink(r->links, parents[i]);
      if (pi < 0) {
        d.error(childPath(paths[i], "parent"), "no link '" + parents[i] + "' (nearest: '" + nearest(parents[i], linkNames(r->links)) + "')");
        return r;
      }
      r->links[i].parent = pi;
    }
    if (roots == 0) {
      d.error(childPath(p, "links"), "no root: one link must have no parent (the parents form a cycle)");
      return r;
    }
    if (!d.empty() || !orderLinks(o, r->links, paths)) return r;
  }
  if (r->links.empty()) return r;
  if (r->links.size() > kMaxLinks) {
    d.error(childPath(p, o.has("links") ? "links" : o.has("urdf") ? "urdf" : o.has("mjcf") ? "mjcf" : "figure"),
            std::to_string(r->links.size()) + " links, more than the limit of " + std::to_string(kMaxLinks));
    return r;
  }
  for (auto& l : r->links)
    if (!(l.mass.mass > 0 && l.mass.mass <= 1e6 && l.mass.inertia.allFinite() && l.mass.inertia.diagonal().minCoeff() > 0 &&
          l.mass.inertia.diagonal().maxCoeff() < 1e12)) {
      d.error(childPath(p, o.has("links") ? "links" : o.has("urdf") ? "urdf" : o.has("mjcf") ? "mjcf" : "figure"),
              "link '" + l.name + "' has no usable mass and inertia (mass " + formatNumber(l.mass.mass, 3) +
                  " kg; at most 1e6 kg, inertia positive and below 1e12 kg·m²)");
      return r;
    }
  // Pose keys: [{time, joints: {link: angle_deg}}], times increasing.
  double last = -1e300;
  readList(o, "poses", [&](Obj& ko) {
    PoseKey key;
    key.time = ko.number("time", 0.0, Range::closed(0.0, 1e6));
    if (key.time <= last) d.error(childPath(ko.path(), "time"), "pose keys must be in increasing time");
    last = key.time;
    if (const Json* j = ko.raw("joints")) {
      const std::string jp = childPath(ko.path(), "joints");
      if (!j->is_object()) d.error(jp, "expected an object of link names → angle_deg");
      else
        for (const auto& [name, value] : j->items()) {
          const int i = namedLink(ko, r->links, name, childPath(jp, name));
          if (i < 0) continue;
          const std::size_t n = static_cast<std::size_t>(jointDofs(r->links[static_cast<std::size_t>(i)].joint.type));
          if (auto a = anglesOf(&value, childPath(jp, name), d, n)) key.targets.emplace_back(i, *a);
        }
    } else {
      d.error(childPath(ko.path(), "joints"), "missing required key");
    }
    r->poses.push_back(std::move(key));
  });
  r->gravity_compensation = o.boolean("gravity_compensation", false);
  // The human figure's controllers: `balance`, `protect` and `stand_up`, true or their keys.
  auto controller = [&](const char* key, bool& on, auto&& keys) {
    const Json* j = o.raw(key);
    if (!j) return;
    if (!o.has("figure")) {
      d.error(childPath(p, key), std::string(key) + " controls a human figure (\"figure\": \"human\")");
      return;
    }
    if (j->is_boolean()) {
      on = j->get<bool>();
      return;
    }
    on = true;
    readObjectKey(o, key, keys);
  };
  ControllersDesc& cd = r->controllers;
  controller("balance", cd.balance, [&](Obj& b) {
    cd.position_gain = b.number("position_gain", cd.position_gain, Range::closed(0.0, 1e3));
    cd.velocity_gain = b.number("velocity_gain", cd.velocity_gain, Range::closed(0.0, 1e3));
    cd.margin = b.number("margin", cd.margin, Range::closed(0.0, 1.0));
  });
  controller("protect", cd.protect, [&](Obj& b) { cd.reach_deg = b.number("reach_deg", cd.reach_deg, Range::closed(0.0, 180.0)); });
  controller("stand_up", cd.stand_up, [&](Obj& b) { cd.stand_up_wait = b.number("wait", cd.stand_up_wait, Range::closed(0.0, 1e6)); });
  // Pushes: [{time, link, impulse}].
  readList(o, "pushes", [&](Obj& po) {
    PushDesc push;
    push.time = po.number("time", 0.0, Range::closed(0.0, 1e6));
    const std::string name = po.string("link", true).value_or("");
    push.link = findLink(r->links, name);
    if (push.link < 0 && !name.empty())
      d.error(childPath(po.path(), "link"), "no link '" + name + "' (nearest: '" + nearest(name, linkNames(r->links)) + "')");
    push.impulse = po.vec3("impulse", Vec3::Zero(), Range::closed(-1e6, 1e6));
    if (push.link >= 0) r->pushes.push_back(push);
  });
  // Each link's object at its start pose.
  std::vector<Mat3> R;
  std::vector<Vec3> x;
  startPoses(*r, R, x);
  for (std::size_t i = 0; i < r->links.size(); ++i) {
    ObjectDesc ob = linkObject(r->links[i], R[i], x[i], body.name);
    ob.path = p;
    ob.surface = surface;
    ob.species_surface = species;
    r->objects.push_back(std::move(ob));
  }
  return r;
}

}  // namespace reel::io
