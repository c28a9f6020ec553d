// The `school` kind's reader: the agents, the model's keys, the shared steering and the look.
#include <algorithm>
#include <memory>

#include "core/format.h"
#include "core/scene/school.h"
#include "io/scene/reader.h"
#include "io/scene/readers.h"

namespace reel::io {
namespace {

// Bounded so that no product of them overflows: speeds, m/s; lengths, m; times, s.
const Range kSpeed{0.0, 1000.0, true, false}, kTime{0.0, 1e4, false, false},
    kWeight{0.0, 1e6, false, false};

// Agents one machine holds: a tenth of its memory at about 1 KiB per agent (state, grid, drawing
// data), at most 50 million.
// A tenth of memory at about 1 KiB an agent, and at most a million: a school of a million steps
// in about 1.5 s on two cores (docs/schools.md); a scene that wants more says so (max_agents).
long long defaultMaxAgents() { return itemsInMemory(0.1, 1024, 10'000, 1'000'000, 1'000'000); }

void readAgents(Obj& o, SchoolDesc& s, long long max_agents) {
  const bool listed = o.has("agents");
  if (listed) {
    readList(o, "agents", [&](Obj& a) {
      SchoolAgentDesc ag;
      ag.position = a.vec3("position", Range::any(), true).value_or(Vec3::Zero());
      ag.heading = readHeading(a, "heading");
      if (auto v = a.number("speed", kSpeed)) ag.speed = *v;
      s.agents.push_back(ag);
    });
    if (o.has("count")) o.diag().error(childPath(o.path(), "count"), "give count or agents, not both");
  } else {
    s.count = o.integer("count", 1ll, 50'000'000ll, true).value_or(0);
    if (s.count > max_agents)
      o.diag().error(childPath(o.path(), "count"), std::to_string(s.count) + " agents, more than max_agents = " +
                                                       std::to_string(max_agents) + " (set \"max_agents\" for more, up to 50000000)");
  }
  if (listed && s.agents.empty()) o.diag().error(childPath(o.path(), "agents"), "must list at least one agent");
  if (static_cast<long long>(s.agents.size()) > max_agents)
    o.diag().error(childPath(o.path(), "agents"), std::to_string(s.agents.size()) + " agents, more than max_agents = " +
                                                      std::to_string(max_agents));
  readStart(o, s.start);
}

// `"orientation": [{"time": t, "value": r_o}, ...]`: r_o over time (times increasing).
void readOrientationKeys(Obj& zo, CouzinDesc& c) {
  readList(zo, "orientation", [&](Obj& k) {
    const double t = k.number("time", kNonNeg, true).value_or(0.0);
    const double r = k.number("value", Range::closed(0.0, 1e4), true).value_or(0.0);
    if (!c.orientation_keys.empty() && t <= c.orientation_keys.back().first)
      k.diag().error(childPath(k.path(), "time"), "times must increase");
    c.orientation_keys.emplace_back(t, r);
  });
  if (c.orientation_keys.empty()) zo.diag().error(childPath(zo.path(), "orientation"), "must list at least one key");
  else c.r_orientation = c.orientation_keys.front().second;
}

void readCouzin(Obj& o, SchoolDesc& s) {
  CouzinDesc& c = s.couzin;
  if (const Json* z = o.raw("zones")) {
    Obj zo(*z, childPath(o.path(), "zones"), o.diag());
    c.r_repulsion = zo.number("repulsion", c.r_repulsion, Range::closed(0.0, 1e4));
    const Json* ro = zo.raw("orientation");
    if (ro && ro->is_array()) {
      readOrientationKeys(zo, c);
    } else {
      c.r_orientation = zo.number("orientation", c.r_orientation, Range::closed(0.0, 1e4));
    }
    c.r_attraction = zo.number("attraction", c.r_attraction, kLength);
    for (const auto& [t, r] : c.orientation_keys)
      if (!(c.r_repulsion <= r && r <= c.r_attraction))
        o.diag().error(childPath(zo.path(), "orientation"), "every key's value must lie between repulsion and attraction (got " + formatNumber(r, 3) + " at " + formatNumber(t, 3) + " s)");
    if (!(c.r_repulsion <= c.r_orientation && c.r_orientation <= c.r_attraction))
      o.diag().error(zo.path(), "the radii must satisfy repulsion ≤ orientation ≤ attraction (got " +
                                    formatNumber(c.r_repulsion, 3) + ", " + formatNumber(c.r_orientation, 3) + ", " +
                                    formatNumber(c.r_attraction, 3) + ")");
    zo.finish();
  }
  c.max_turn_deg_per_s = o.number("max_turn_deg_per_s", c.max_turn_deg_per_s, Range{0.0, 36000.0, true, false});
  c.noise = o.number("noise", c.noise, Range::closed(0.0, 10.0));
  c.reaction_time = o.number("reaction_time", c.reaction_time, Range{0.0, 100.0, true, false});
}

// A rule's radius and weight.
void readRule(Obj& o, const std::string& key, double& radius, double& weight) {
  if (const Json* r = o.raw(key)) {
    Obj ro(*r, childPath(o.path(), key), o.diag());
    radius = ro.number("radius", radius, kLength);
    weight = ro.number("weight", weight, kWeight);
    ro.finish();
  }
}

void readBoids(Obj& o, SchoolDesc& s) {
  BoidsDesc& b = s.boids;
  readRule(o, "separation", b.separation_radius, b.separation_weight);
  readRule(o, "alignment", b.alignment_radius, b.alignment_weight);
  readRule(o, "cohesion", b.cohesion_radius, b.cohesion_weight);
  b.max_speed = o.number("max_speed", std::max(b.max_speed, s.speed), kSpeed);
  b.min_speed = o.number("min_speed", std::min(b.min_speed, b.max_speed), kSpeed);
  b.max_accel = o.number("max_accel", b.max_accel, Range{0.0, 1e6, true, false});
  if (b.min_speed > b.max_speed)
    o.diag().error(childPath(o.path(), "min_speed"), "must not be above max_speed (" + formatNumber(b.max_speed, 3) + ")");
}

// Keys of the other model are refused by name rather than as unknown keys.
void refuseOtherModel(Obj& o, const std::string& model, std::initializer_list<const char*> keys) {
  for (const char* k : keys)
    if (o.has(k)) o.diag().error(childPath(o.path(), k), "is a key of model \"" + std::string(model == "couzin" ? "boids" : "couzin") + "\" (this school's model is \"" + model + "\")");
}

void readTarget(Obj& g, TargetDesc& t) {
  const bool path = g.has("path");
  if (path) {
    readList(g, "path", [&](Obj& k) {
      TargetDesc::Key key;
      key.time = k.number("time", kNonNeg, true).value_or(0.0);
      key.position = k.vec3("position", Range::any(), true).value_or(Vec3::Zero());
      if (!t.keys.empty() && key.time <= t.keys.back().time) k.diag().error(childPath(k.path(), "time"), "times must increase");
      t.keys.push_back(key);
    }, true);
    if (g.has("position")) g.diag().error(childPath(g.path(), "position"), "give position or path, not both");
  } else if (auto p = g.vec3("position", Range::any(), true)) {
    t.keys.push_back({0.0, *p});
  }
}

}  // namespace

void readBounds(Obj& bo, SchoolBoundsDesc& bd) {
  bd.sphere = bo.has("center") || bo.has("radius");
  if (bd.sphere) {
    bd.center = bo.vec3("center", bd.center);
    bd.radius = bo.number("radius", kLength, true).value_or(bd.radius);
  } else {
    bd.min = bo.vec3("min", Range::any(), true).value_or(bd.min);
    bd.max = bo.vec3("max", Range::any(), true).value_or(bd.max);
    if (!(bd.min.array() < bd.max.array()).all()) bo.diag().error(childPath(bo.path(), "max"), "must be above min on every axis");
  }
  bd.margin = bo.number("margin", bd.margin, kLength);
}

namespace {

void readGoal(Obj& go, SchoolDesc& s) {
  SchoolGoalDesc gd;
  readTarget(go, gd.target);
  gd.weight = go.number("weight", gd.weight, kWeight);
  gd.informed = go.number("informed", gd.informed, kUnit);
  s.goal = gd;
}

void readPredator(Obj& po, SchoolDesc& s, const SceneDesc& scene) {
  Diagnostics& d = po.diag();
  SchoolPredatorDesc pd;
  pd.path = po.path();
  pd.is_school = po.has("school");
  const std::string key = pd.is_school ? "school" : "object";
  pd.name = po.string(key, true).value_or("");
  if (pd.is_school && po.has("object")) d.error(childPath(po.path(), "object"), "give school or object, not both");
  pd.fear_radius = po.number("fear_radius", pd.fear_radius, kLength);
  // A predator school comes before its prey in `bodies`: it has moved when the prey looks.
  const bool found = pd.is_school ? std::any_of(scene.bodies.begin(), scene.bodies.end(), [&](const BodyDesc& b) { return b.type == "school" && b.name == pd.name; })
                                  : objectIndex(scene, pd.name) >= 0;
  if (!found && !pd.name.empty())
    d.error(childPath(po.path(), key), "names no " + key + " of the scene: \"" + pd.name + "\"" +
                                            (pd.is_school ? " (a predator school must come before its prey in bodies)" : ""));
  s.predator = pd;
}

void readSteering(Obj& o, SchoolDesc& s, const SceneDesc& scene) {
  readObjectKey(o, "avoid", [&](Obj& ao) {
    s.look_ahead = ao.number("look_ahead", s.look_ahead, kTime);
    s.avoid_margin = ao.number("margin", s.avoid_margin, kLength);
  });
  readObjectKey(o, "bounds", [&](Obj& bo) {
    SchoolBoundsDesc bd;
    readBounds(bo, bd);
    s.bounds = bd;
  });
  readObjectKey(o, "goal", [&](Obj& go) { readGoal(go, s); });
  readObjectKey(o, "predator", [&](Obj& po) { readPredator(po, s, scene); });
}

}  // namespace

std::shared_ptr<const BodyParams> readSchoolBody(Obj& o, BodyDesc& body, const SceneDesc& scene) {
  auto s = std::make_shared<SchoolDesc>();
  const std::string model = o.choice("model", "couzin", {"couzin", "boids"});
  s->model = model == "boids" ? SchoolModel::Boids : SchoolModel::Couzin;
  const long long max_agents = o.integer("max_agents", 1ll, 50'000'000ll).value_or(defaultMaxAgents());
  readAgents(o, *s, max_agents);
  s->speed = o.number("speed", s->speed, kSpeed);
  s->field_of_view_deg = o.number("field_of_view_deg", s->field_of_view_deg, Range{0.0, 360.0, true, false});
  if (s->model == SchoolModel::Couzin) {
    readCouzin(o, *s);
    refuseOtherModel(o, model, {"separation", "alignment", "cohesion", "min_speed", "max_speed", "max_accel"});
  } else {
    readBoids(o, *s);
    refuseOtherModel(o, model, {"zones", "max_turn_deg_per_s", "noise", "reaction_time"});
  }
  readSteering(o, *s, scene);
  s->length = o.number("length", s->length, Range{0.0, 1000.0, true, false});
  s->color_variation = o.number("color_variation", s->color_variation, kUnit);
  if (o.has("mesh")) s->mesh = readMeshFile(o, "mesh", true, &s->mesh_file);
  body.material.color = Vec3(0.55, 0.6, 0.65);  // silver-grey fish unless told otherwise
  body.material.specular = 0.4;
  body.material.shininess = 48.0;
  return s;
}

}  // namespace reel::io
