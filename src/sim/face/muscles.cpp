#include "sim/face/muscles.h"

#include <algorithm>
#include <cmath>

#include "core/keys.h"
#include "core/math.h"

namespace reel {

std::pair<std::size_t, double> nearestOf(std::span<const Vec3> points, const Vec3& p) {
  std::size_t best = 0;
  double bd = 1e300;
  for (std::size_t k = 0; k < points.size(); ++k) {
    const double d = (points[k] - p).squaredNorm();
    if (d < bd) bd = d, best = k;
  }
  return {best, std::sqrt(bd)};
}

namespace {

}  // namespace

void sphincterAxes(const Vec3& normal, Vec3& u, Vec3& v) {
  v = unitOr(normal.cross(Vec3::UnitX()), Vec3::UnitY());
  u = v.cross(normal).normalized();
}

std::vector<FaceMuscleDesc> defaultMuscles(const FaceSurface& s) {
  const double k = s.scale, ym = s.mouth.y() / k, corner = 0.5 * s.mouth_width / k;
  std::vector<FaceMuscleDesc> out;
  auto bone = [&](double x, double y) { return s.bone[frontVertex(s, k * x, k * y)]; };
  auto tissue = [&](double x, double y) {
    const std::size_t v = frontVertex(s, k * x, k * y);
    return Vec3(0.5 * (s.skin[v] + s.bone[v]));
  };
  // The cheek's muscles thicken as they shorten, their fibres keeping their volume (Kähler, Haber &
  // Seidel 2001, "Geometry-based muscle modeling for facial animation", model a muscle as segments
  // that bulge so), and push the cheek's fat off the bone: the cheek bunches over a smile and the
  // fold from the nose to the mouth's corner deepens. Pulled along the skull alone, the skin slid
  // over it and stretched like rubber, viewers said, the smile in the mouth alone. Half the pull:
  // at a whole one the cheek ballooned past the nose's outline in a three-quarter view. (Not the
  // forehead's, the chin's or the mouth's muscles: thin sheets, and a push there narrowed the open
  // mouth of surprise and fear.)
  constexpr double kCheekBulge = 0.5;
  // (name, attachment x y, insertion x y, strength N, bulge) at height 0.24, the left side (+x).
  struct Linear {
    const char* name;
    double ax, ay, ix, iy, strength;
    double bulge = 0.0;
  };
  const Linear linear[] = {
      {"zygomatic_major", 0.060, -0.012, corner + 0.001, ym, 26.0, kCheekBulge},
      {"zygomatic_minor", 0.046, -0.008, 0.013, ym + 0.007, 2.5, kCheekBulge},
      {"levator_labii", 0.017, -0.006, 0.009, ym + 0.008, 4.5, kCheekBulge},
      {"depressor_anguli_oris", 0.040, ym - 0.040, corner + 0.002, ym + 0.0005, 11.0},
      {"frontalis_inner", 0.015, 0.088, 0.015, 0.025, 5.0},
      {"frontalis_outer", 0.046, 0.082, 0.046, 0.023, 4.5},
      {"corrugator", 0.012, 0.006, 0.030, 0.028, 4.5},
      {"risorius", 0.064, ym - 0.006, corner, ym - 0.001, 6.0},
  };
  for (const Linear& l : linear)
    for (double side : {1.0, -1.0}) {
      FaceMuscleDesc d;
      d.name = std::string(l.name) + (side > 0 ? "_left" : "_right");
      d.attachment = bone(side * l.ax, l.ay);
      d.insertion = tissue(side * l.ix, l.iy);
      d.strength = 1.6 * l.strength * k * k;
      d.bulge = l.bulge;
      // The smile's muscle takes the mouth's corner, not the upper lip (which it would bunch
      // into a crease under the nose).
      if (std::string(l.name) == "zygomatic_major") d.angle_deg = 18.0;
      out.push_back(d);
    }
  for (int e = 0; e < 2; ++e) {
    FaceMuscleDesc d;
    d.name = e == 0 ? "orbicularis_oculi_left" : "orbicularis_oculi_right";
    d.sphincter = true;
    d.center = s.eye[static_cast<std::size_t>(e)];
    d.radii = {0.027 * k, 0.021 * k};
    d.strength = 4.0 * k * k;
    out.push_back(d);
  }
  FaceMuscleDesc oris;
  oris.name = "orbicularis_oris";
  oris.sphincter = true;
  oris.center = s.mouth - Vec3(0, 0, 0.004 * k);
  oris.radii = {0.036 * k, 0.026 * k};
  oris.strength = 6.0 * k * k;
  out.push_back(oris);
  FaceMuscleDesc mentalis;
  mentalis.name = "mentalis";
  mentalis.attachment = bone(0.0, ym - 0.022);
  mentalis.insertion = tissue(0.0, ym - 0.036);
  mentalis.angle_deg = 45;
  mentalis.strength = 4.0 * k * k;
  out.push_back(mentalis);
  // The procerus: from the nasal bones up into the skin between the brows, which it pulls down
  // with the brows' heads (AU4 with the corrugator; AU9). Without it anger's brows drew together
  // but barely lowered, and viewers read the frown as puzzled.
  FaceMuscleDesc procerus;
  procerus.name = "procerus";
  procerus.attachment = bone(0.0, -0.014);
  procerus.insertion = tissue(0.0, 0.018);
  procerus.angle_deg = 45;
  procerus.strength = 10.0 * k * k;
  out.push_back(procerus);
  // The lips' pucker (AU18 lip pucker with AU22 funneler; the incisivii and the orbicularis oris'
  // deep fibres): a ring over the orbicularis oris' zone that draws the lips in, which then bulge
  // forward as the tissue keeps its volume, and, as it thickens, pushes them a little further
  // forward off the teeth (its bulge, along its axis). The orbicularis oris alone pulls toward its
  // centre in the face's plane: "oo" narrowed the mouth by 3 mm and pushed the lips out by under
  // 1, a slot, viewers said (now 10 and 5.6 mm at the default head). (At a bulge of 2 the lower
  // lip's middle stood out in a V that viewers read as a sneer, and stronger still the lips
  // parted in jagged edges; as a pair of linear muscles from beside the midline to the corners,
  // the corners see-sawed in and out as the pull's direction flipped over them.) Listed last, so
  // the muscles and controls before it keep their indices in a dump.
  FaceMuscleDesc pucker;
  pucker.name = "incisivii";
  pucker.sphincter = true;
  pucker.center = s.mouth - Vec3(0, 0, 0.004 * k);  // the orbicularis oris' centre
  pucker.radii = {0.03 * k, 0.02 * k};
  pucker.strength = 20.0 * k * k;
  pucker.bulge = 0.4;
  out.push_back(pucker);
  return out;
}

Result<FaceMuscle> placeMuscle(const FaceMuscleDesc& d, const FaceSurface& s, const std::vector<Vec3>& fascia,
                               const std::string& file) {
  FaceMuscle m;
  m.desc = d;
  auto bad = [&](const std::string& key, const std::string& what) {
    return Error(ErrorKind::BadInput, file + ": " + d.path + "/" + key + ": " + what);
  };
  auto depthAt = [&](std::size_t k) { return (s.skin[k] - s.bone[k]).norm(); };
  if (!d.sphincter) {
    const auto [kb, db] = nearestOf(s.bone, d.attachment);
    const Vec3 out = (s.skin[kb] - s.bone[kb]).normalized();
    if (db > depthAt(kb) || (d.attachment - s.bone[kb]).dot(out) > 0.5 * depthAt(kb))
      return bad("attachment", "muscle '" + d.name + "' is attached outside the skull (" + std::to_string(db) +
                                   " m from the nearest bone point; it must lie on the skull)");
    const auto [ki, di] = nearestOf(fascia, d.insertion);
    const double h = (d.insertion - s.bone[ki]).dot((s.skin[ki] - s.bone[ki]).normalized());
    if (di > 2 * depthAt(ki) || h < -0.25 * depthAt(ki) || h > depthAt(ki))
      return bad("insertion", "muscle '" + d.name + "' is inserted outside the tissue (it must lie between skull and skin)");
    if ((d.insertion - d.attachment).norm() < 1e-6) return bad("insertion", "is at the attachment: the muscle has no length");
    m.jaw = s.jaw[kb];
  } else {
    const auto [kc, dc] = nearestOf(fascia, d.center);
    if (dc > 0.5 * std::max(d.radii[0], d.radii[1]) + 2 * depthAt(kc))
      return bad("center", "sphincter '" + d.name + "' is not on the face (its centre is " + std::to_string(dc) +
                               " m from the tissue)");
  }
  Vec3 u, v;
  sphincterAxes(d.normal.normalized(), u, v);
  const Vec3 n = d.normal.normalized();
  const double L = (d.insertion - d.attachment).norm();
  const Vec3 axis = d.sphincter ? Vec3::Zero() : Vec3((d.insertion - d.attachment) / L);
  const double omega = d.angle_deg * kPi / 180.0, Rs = d.falloff_start * L, Rf = d.falloff_end * L;
  double total = 0.0;
  for (std::size_t k = 0; k < s.size(); ++k) {
    const Vec3 p = fascia[k];
    double w = 0.0;
    if (!d.sphincter) {
      // Waters' linear muscle: angular fall-off cos(μ/Ω · π/2) within the cone, radial fall-off
      // rising to 1 at R_s and falling to 0 at R_f.
      const Vec3 dp = p - d.attachment;
      const double D = dp.norm();
      if (D < 1e-9 || D >= Rf) continue;
      const double mu = std::acos(std::clamp(dp.dot(axis) / D, -1.0, 1.0));
      if (mu >= omega) continue;
      const double radial = D <= Rs ? std::cos((1 - D / Rs) * kPi / 2) : std::cos((D - Rs) / (Rf - Rs) * kPi / 2);
      w = std::cos(mu / omega * kPi / 2) * radial;
    } else {
      // Waters' sphincter: the nodes inside the ellipse, most strongly halfway out (the ring).
      const Vec3 dp = p - d.center;
      const double pu = dp.dot(u) / d.radii[0], pv = dp.dot(v) / d.radii[1], pn = dp.dot(n);
      const double q = std::sqrt(pu * pu + pv * pv);
      if (q >= 1 || std::abs(pn) > std::max(d.radii[0], d.radii[1])) continue;
      w = std::sin(kPi * q);
    }
    if (w > 1e-6) {
      m.nodes.push_back(static_cast<int>(k));
      m.weight.push_back(w);
      total += w;
    }
  }
  if (m.nodes.empty()) return bad(d.sphincter ? "center" : "insertion", "muscle '" + d.name + "' moves no node of the tissue");
  for (double& w : m.weight) w /= total;
  return m;
}

Vec3 musclePull(const FaceMuscle& m, const Vec3& p, const Vec3& attachment, const Vec3& center, const Vec3& axis_u,
                const Vec3& axis_v) {
  if (!m.desc.sphincter) return unitOr(attachment - p, Vec3::Zero());
  const Vec3 d = p - center;
  return unitOr(-(d.dot(axis_u) * axis_u + d.dot(axis_v) * axis_v), Vec3::Zero());
}

double easeKey(double s) { return smoothstep(0.0, 1.0, s); }

double blinkClosure(double t) {
  if (t <= 0 || t >= 0.25) return 0.0;
  if (t < 0.08) return smoothstep(0.0, 0.08, t);
  if (t < 0.12) return 1.0;
  return 1.0 - smoothstep(0.12, 0.25, t);
}

int FaceActivations::index(const std::string& control) const {
  for (std::size_t k = 0; k < controls.size(); ++k)
    if (controls[k] == control) return static_cast<int>(k);
  return -1;
}

void FaceActivations::at(double t, std::vector<double>& out) const {
  out.assign(controls.size(), 0.0);
  if (!times.empty()) {
    // Eased between keys: a muscle takes up and lets go of its pull smoothly (a linear ramp's
    // kinks jolted the tissue at each key, and the implicit solve's warm start with it).
    const KeySpan ks = keySpan(times, t, [](double x) { return x; });
    const double s = easeKey(ks.s);
    for (std::size_t c = 0; c < controls.size(); ++c)
      out[c] = s == 0.0 ? values[ks.i][c] : (1 - s) * values[ks.i][c] + s * values[ks.i + 1][c];
  }
  if (!speech_times.empty()) {
    const KeySpan ks = keySpan(speech_times, t, [](double x) { return x; });
    const double s = easeKey(ks.s);
    for (std::size_t c = 0; c < controls.size(); ++c) {
      const double v = s == 0.0 ? speech[ks.i][c] : (1 - s) * speech[ks.i][c] + s * speech[ks.i + 1][c];
      out[c] = std::min(1.0, out[c] + v);
    }
  }
  const int b = index("blink");
  for (double start : blinks) out[static_cast<std::size_t>(b)] = std::max(out[static_cast<std::size_t>(b)], blinkClosure(t - start));
}

Result<FaceActivations> makeActivations(const FaceDesc& desc, const std::vector<FaceMuscle>& muscles,
                                        const std::string& file) {
  FaceActivations A;
  for (const FaceMuscle& m : muscles) A.controls.push_back(m.desc.name);
  for (const char* c : kFaceControls) A.controls.push_back(c);
  A.blinks = desc.blinks;
  auto bad = [&](const std::string& p, const std::string& what) { return Error(ErrorKind::BadInput, file + ": " + p + ": " + what); };
  // Sets control `name` (or both sides of a paired one) to `value` scaled, on `side`.
  auto apply = [&](std::vector<double>& v, const std::string& name, double value, const std::string& side) -> bool {
    if (int i = A.index(name); i >= 0) {
      v[static_cast<std::size_t>(i)] = std::min(1.0, v[static_cast<std::size_t>(i)] + value);
      return true;
    }
    bool any = false;
    for (const char* s : {"left", "right"}) {
      if (side != "both" && side != s) {
        any = any || A.index(name + "_" + s) >= 0;
        continue;
      }
      if (int i = A.index(name + "_" + s); i >= 0) {
        v[static_cast<std::size_t>(i)] = std::min(1.0, v[static_cast<std::size_t>(i)] + value);
        any = true;
      }
    }
    return any;
  };
  for (const FaceActivationKey& key : desc.activations) {
    std::vector<double> v(A.controls.size(), 0.0);
    for (const auto& [preset, amount] : key.presets) {
      const auto* p = std::find_if(kFacePresets.begin(), kFacePresets.end(), [&, preset = preset](const FacePreset& f) { return preset == f.name; });
      for (const auto& [control, value] : p->controls)
        if (control && !apply(v, control, amount * value, key.side))
          return bad(key.path, "preset '" + preset + "' moves '" + control + "', which this face does not have" +
                                   (desc.default_muscles ? "" : " (its default muscles are off)"));
    }
    for (const auto& [control, value] : key.muscles)
      if (!apply(v, control, value, "both"))
        return bad(key.path + "/muscles/" + control, "unknown muscle or control '" + control + "'");
    A.times.push_back(key.time);
    A.values.push_back(std::move(v));
  }
  for (const FaceVisemeKey& key : desc.visemes) {
    std::vector<double> v(A.controls.size(), 0.0);
    const auto* p = std::find_if(kFaceVisemes.begin(), kFaceVisemes.end(), [&](const FacePreset& f) { return key.viseme == f.name; });
    if (p != kFaceVisemes.end())
      for (const auto& [control, value] : p->controls)
        if (control && !apply(v, control, key.amount * value, "both"))
          return bad(key.path, "viseme '" + key.viseme + "' moves '" + control + "', which this face does not have" +
                                   (desc.default_muscles ? "" : " (its default muscles are off)"));
    A.speech_times.push_back(key.time);
    A.speech.push_back(std::move(v));
  }
  return A;
}

}  // namespace reel
