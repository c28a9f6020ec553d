// The `face` kind's reader: the head, its tissue, muscles, activations, eyes and drawing
// (docs/face.md).
#include <algorithm>
#include <memory>
#include <set>

#include "core/format.h"
#include "core/scene/face.h"
#include "io/scene/reader.h"
#include "io/scene/readers.h"

namespace reel::io {
namespace {

const Range kTimes{0.0, 1e6, false, false};

void readLayer(Obj& o, const std::string& key, FaceLayerDesc& layer) {
  readObjectKey(o, key, [&](Obj& lo) {
    layer.thickness = lo.number("thickness", layer.thickness, Range{0.0, 0.1, true, false});
    layer.modulus = lo.number("modulus", layer.modulus, Range{0.0, 1e9, true, false});
  });
}

// A list of name → number pairs in [0, 1] (contractions, preset amounts).
std::vector<std::pair<std::string, double>> readAmounts(Obj& o, const std::string& key) {
  std::vector<std::pair<std::string, double>> out;
  const Json* j = o.raw(key);
  if (!j) return out;
  const std::string p = childPath(o.path(), key);
  if (!j->is_object()) {
    o.diag().error(p, "expected an object of names and contractions, got " + typeName(*j));
    return out;
  }
  for (const auto& [name, value] : j->items())
    if (auto v = readNumber(value, childPath(p, name), o.diag(), kUnit)) out.emplace_back(name, *v);
  return out;
}

bool isPreset(const std::string& name) {
  return std::any_of(kFacePresets.begin(), kFacePresets.end(), [&](const FacePreset& p) { return name == p.name; });
}

std::vector<std::string> presetNames() {
  std::vector<std::string> out;
  for (const FacePreset& p : kFacePresets) out.push_back(p.name);
  return out;
}

void readMuscle(Obj& mo, FaceMuscleDesc& m) {
  Diagnostics& d = mo.diag();
  m.path = mo.path();
  m.name = mo.string("name", true).value_or("");
  m.sphincter = mo.choice("type", "linear", {"linear", "sphincter"}) == "sphincter";
  m.strength = mo.number("strength", m.strength, Range{0.0, 1e4, true, false});
  m.bulge = mo.number("bulge", m.bulge, Range::closed(0.0, 2.0));
  if (!m.sphincter) {
    m.attachment = mo.vec3("attachment", Range::any(), true).value_or(Vec3::Zero());
    m.insertion = mo.vec3("insertion", Range::any(), true).value_or(Vec3::Zero());
    m.angle_deg = mo.number("angle_deg", m.angle_deg, Range{0.0, 90.0, true, false});
    m.falloff_start = mo.number("falloff_start", m.falloff_start, kPos);
    m.falloff_end = mo.number("falloff_end", m.falloff_end, kPos);
    if (m.falloff_end <= m.falloff_start) d.error(childPath(m.path, "falloff_end"), "must be greater than falloff_start");
  } else {
    m.center = mo.vec3("center", Range::any(), true).value_or(Vec3::Zero());
    if (auto n = readHeading(mo, "normal")) m.normal = *n;
    if (auto r = mo.numbers<2>("radii", Range{0.0, 1.0, true, false})) m.radii = *r;
  }
}

void readFace(Obj& o, FaceDesc& f) {
  Diagnostics& d = o.diag();
  const std::string& p = o.path();
  f.mesh = readMeshFile(o, "mesh", false, &f.mesh_file);
  f.skull = readMeshFile(o, "skull", false, &f.skull_file);
  f.inset = o.number("inset", 0.0, Range{0.0, 0.1, false, false});
  if (f.mesh && !f.skull && f.inset == 0.0) d.error(childPath(p, "mesh"), "a face mesh needs its `skull` mesh or an `inset` (m)");
  if (!f.mesh && (o.has("skull") || o.has("inset"))) d.error(childPath(p, o.has("skull") ? "skull" : "inset"), "needs a face `mesh`");
  if (f.skull && f.inset > 0) d.error(childPath(p, "inset"), "give a skull mesh or an inset, not both");
  f.height = o.number("height", f.height, Range{0.01, 10.0, false, false});
  // (at [128, 128] the face settles in about 50 s on two cores and steps slowly: past it, nothing
  // a film can use)
  if (auto r = o.integers<2>("resolution", 16, 128)) f.resolution = {static_cast<int>((*r)[0]), static_cast<int>((*r)[1])};
  if (f.resolution[1] < 16) d.error(childPath(p, "resolution"), "needs at least 16 rows");
  f.position = o.vec3("position", f.position);
  f.rotation_deg = o.vec3("rotation_deg", f.rotation_deg);
  readList(o, "keys", [&](Obj& ko) {
    FacePoseKey k;
    k.time = ko.number("time", kTimes, true).value_or(0.0);
    k.rotation_deg = ko.vec3("rotation_deg", Vec3::Zero());
    if (!f.keys.empty() && k.time <= f.keys.back().time) d.error(childPath(ko.path(), "time"), "keyframe times must increase");
    f.keys.push_back(k);
  });
  if (!f.keys.empty() && o.has("rotation_deg")) d.error(childPath(p, "rotation_deg"), "the head turns by its keys or stays at rotation_deg, not both");
  readLayer(o, "epidermis", f.epidermis);
  readLayer(o, "dermis", f.dermis);
  readLayer(o, "muscle", f.muscle);
  if (!f.mesh && f.dermis.thickness + f.muscle.thickness > 0.1 * f.height)
    d.error(childPath(p, "dermis"), "the dermis and muscle layers are together " + std::to_string(f.dermis.thickness + f.muscle.thickness) +
                                        " m thick, more than a tenth of the head's height: they would cross the skull");
  readObjectKey(o, "biphasic", [&](Obj& bo) {
    f.biphasic_strain = bo.number("strain", f.biphasic_strain, Range{0.0, 10.0, true, false});
    f.biphasic_ratio = bo.number("ratio", f.biphasic_ratio, Range{1.0, 100.0, false, false});
  });
  f.volume_modulus = o.number("volume_modulus", f.volume_modulus, Range{0.0, 1e9, false, false});
  f.density = o.number("density", f.density, Range{1.0, 1e5, false, false});
  f.damping = o.number("damping", f.damping, Range{0.0, 1e4, false, false});
  f.spring_damping = o.number("spring_damping", f.spring_damping, Range{0.0, 1.0, false, false});
  f.gravity_scale = o.number("gravity_scale", f.gravity_scale, Range{0.0, 10.0, false, false});
  f.default_muscles = o.boolean("default_muscles", !f.mesh);
  if (f.mesh && f.default_muscles) d.error(childPath(p, "default_muscles"), "reel's muscles fit reel's head only; give `muscles` for a mesh");
  // Muscle and control names: unique, not a control's.
  std::set<std::string> names;
  if (f.default_muscles) {
    for (const char* m : kFacePairedMuscles) names.insert(std::string(m) + "_left"), names.insert(std::string(m) + "_right");
    for (const char* m : kFaceMidlineMuscles) names.insert(m);
  }
  for (const char* c : kFaceControls) names.insert(c);
  readList(o, "muscles", [&](Obj& mo) {
    FaceMuscleDesc m;
    readMuscle(mo, m);
    if (!m.name.empty() && !names.insert(m.name).second)
      d.error(childPath(mo.path(), "name"), "\"" + m.name + "\" names a muscle or control already");
    f.muscles.push_back(std::move(m));
  });
  readList(o, "activations", [&](Obj& ko) {
    FaceActivationKey k;
    k.path = ko.path();
    k.time = ko.number("time", kTimes, true).value_or(0.0);
    if (auto pr = ko.string("preset")) {
      if (!isPreset(*pr)) {
        const std::string near = nearest(*pr, presetNames());
        d.error(childPath(ko.path(), "preset"), "unknown preset \"" + *pr + "\"" + (near.empty() ? "" : " (did you mean \"" + near + "\"?)"));
      }
      k.presets.emplace_back(*pr, ko.number("amount", 1.0, kUnit));
    } else if (ko.has("amount")) {
      d.error(childPath(ko.path(), "amount"), "is the amount of a `preset`");
    }
    for (auto& [name, amount] : readAmounts(ko, "presets")) {
      if (!isPreset(name)) d.error(childPath(childPath(ko.path(), "presets"), name), "unknown preset \"" + name + "\"");
      k.presets.emplace_back(name, amount);
    }
    k.side = ko.choice("side", "both", {"both", "left", "right"});
    k.muscles = readAmounts(ko, "muscles");
    for (const auto& [name, amount] : k.muscles) {
      const bool known = names.count(name) || names.count(name + "_left");
      if (!known) {
        std::vector<std::string> all(names.begin(), names.end());
        for (const char* m : kFacePairedMuscles) all.emplace_back(m);
        const std::string near = nearest(name, all);
        d.error(childPath(childPath(ko.path(), "muscles"), name),
                "unknown muscle or control \"" + name + "\"" + (near.empty() ? "" : " (did you mean \"" + near + "\"?)"));
      }
    }
    if (!f.activations.empty() && k.time <= f.activations.back().time)
      d.error(childPath(ko.path(), "time"), "keyframe times must increase");
    f.activations.push_back(std::move(k));
  });
  if (const Json* b = o.raw("blinks")) {
    const std::string bp = childPath(p, "blinks");
    if (!b->is_array()) d.error(bp, "expected a list of times, got " + typeName(*b));
    else
      for (std::size_t i = 0; i < b->size(); ++i)
        if (auto t = readNumber((*b)[i], childPath(bp, i), d, kTimes)) f.blinks.push_back(*t);
  }
  readList(o, "gaze", [&](Obj& go) {
    FaceGazeKey g;
    g.time = go.number("time", kTimes, true).value_or(0.0);
    g.target = go.vec3("target", Range::any(), true).value_or(Vec3::UnitZ());
    if (!f.gaze.empty() && g.time <= f.gaze.back().time) d.error(childPath(go.path(), "time"), "keyframe times must increase");
    f.gaze.push_back(g);
  });
  if (const Json* dr = o.raw("draw")) {
    if (dr->is_string()) {
      const std::string mode = dr->get<std::string>();
      if (mode != "skin" && mode != "layers") d.error(childPath(p, "draw"), "expected \"skin\" or \"layers\", got \"" + mode + "\"");
      f.draw.push_back({0.0, mode == "layers"});
    } else {
      std::string fade_before;  // the previous key's fade's path
      readList(o, "draw", [&](Obj& ko) {
        FaceDrawKey k;
        k.time = ko.number("time", kTimes, true).value_or(0.0);
        k.layers = ko.choice("mode", "skin", {"skin", "layers"}) == "layers";
        k.fade = ko.number("fade", 0.0, Range::closed(0.0, 10.0));
        // A fade dissolves the mode before (skin before the first key) into this one: it needs a
        // change of mode, and ends before the next key.
        const bool before = !f.draw.empty() && f.draw.back().layers;
        if (k.fade > 0 && k.layers == before)
          d.error(childPath(ko.path(), "fade"), std::string("fades from \"") + (before ? "layers" : "skin") + "\" into the same mode");
        if (!f.draw.empty() && k.time <= f.draw.back().time) d.error(childPath(ko.path(), "time"), "keyframe times must increase");
        else if (!f.draw.empty() && f.draw.back().fade > k.time - f.draw.back().time)
          d.error(fade_before, "runs past the next draw key, at " + formatNumber(k.time, 6) + " s");
        fade_before = childPath(ko.path(), "fade");
        f.draw.push_back(k);
      });
    }
  }
  if (auto c = o.vec3("iris_color", Range::closed(0.0, 1.0))) f.iris_color = *c;
  // reel's head's looks, shoulders and held scalp: refused on a user's mesh, which has none of them.
  for (const char* key : {"sex", "age", "build", "shoulders", "held_beyond"})
    if (f.mesh && o.has(key)) d.error(childPath(p, key), "shapes reel's own head; a face with a `mesh` has none");
  f.look.sex = o.number("sex", f.look.sex, Range::closed(0.0, 1.0));
  f.look.age = o.number("age", f.look.age, Range::closed(18.0, 90.0));
  f.look.build = o.number("build", f.look.build, Range::closed(0.0, 1.0));
  f.shoulders = o.boolean("shoulders", f.shoulders);
  f.held_beyond = o.number("held_beyond", f.held_beyond, Range::closed(0.0, 1.0));
  readList(o, "visemes", [&](Obj& vo) {
    FaceVisemeKey v;
    v.path = vo.path();
    v.time = vo.number("time", kTimes, true).value_or(0.0);
    v.viseme = vo.string("viseme", true).value_or("rest");
    v.amount = vo.number("amount", 1.0, kUnit);
    std::vector<std::string> visemes{"rest"};
    for (const FacePreset& fp : kFaceVisemes) visemes.emplace_back(fp.name);
    if (std::find(visemes.begin(), visemes.end(), v.viseme) == visemes.end()) {
      const std::string near = nearest(v.viseme, visemes);
      d.error(childPath(vo.path(), "viseme"), "unknown viseme \"" + v.viseme + "\"" + (near.empty() ? "" : " (did you mean \"" + near + "\"?)"));
    }
    if (!f.visemes.empty() && v.time <= f.visemes.back().time) d.error(childPath(vo.path(), "time"), "keyframe times must increase");
    f.visemes.push_back(std::move(v));
  });
}

}  // namespace

std::shared_ptr<const BodyParams> readFaceBody(Obj& o, BodyDesc& body, const SceneDesc&) {
  auto f = std::make_shared<FaceDesc>();
  // Skin's colours are per vertex: the material multiplies them.
  body.material.color = Vec3(1, 1, 1);
  body.material.specular = 0.2;
  // Rough (dull where hair covers reel's head; its skin's per-vertex gloss smooths the rest).
  body.material.roughness = 0.7;
  readFace(o, *f);
  return f;
}

}  // namespace reel::io
