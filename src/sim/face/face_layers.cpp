// The face's layers mode: the classic figure of Terzopoulos & Waters (1990) and Lee, Terzopoulos
// & Waters (1995), the lattice's layers, the skull sculpted from the bone layer with its teeth,
// and the muscles coloured from muscle red (relaxed) to a brighter red (fully contracted).
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <span>
#include <string>

#include "core/math.h"
#include "sim/draw_material.h"
#include "sim/face/face_body.h"
#include "sim/face/head.h"
#include "sim/face/head_shape.h"

namespace reel {
namespace {

void pushTube(DrawTubes& t, const Vec3& a, const Vec3& b) {
  for (const Vec3* p : {&a, &b})
    for (int k = 0; k < 3; ++k) t.ends.push_back(static_cast<float>((*p)[k]));
}

// A muscle's body swept along `path` (the surface's normals `up` under it), each ring an ellipse
// of half-width `wide[i]` across the path and half-height `thick[i]` off the surface: a strap's
// ends closed with fans, a ring's (closed) last ring joined to its first. Its fibres run along it:
// the vertex colours alternate round each ring, so it is striped lengthwise as muscle is (flat
// red read as a sausage).
std::shared_ptr<TriMesh> muscleBody(std::span<const Vec3> path, std::span<const Vec3> up, std::span<const double> wide,
                                    std::span<const double> thick, bool closed) {
  constexpr int kAround = 16;
  const std::size_t rings = path.size();
  auto m = std::make_shared<TriMesh>();
  for (std::size_t k = 0; k < rings; ++k) {
    const std::size_t next = closed ? (k + 1) % rings : std::min(k + 1, rings - 1), prev = closed ? (k + rings - 1) % rings : (k > 0 ? k - 1 : 0);
    const Vec3 along = unitOr(path[next] - path[prev], Vec3::UnitY());
    const Vec3 across = unitOr(along.cross(up[k]), Vec3::UnitX()), off = across.cross(along);
    for (int j = 0; j < kAround; ++j) {
      const double a = 2 * kPi * j / kAround, c = std::cos(a), sn = std::sin(a);
      const Vec3 normal = unitOr(c / wide[k] * across + sn / thick[k] * off, off);
      m->addVertex(path[k] + wide[k] * c * across + thick[k] * sn * off, normal);
      const float fibre = j % 2 == 0 ? 1.0f : 0.8f;
      m->colors.insert(m->colors.end(), {fibre, fibre, fibre});
    }
  }
  ringTriangles(*m, 0, static_cast<int>(closed ? rings : rings - 1), kAround, false, closed);
  if (closed) return m;
  // The ends: a fan round each end's centre.
  for (int e = 0; e < 2; ++e) {
    const std::size_t k = e == 0 ? 0 : rings - 1;
    const auto centre = static_cast<std::uint32_t>(m->vertexCount());
    const Vec3 along = unitOr(path[rings - 1] - path[0], Vec3::UnitY());
    m->addVertex(path[k], e == 0 ? Vec3(-along) : along);
    m->colors.insert(m->colors.end(), {0.9f, 0.9f, 0.9f});
    const auto ring = static_cast<std::uint32_t>(k * kAround);
    for (int j = 0; j < kAround; ++j) {
      const std::uint32_t a = ring + static_cast<std::uint32_t>(j), b = ring + static_cast<std::uint32_t>((j + 1) % kAround);
      if (e == 0) m->indices.insert(m->indices.end(), {centre, a, b});
      else m->indices.insert(m->indices.end(), {centre, b, a});
    }
  }
  return m;
}

// A linear muscle's half-widths at its attachment and at its insertion (m at 0.24 m; after the
// plates of Gray's Anatomy: the frontalis a broad sheet, the depressor anguli oris a triangle on
// the jaw, the risorius a fan from the cheek's side, the zygomatics straps, each of the mentalis'
// pair a strap on the chin); a user's muscle 4.5 mm all along.
std::array<double, 2> bellyWidths(const std::string& name) {
  struct Width {
    const char* name;
    double attach, insert;
  };
  static constexpr Width kWidths[] = {{"frontalis", 0.015, 0.016},       {"corrugator", 0.003, 0.0045},
                                      {"zygomatic_major", 0.0045, 0.004}, {"zygomatic_minor", 0.003, 0.003},
                                      {"levator_labii", 0.004, 0.006},    {"depressor_anguli_oris", 0.010, 0.003},
                                      {"risorius", 0.007, 0.003},         {"mentalis", 0.003, 0.0045},
                                      {"procerus", 0.003, 0.005}};
  for (const Width& w : kWidths)
    if (name.rfind(w.name, 0) == 0) return {w.attach, w.insert};
  return {0.0045, 0.0045};
}

// Relaxes the points of a polyline toward their neighbours' mean, halfway, `passes` times: its
// ends held, or round a loop (`closed`).
template <std::size_t N>
void relax(std::array<Vec3, N>& p, int passes, bool closed) {
  for (int pass = 0; pass < passes; ++pass) {
    const std::array<Vec3, N> was = p;
    for (std::size_t i = closed ? 0 : 1; i < (closed ? N : N - 1); ++i) p[i] = 0.5 * was[i] + 0.25 * (was[(i + N - 1) % N] + was[(i + 1) % N]);
  }
}

bool frontalis(const std::string& name) { return name.rfind("frontalis", 0) == 0; }

// A muscle's red at activation a (0..1): muscle red relaxed, a brighter, warmer red as it
// contracts (yellow sticks read as a debug view; a glowing orange, with the lips' ring round bared
// teeth, as a clown's mask).
Vec3 muscleRed(double a) { return (1 - a) * Vec3(0.42, 0.07, 0.06) + a * Vec3(0.8, 0.2, 0.1); }

}  // namespace

// The skull of the layers' figure. The tissue's bone layer follows the skin a few millimetres in,
// so drawn as it is it is an egg with a nose (a viewer's words). Drawn, it is sculpted after the
// skull's anatomy (proportions as in Gray's Anatomy, plate 190, the skull from the front): the
// orbits, about 40 mm wide and 35 tall with squarish rims, sunk 20 mm to floors behind the
// eyeballs; the pear-shaped nasal aperture, 24 mm wide at its base and 32 tall, with the nose's
// cartilage taken away; the cheekbones standing out 5 mm over the hollows beside the nose; the
// temples' hollows; the teeth's recess where the lips were.
// The cavities are shaded darker with depth. The simulation's skull is not changed.
void FaceBody::sculptSkull() const {
  const std::size_t n = surface_.size();
  const double s = surface_.scale, ym = surface_.mouth.y() / s;
  skull_rest_.resize(n);
  skull_shade_.assign(3 * n, 1.0f);
  for (std::size_t k = 0; k < n; ++k) {
    const Vec3 q = surface_.bone[k], p = q / s;
    const Vec3 out = unitOr(surface_.skin[k] - q, p.normalized());
    double sink = 0.0, shade = 1.0, rise = 0.0;
    if (surface_.generated && p.z() > 0.02) {
      const double ax = std::abs(p.x()), y = p.y();
      // The orbits: a superellipse (n = 3) about each eye, a bowl 20 mm deep.
      const double u = (ax - head::kEyeX) / 0.021, v = (y - head::kEyeY + 0.001) / 0.0175;
      const double rho = std::cbrt(std::pow(std::abs(u), 3) + std::pow(std::abs(v), 3));
      if (rho < 1.0) {
        const double bowl = std::sqrt(1.0 - rho * rho);
        sink = std::max(sink, 0.02 * bowl);
        shade = std::min(shade, 1.0 - 0.75 * smoothstep(0.0, 0.6, bowl));
      }
      // The nasal aperture: a pear, widest a third of the way up.
      const double t = (y + 0.053) / 0.032;
      if (t > -0.1 && t < 1.1) {
        const double w = 0.002 + 0.0105 * std::sin(kPi * std::pow(std::clamp(t, 0.0, 1.0), 0.7));
        const double hole = smoothstep(w, w - 0.002, ax) * smoothstep(-0.1, 0.05, t) * smoothstep(1.1, 0.95, t);
        sink = std::max(sink, 0.022 * hole);
        shade = std::min(shade, 1.0 - 0.85 * hole);
      }
      // The teeth's recess, where the lips were: the teeth drawn stand in front of it.
      const double mouth = smoothstep(0.026, 0.02, ax) * smoothstep(0.013, 0.009, std::abs(y - ym));
      sink = std::max(sink, 0.008 * mouth);
      shade = std::min(shade, 1.0 - 0.6 * mouth);
      // The cheekbones (the zygomatic bones' bodies), and the hollow under each beside the nose
      // (the canine fossa).
      rise = 0.005 * std::exp(-0.5 * (head::sq((ax - 0.05) / 0.012) + head::sq((y + 0.022) / 0.008)));
      sink = std::max(sink, 0.003 * std::exp(-0.5 * (head::sq((ax - 0.026) / 0.008) + head::sq((y + 0.045) / 0.007))));
      // The cheeks' hollows under the cheekbones, down to the jaw's body: the maxilla and the
      // mandible's ramus lie well inside the cheek's fat and the masseter (with the bone layer's
      // full cheeks, the skull kept the face's fleshy outline and read as a mannequin's head).
      const double buccal = smoothstep(0.026, 0.042, ax) * std::exp(-0.5 * (head::sq((ax - 0.056) / 0.016) + head::sq((y + 0.06) / 0.017)));
      sink = std::max(sink, 0.008 * buccal);
      shade = std::min(shade, 1.0 - 0.2 * buccal);
    }
    if (surface_.generated) {
      // The temples' hollows (the temporal fossae), above the cheekbones' arches on the sides.
      const double side = std::abs(p.x()) / std::max(p.norm(), 1e-9);
      const double temple = smoothstep(0.55, 0.8, side) * std::exp(-0.5 * (head::sq((p.y() - 0.015) / 0.018) + head::sq((p.z() - 0.025) / 0.025)));
      sink = std::max(sink, 0.004 * temple);
      shade = std::min(shade, 1.0 - 0.15 * temple);
    }
    skull_rest_[k] = q + s * (rise - sink) * out;
    for (int c = 0; c < 3; ++c) skull_shade_[3 * k + static_cast<std::size_t>(c)] = static_cast<float>(shade);
  }
}

// The teeth, in both modes (face_draw.cpp's skin, the layers' skull).
void FaceBody::drawTeeth(DrawList& out, double lit) const {
  DrawMaterial enamel = plainMaterial(Vec3(1, 1, 1), 0.5);
  enamel.roughness = 0.3;
  enamel.casts_shadow = false;
  for (int row = 0; row < 2; ++row) {
    // The upper row with the skull, the lower with the jaw: jawMoved is a rigid motion.
    const double share = row == 0 ? 0.0 : 1.0;
    auto teeth = std::make_shared<TriMesh>(*surface_.teeth[static_cast<std::size_t>(row)]);
    teeth->transform(jawRotation(share), Vec3(desc_.position + R_ * jawMoved(share, Vec3::Zero())));
    for (float& c : teeth->colors) c *= static_cast<float>(lit);
    out.meshes.push_back({std::move(teeth), true, enamel});
  }
}

void FaceBody::drawLayers(DrawList& out, double reveal) const {
  const std::size_t n = surface_.size();
  const auto& x = net_.state.x;
  const double s = surface_.scale;
  // The figure of the lattice under the face, cut away: only the front of the head, and only its
  // left half (+x) from 12 mm off the midline, so the muscles show on the skull over the right half
  // and the nasal aperture between (cut at the midline, the lattice hid it); and only below the
  // hairline (over the scalp the hair's thickness stood the lattice off the skull as a bulge).
  auto shown = [&](std::size_t k) {
    const Vec3& p = surface_.skin[k];
    return p.z() > -0.01 * s && p.x() > 0.012 * s && head::hairCover(p / s, p.normalized(), 0.004) < 0.05;
  };
  DrawTubes skin, fascia, across;
  skin.radius = static_cast<float>(0.0004 * s);
  fascia.radius = skin.radius;
  across.radius = static_cast<float>(0.0003 * s);
  // The lattice's skin layer lies at the skin, its fascia just under it: as the reveal goes they
  // rise to their places from the bone, under the skin and the mouth's lining until the skin has
  // faded (risen from the fascia, the lips' strands showed in the parting as the fade began; its
  // tubes thinned instead, the renderer's least width left them showing at once).
  reveal = std::clamp(reveal, 0.0, 1.0);
  auto lifted = [&](std::size_t k) { return Vec3(x[2 * n + k % n] + reveal * (x[k] - x[2 * n + k % n])); };
  skin.material = plainMaterial(Vec3(0.9, 0.62, 0.45));
  // (The layers below the skin in muted tones: saturated red and blue, their edges at the cut
  // read as zig-zags and a checkered pattern.)
  fascia.material = plainMaterial(Vec3(0.6, 0.4, 0.33));
  across.material = plainMaterial(Vec3(0.42, 0.46, 0.52));
  const Springs& sp = net_.model.springs;
  for (std::size_t q = 0; q < sp.size(); ++q) {
    const auto a = static_cast<std::size_t>(sp.a[q]), b = static_cast<std::size_t>(sp.b[q]);
    if (!shown(a % n) || !shown(b % n)) continue;
    if (a < n && b < n) pushTube(skin, lifted(a), lifted(b));
    else if (a >= n && b >= n && a < 2 * n && b < 2 * n) pushTube(fascia, lifted(a), lifted(b));
    else if (b == a + n) pushTube(across, lifted(a), lifted(b));
  }
  out.tubes.push_back(std::move(skin));
  out.tubes.push_back(std::move(fascia));
  out.tubes.push_back(std::move(across));
  // The skull, sculpted (sculptSkull), posed as the bone nodes are, in bone's ivory, and the eyes
  // in their sockets.
  std::call_once(skull_once_, [&] { sculptSkull(); });
  std::vector<Vec3> skull(n);
  for (std::size_t k = 0; k < n; ++k) skull[k] = boneToWorld(k, skull_rest_[k]);
  auto bone = smoothMesh(skull, 0, n, surface_.tris);
  bone->colors = skull_shade_;
  // A point laid on the skull: onto the tangent plane of its nearest vertex, a muscle belly's
  // half-thickness and a little more above it; and that vertex's normal.
  const std::vector<float> skull_normal = bone->normals;
  auto onSkull = [&](const Vec3& p, Vec3* normal = nullptr) {
    const std::size_t best = nearestOf(std::span<const Vec3>(skull.data(), n), p).first;
    const Vec3 nk(skull_normal[3 * best], skull_normal[3 * best + 1], skull_normal[3 * best + 2]);
    if (normal) *normal = nk;
    return Vec3(p - (p - skull[best]).dot(nk) * nk + 0.0024 * s * nk);
  };
  out.meshes.push_back({std::move(bone), true, plainMaterial(Vec3(0.55, 0.5, 0.42), 0.2)});
  if (surface_.generated) {
    drawEyes(out);
    // (From the skin's shade to the layers' full light as they are revealed: the same teeth are
    // in both views, and in a dissolve these, drawn solid, hide the skin's; lit by the reveal
    // alone, the teeth showed as near-black bars as the skin faded back in.)
    const double lit = mouthLight();
    drawTeeth(out, lit + reveal * (1.0 - lit));
  }
  // Muscles: attachment to the centre of the nodes they pull (sphincters: their ellipse).
  for (std::size_t m = 0; m < muscles_.size(); ++m) {
    const FaceMuscle& mu = muscles_[m];
    double a = std::clamp(act_[m], 0.0, 1.0);
    // (The orbicularis oris' band shows the lips' pucker's contraction too: the pucker lies in it.)
    if (mu.desc.name == "orbicularis_oris" && surface_.generated)
      for (std::size_t p = 0; p < muscles_.size(); ++p)
        if (muscles_[p].desc.name == "incisivii") a = std::max(a, std::clamp(act_[p], 0.0, 1.0));
    if (!mu.desc.sphincter && frontalis(mu.desc.name) && surface_.generated) continue;  // drawn as a sheet, below
    // (The lips' pucker lies deep in the orbicularis oris' band: its ring drawn too, the two bands
    // overlapped round the mouth.)
    if (mu.desc.sphincter && mu.desc.name == "incisivii" && surface_.generated) continue;
    const DrawMaterial red = plainMaterial(muscleRed(a), 0.3);
    if (!mu.desc.sphincter) {
      Vec3 mid = Vec3::Zero();
      for (std::size_t j = 0; j < mu.nodes.size(); ++j) mid += mu.weight[j] * x[n + static_cast<std::size_t>(mu.nodes[j])];
      const Vec3 att = attachmentWorld(m);
      // From its attachment to the centre of the nodes it pulls, lying on the skull along twelve
      // pieces, smoothed (a straight stick stood off the cheek's curve and over the sculpted
      // orbits; laid on the nearest vertices' planes unsmoothed, it kinked from plane to plane),
      // drawn flat, as wide as its kind is (bellyWidths), rounded at its ends (spindles of one
      // width read as sausages).
      const auto [w0, w1] = bellyWidths(mu.desc.name);
      auto belly = [&](const Vec3& from, const Vec3& to) {
        std::array<Vec3, 13> path, up;
        for (std::size_t i = 0; i < path.size(); ++i) path[i] = onSkull(from + (static_cast<double>(i) / 12.0) * (to - from), &up[i]);
        relax(path, 3, false);
        std::array<double, 13> wide, thick;
        for (std::size_t i = 0; i < path.size(); ++i) {
          const double t = static_cast<double>(i) / 12.0, round = std::pow(std::sin(kPi * (0.04 + 0.92 * t)), 0.35);
          wide[i] = s * (w0 + (w1 - w0) * t) * round;
          thick[i] = s * 0.0014 * (0.4 + 0.6 * std::pow(std::sin(kPi * t), 0.7));
        }
        out.meshes.push_back({muscleBody(path, up, wide, thick, false), true, red});
      };
      // A muscle on the midline (the mentalis, the procerus) is a pair, drawn either side of it, parting as it
      // goes (drawn as one lobe under the lips' band, the mentalis read as a tongue hanging out).
      if (std::abs(mu.desc.attachment.x()) < 1e-3 * s && std::abs(mu.desc.insertion.x()) < 1e-3 * s) {
        const Vec3 leftward = R_ * Vec3::UnitX();
        for (double side : {-1.0, 1.0}) belly(att + side * 0.004 * s * leftward, mid + side * 0.008 * s * leftward);
      } else {
        belly(att, mid);
      }
    } else {
      Vec3 u, v;
      sphincterAxes(mu.desc.normal.normalized(), u, v);
      // Its ring lies in the tissue: each point on the fascia node its nodes hold nearest to it
      // across the muscle's plane (the ring follows the face's curve and its contraction).
      const double shrink = 1.0 - 0.25 * a;
      auto at = [&](int j) {
        const double ang = 2 * kPi * j / 24;
        const Vec3 q = mu.desc.center + shrink * 0.6 * (mu.desc.radii[0] * std::cos(ang) * u + mu.desc.radii[1] * std::sin(ang) * v);
        const Vec3 axis = mu.desc.normal.normalized();
        std::size_t best = 0;
        double bd = 1e300;
        for (int k : mu.nodes) {
          const Vec3 r = surface_.skin[static_cast<std::size_t>(k)] - q;
          const double off = (r - r.dot(axis) * axis).squaredNorm();
          if (off < bd) bd = off, best = static_cast<std::size_t>(k);
        }
        return mu.nodes.empty() ? Vec3(desc_.position + R_ * q) : Vec3(x[n + best]);
      };
      // (Each point on its nearest node, the ring steps from node to node: smoothed, it runs round.)
      std::array<Vec3, 24> ring;
      for (int i = 0; i < 24; ++i) ring[static_cast<std::size_t>(i)] = at(i);
      relax(ring, 4, true);
      // A flat band round it, its fibres running round (a tube read as a rubber ring), as wide as
      // eight tenths of the ring's smaller radius (the lips' 12 mm, the eyes' 10 mm).
      const Vec3 facing = R_ * mu.desc.normal.normalized();
      std::array<Vec3, 24> up;
      up.fill(facing);
      std::array<double, 24> wide, thick;
      wide.fill(0.4 * 0.6 * std::min(mu.desc.radii[0], mu.desc.radii[1]) * shrink * reveal);
      thick.fill(0.0012 * s * reveal);
      if (reveal > 0.0) out.meshes.push_back({muscleBody(ring, up, wide, thick, true), true, red});
    }
  }
  if (surface_.generated) drawFrontalis(out, onSkull);
}

// The frontalis as the sheet it is (Gray's Anatomy, plate 378): one thin layer over the forehead
// from the brows up to the scalp's aponeurosis, its two bellies parted low over the nose, its
// fibres running up; each column coloured by the pull of the frontalis muscles nearest it (as
// four separate bellies it read as four pads on an egg). Its lower edge rides on the skin under
// the brows, so it rises as they do; its upper edge lies on the skull.
void FaceBody::drawFrontalis(DrawList& out, const std::function<Vec3(const Vec3&, Vec3*)>& onSkull) const {
  // Each frontalis muscle's place across the forehead (x at 0.24 m) and its pull now.
  std::vector<std::pair<double, double>> pulls;
  for (std::size_t m = 0; m < muscles_.size(); ++m)
    if (frontalis(muscles_[m].desc.name)) pulls.emplace_back(muscles_[m].desc.insertion.x() / surface_.scale, std::clamp(act_[m], 0.0, 1.0));
  if (pulls.empty()) return;  // (a head made without the default muscles)
  const std::size_t n = surface_.size();
  const auto& x = net_.state.x;
  const double s = surface_.scale;
  // The sheet: 41 columns across (fibres of alternate shades, 82% and 100%, so it is striped as
  // muscle is) and 15 rows up, 64 mm to either side of the midline (m at 0.24 m).
  constexpr int kAcross = 40, kUp = 14;
  constexpr double kHalf = 0.064, kSunk = 0.0016;  // its edges sink kSunk onto the bone
  // Its edges: the lower along the brows, rising into the notch between the bellies; the upper
  // curving down to the temples.
  auto low = [](double X) { return 0.026 + 0.014 * std::exp(-0.5 * head::sq(X / 0.009)); };
  auto top = [](double X) { return 0.09 - 0.014 * head::sq(X / kHalf); };
  // The head's base surface where the ray toward (X, Y) on the face's front meets it.
  auto onBase = [&](double X, double Y) {
    const Vec3 d = Vec3(X, Y, 0.09).normalized();
    return Vec3(s * head::baseRadius(d, surface_.look) * d);
  };
  // A column's pull: the muscles' pulls blended by their nearness across the forehead (12 mm), so
  // the midline, as near one side's as the other's, takes both.
  auto pull = [&](double X) {
    double sum = 0.0, weight = 0.0;
    for (const auto& [px, pa] : pulls) {
      const double w = std::exp(-0.5 * head::sq((px - X) / 0.012));
      sum += w * pa, weight += w;
    }
    return weight > 0 ? sum / weight : 0.0;
  };
  auto sheet = std::make_shared<TriMesh>();
  std::vector<Vec3> moved(kAcross + 1);
  for (int i = 0; i <= kAcross; ++i) {
    // The lower edge carried by the skin over it as it moves from rest (that of the vertex nearest
    // at rest).
    const double X = kHalf * (2.0 * i / kAcross - 1.0);
    const std::size_t k = nearestOf(std::span<const Vec3>(surface_.skin.data(), n), onBase(X, low(X))).first;
    moved[static_cast<std::size_t>(i)] = x[k] - boneToWorld(k, surface_.skin[k]);
  }
  for (int j = 0; j <= kUp; ++j)
    for (int i = 0; i <= kAcross; ++i) {
      const double X = kHalf * (2.0 * i / kAcross - 1.0), f = static_cast<double>(j) / kUp;
      const double y0 = low(X), Y = y0 + f * (top(X) - y0);
      // The lower rows carried with the skin, the upper lying on the skull.
      Vec3 normal;
      const Vec3 p = onSkull(desc_.position + R_ * onBase(X, Y) + (1.0 - smoothstep(0.0, 0.7, f)) * moved[static_cast<std::size_t>(i)], &normal);
      // Thinning to nothing at its edges, down onto the bone, and darker there as the bone shows
      // through.
      const double edges = smoothstep(0.0, 0.12, f) * smoothstep(1.0, 0.8, f) * smoothstep(kHalf, kHalf - 0.01, std::abs(X));
      sheet->addVertex(p - kSunk * s * (1.0 - edges) * normal, normal);
      const Vec3 c = (i % 2 == 0 ? 1.0 : 0.82) * (0.55 + 0.45 * edges) * muscleRed(pull(X));
      sheet->colors.insert(sheet->colors.end(), {static_cast<float>(c[0]), static_cast<float>(c[1]), static_cast<float>(c[2])});
    }
  gridTriangles(*sheet, 0, kUp, kAcross);
  out.meshes.push_back({std::move(sheet), true, plainMaterial(Vec3(1, 1, 1), 0.3)});
}

}  // namespace reel
