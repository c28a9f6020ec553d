// The readers of the fish world's kinds: `fish`, `food`, `seaweed` (docs/fish.md).
#include <algorithm>
#include <memory>

#include "core/format.h"
#include "core/scene/fish.h"
#include "io/scene/reader.h"
#include "io/scene/readers.h"

namespace reel::io {
namespace {

const Range kSpeedBl{0.0, 100.0, true, false}, kTimes{0.0, 1e6, false, false};

// The species presets: habits, size, speeds, senses, mood and look.
void preset(FishDesc& f, BodyDesc& body) {
  Material& m = body.material;
  m.specular = 0.35, m.shininess = 40.0;
  switch (f.species) {
    case FishSpecies::Prey:
      f.habits = {true, false, false, 0.9};
      f.length = 0.3, f.cruise_speed = 1.2, f.max_speed = 3.0, f.vision_radius = 6.0;
      f.pattern = "stripes", m.color = Vec3(0.55, 0.62, 0.72), f.pattern_color = Vec3(0.08, 0.1, 0.16);
      break;
    case FishSpecies::Predator:
      f.habits = {false, true, false, 0.0};
      f.length = 1.0, f.cruise_speed = 0.7, f.max_speed = 2.0, f.vision_radius = 12.0, f.hunger = 0.8;
      f.digestion = 0.08;
      f.pattern = "gradient", m.color = Vec3(0.35, 0.38, 0.42), f.pattern_color = Vec3(0.12, 0.13, 0.16);
      break;
    case FishSpecies::Pacifist:
      f.habits = {false, false, true, 0.6};
      f.length = 0.45, f.cruise_speed = 0.9, f.max_speed = 2.4, f.vision_radius = 8.0, f.libido = 0.3;
      f.urge = 0.05;
      f.pattern = "spots", m.color = Vec3(0.85, 0.42, 0.12), f.pattern_color = Vec3(0.95, 0.9, 0.8);
      break;
  }
}

// A muscle name: "<front|middle|rear>_<left|right>" (both of the side) or with "_upper"/"_lower".
std::vector<int> muscleNames(const std::string& name) {
  for (int seg = 0; seg < 3; ++seg)
    for (int side = 0; side < 2; ++side) {
      const std::string stem = std::string(kFishSegments[static_cast<std::size_t>(seg)]) + "_" + kFishSides[static_cast<std::size_t>(side)];
      const int first = 4 * seg + 2 * side;
      if (name == stem) return {first, first + 1};
      if (name == stem + "_upper") return {first};
      if (name == stem + "_lower") return {first + 1};
    }
  return {};
}

void readDrive(Obj& o, FishDesc& f) {
  FishDriveDesc& d = f.drive;
  readObjectKey(o, "swim", [&](Obj& so) {
    d.swim_frequency = so.number("frequency", d.swim_frequency, Range::closed(0.0, 100.0));
    d.swim_amplitude = so.number("amplitude", d.swim_amplitude, kUnit);
    d.swim_start = so.number("start", d.swim_start, kTimes);
    d.swim_stop = so.number("stop", d.swim_stop, kTimes);
  });
  readObjectKey(o, "turn", [&](Obj& to) {
    d.turn_side = to.choice("side", "left", {"left", "right"}) == "left" ? 1 : -1;
    d.turn_amount = to.number("amount", d.turn_amount, kUnit);
    d.turn_start = to.number("start", 0.0, kTimes);
    if (to.has("angle_deg")) {
      d.turn_angle_deg = to.number("angle_deg", Range{0.0, 3600.0, true, false}, true).value_or(0.0);
      d.turn_stop = 1e30;
      if (to.has("stop")) o.diag().error(childPath(to.path(), "stop"), "give angle_deg or stop, not both");
    } else {
      d.turn_stop = to.number("stop", Range::nonNegative(), true).value_or(0.0);
      if (d.turn_stop <= d.turn_start) o.diag().error(childPath(to.path(), "stop"), "must be after start");
    }
  });
  d.pitch_deg = o.number("pitch_deg", d.pitch_deg, Range::closed(-60.0, 60.0));
  d.yaw_deg = o.number("yaw_deg", d.yaw_deg, Range::closed(-60.0, 60.0));
  readList(o, "muscles", [&](Obj& m) {
    MusclePatternDesc p;
    const std::string name = m.string("muscle", true).value_or("");
    p.muscles = muscleNames(name);
    if (p.muscles.empty() && !name.empty())
      m.diag().error(childPath(m.path(), "muscle"), "names no muscle: \"" + name + "\" (muscles are <front|middle|rear>_<left|right>, optionally with _upper or _lower)");
    p.contraction = m.number("contraction", kUnit, true).value_or(0.0);
    p.frequency = m.number("frequency", p.frequency, Range::closed(0.0, 100.0));
    p.phase_deg = m.number("phase_deg", p.phase_deg, Range::closed(-3600.0, 3600.0));
    p.start = m.number("start", p.start, kTimes);
    p.stop = m.number("stop", p.stop, kTimes);
    d.muscles.push_back(p);
  });
}

}  // namespace

std::shared_ptr<const BodyParams> readFishBody(Obj& o, BodyDesc& body, const SceneDesc& scene) {
  auto f = std::make_shared<FishDesc>();
  const std::string species = o.choice("species", "prey", {"prey", "predator", "pacifist"});
  f->species = species == "predator" ? FishSpecies::Predator : species == "pacifist" ? FishSpecies::Pacifist : FishSpecies::Prey;
  preset(*f, body);
  f->count = o.integer("count", 1ll, 100'000ll).value_or(1);
  f->start_given = o.has("start") || f->count > 1;
  readStart(o, f->start);
  if (!f->start_given) {
    f->position = o.vec3("position", f->position);
    f->heading = f->start.heading;
  } else if (o.has("position")) {
    o.diag().error(childPath(o.path(), "position"), "give position (one fish) or start and count, not both");
  }
  // At least a centimetre: smaller bodies have nodes below reel's smallest mass.
  f->length = o.number("length", f->length, Range::closed(0.01, 100.0));
  f->cruise_speed = o.number("cruise_speed", f->cruise_speed, kSpeedBl);
  f->max_speed = o.number("max_speed", std::max(f->max_speed, f->cruise_speed), kSpeedBl);
  f->behaviour = o.choice("behaviour", "full", {"full", "none"}) == "full";
  readObjectKey(o, "drive", [&](Obj& dobj) { readDrive(dobj, *f); });
  if (f->behaviour && o.has("drive"))
    o.diag().error(childPath(o.path(), "drive"), "needs \"behaviour\": \"none\" (the behaviour drives the motor controllers otherwise)");
  readObjectKey(o, "mental", [&](Obj& mo) {
    f->hunger = mo.number("hunger", f->hunger, kUnit);
    f->libido = mo.number("libido", f->libido, kUnit);
    f->fear = mo.number("fear", f->fear, kUnit);
  });
  f->digestion = o.number("digestion", f->digestion, Range::closed(0.0, 100.0));
  f->urge = o.number("urge", f->urge, Range::closed(0.0, 100.0));
  readObjectKey(o, "perception", [&](Obj& po) {
    f->vision_radius = po.number("vision_radius", f->vision_radius, kLength);
    f->field_of_view_deg = po.number("field_of_view_deg", f->field_of_view_deg, Range{0.0, 360.0, true, false});
    f->smell_radius = po.number("smell_radius", std::max(f->smell_radius, f->vision_radius), kLength);
  });
  readObjectKey(o, "habits", [&](Obj& ho) {
    f->habits.schools = ho.boolean("schools", f->habits.schools);
    f->habits.hunts = ho.boolean("hunts", f->habits.hunts);
    f->habits.mates = ho.boolean("mates", f->habits.mates);
    f->habits.timidity = ho.number("timidity", f->habits.timidity, kUnit);
  });
  if (auto hook = o.string("hook")) {
    f->hook = *hook;
    if (objectIndex(scene, *hook) < 0)
      o.diag().error(childPath(o.path(), "hook"), "names no object of the scene: \"" + *hook + "\"");
  }
  if (const Json* ig = o.raw("ignore")) {
    const std::string path = childPath(o.path(), "ignore");
    if (!ig->is_array()) o.diag().error(path, "expected a list of object names");
    for (std::size_t k = 0; ig->is_array() && k < ig->size(); ++k) {
      const Json& e = (*ig)[k];
      const std::string name = e.is_string() ? e.get<std::string>() : "";
      if (objectIndex(scene, name) < 0)
        o.diag().error(childPath(path, k), "names no object of the scene" + (name.empty() ? std::string() : ": \"" + name + "\""));
      else f->ignore.push_back(name);
    }
  }
  readObjectKey(o, "bounds", [&](Obj& bo) {
    SchoolBoundsDesc bd;
    readBounds(bo, bd);
    f->bounds = bd;
  });
  f->wireframe = o.choice("draw", "skin", {"skin", "wireframe"}) == "wireframe";
  std::vector<std::string> patterns(std::begin(kFishPatternNames), std::end(kFishPatternNames));
  f->pattern = o.choice("skin", f->pattern, patterns);
  f->pattern_color = o.vec3("skin_color", f->pattern_color, kUnit);
  return f;
}

std::shared_ptr<const BodyParams> readFoodBody(Obj& o, BodyDesc& body, const SceneDesc&) {
  auto f = std::make_shared<FoodDesc>();
  if (!o.has("region")) o.diag().error(childPath(o.path(), "region"), "missing required key: the box food is emitted in ({\"min\": [...], \"max\": [...]})");
  readObjectKey(o, "region", [&](Obj& ro) {
    f->min = ro.vec3("min", Range::any(), true).value_or(f->min);
    f->max = ro.vec3("max", Range::any(), true).value_or(f->max);
    if (!(f->min.array() < f->max.array()).all()) o.diag().error(childPath(ro.path(), "max"), "must be above min on every axis");
  });
  f->max_alive = o.integer("max_alive", 0ll, 1'000'000ll).value_or(f->max_alive);
  f->initial = o.integer("initial", 0ll, f->max_alive).value_or(std::min(f->initial, f->max_alive));
  f->rate = o.number("rate", f->rate, Range::closed(0.0, 1e6));
  f->sink_speed = o.number("sink_speed", f->sink_speed, Range::closed(-100.0, 100.0));
  f->jitter = o.number("jitter", f->jitter, Range::closed(0.0, 100.0));
  f->size = o.number("size", f->size, kLength);
  f->bite = o.number("bite", f->bite, Range::closed(0.0, 1e3));
  body.material.color = Vec3(0.75, 0.8, 0.45);
  return f;
}

std::shared_ptr<const BodyParams> readSeaweedBody(Obj& o, BodyDesc& body, const SceneDesc&) {
  auto s = std::make_shared<SeaweedDesc>();
  if (o.has("bases")) {
    const Json* b = o.raw("bases");
    if (!b->is_array() || b->empty()) {
      o.diag().error(childPath(o.path(), "bases"), "expected a list of points [x, y, z]");
    } else {
      if (b->size() > 100'000) o.diag().error(childPath(o.path(), "bases"), std::to_string(b->size()) + " strands, more than 100000");
      for (std::size_t k = 0; k < b->size() && k < 100'000; ++k)
        if (auto p = readVec3((*b)[k], childPath(childPath(o.path(), "bases"), k), o.diag(), Range::any())) s->bases.push_back(*p);
    }
    if (o.has("count")) o.diag().error(childPath(o.path(), "count"), "give bases or count, not both");
  } else {
    s->count = o.integer("count", 1ll, 100'000ll, true).value_or(0);
    readObjectKey(o, "region", [&](Obj& ro) {
      s->min = ro.vec3("min", Range::any(), true).value_or(s->min);
      s->max = ro.vec3("max", Range::any(), true).value_or(s->max);
    });
  }
  s->height = o.number("height", s->height, kLength);
  s->height_variation = o.number("height_variation", s->height_variation, Range{0.0, 1.0, false, true});
  s->segments = o.integer("segments", s->segments, 2, 200);
  s->mass = o.number("mass", s->mass, Range{0.0, 1e6, true, false});
  checkNodeMass(o, s->mass, s->segments + 1);
  s->stiffness = o.number("stiffness", s->stiffness, Range{0.0, 1e9, true, false});
  s->buoyancy = o.number("buoyancy", s->buoyancy, Range::closed(0.0, 100.0));
  s->drag = o.number("drag", s->drag, Range::closed(0.0, 1e6));
  s->width = o.number("width", s->width, kLength);
  body.material.color = Vec3(0.18, 0.42, 0.12);
  body.material.specular = 0.25;
  return s;
}

}  // namespace reel::io
