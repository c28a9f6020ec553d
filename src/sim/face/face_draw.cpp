// What a face gives the renderer: its skin (per-vertex colours: skin, lips, brows, hair) with
// eyes that look at the gaze target, eyelids that blink, and the mouth's inside; or, in
// layers mode, the classic figure: the lattice's layers, the skull, and the muscles coloured from
// yellow (relaxed) to red (fully contracted).
#include <cmath>

#include "core/keys.h"
#include "core/math.h"
#include "sim/draw_material.h"
#include "sim/face/face_body.h"

namespace reel {
namespace {

// Skin is lit with wrap lighting: light scattered beneath it softens the terminator.
constexpr double kSkinWrap = 0.5;


// A unit eye looking along +z: white, an iris and a pupil by the angle from +z.
std::shared_ptr<const TriMesh> eyeMesh(const Vec3& iris) {
  auto m = std::make_shared<TriMesh>(makeUvSphere(1.0, 48, 48));
  // Its pole turned from +y to +z: the rings of latitude circle the gaze, the iris's edge is one.
  m->transform(Eigen::AngleAxisd(0.5 * kPi, Vec3::UnitX()).toRotationMatrix(), Vec3::Zero());
  m->colors.resize(m->positions.size());
  for (std::size_t v = 0; v < m->vertexCount(); ++v) {
    const double z = m->positions[3 * v + 2];
    Vec3 c(0.7, 0.68, 0.64);
    if (z > std::cos(0.2)) c = Vec3(0.015, 0.015, 0.015);
    else if (z > std::cos(0.5)) c = iris * (0.7 + 0.6 * (std::acos(z) - 0.2) / 0.3);
    for (int k = 0; k < 3; ++k) m->colors[3 * v + static_cast<std::size_t>(k)] = static_cast<float>(c[k]);
  }
  return m;
}

void pushTube(DrawTubes& t, const Vec3& a, const Vec3& b) {
  for (const Vec3* p : {&a, &b})
    for (int k = 0; k < 3; ++k) t.ends.push_back(static_cast<float>((*p)[k]));
}

DrawMaterial plain(const Vec3& color, double specular = 0.1) {
  DrawMaterial m;
  m.color = color;
  m.specular = specular;
  m.shininess = 24;
  return m;
}

}  // namespace

void FaceBody::draw(DrawList& out) const {
  bool layers = false;
  for (const FaceDrawKey& k : desc_.draw)
    if (k.time <= t_ + 1e-9) layers = k.layers;
  if (layers) drawLayers(out);
  else drawSkin(out);
}

void FaceBody::drawSkin(DrawList& out) const {
  const std::size_t n = surface_.size();
  const auto& x = net_.state.x;
  const auto& tris = surface_.tris;
  auto mesh = smoothMesh(x, 0, n, tris);
  DrawMesh skin;
  skin.material = drawMaterial(material_);
  skin.material.wrap = kSkinWrap;
  if (surface_.generated) {
    // reel's head: its skin's texture, made once when first drawn.
    if (!skin_texture_) skin_texture_ = skinTexture(surface_);
    skin.material.texture = skin_texture_;
    for (std::size_t k = 0; k < n; ++k) mesh->uvs[2 * k] = surface_.uv[k][0], mesh->uvs[2 * k + 1] = surface_.uv[k][1];
  } else {
    for (std::size_t k = 0; k < n; ++k)
      for (int c = 0; c < 3; ++c) mesh->colors.push_back(static_cast<float>(surface_.color[k][c]));
  }
  skin.mesh = std::move(mesh);
  skin.per_frame = true;
  out.meshes.push_back(std::move(skin));
  if (!surface_.generated) return;
  auto world = [&](const Vec3& q) { return Vec3(desc_.position + R_ * q); };
  // The ears turn with the skull; the shoulders a third as far (a person turning the head).
  if (surface_.ears) {
    auto ears = std::make_shared<TriMesh>(*surface_.ears);
    ears->transform(R_, desc_.position);
    DrawMaterial ear = skin.material;
    ear.texture.reset();
    ear.double_sided = true;
    out.meshes.push_back({std::move(ears), true, ear});
  }
  if (surface_.bust) {
    auto bust = std::make_shared<TriMesh>(*surface_.bust);
    const Mat3 turn = Eigen::Quaterniond::Identity().slerp(1.0 / 3.0, Eigen::Quaterniond(R_)).toRotationMatrix();
    bust->transform(turn, desc_.position);
    DrawMaterial wool = plain(Vec3(0.07, 0.1, 0.12), 0.2);
    wool.roughness = 0.85;
    wool.sheen = 0.6;
    wool.double_sided = true;
    out.meshes.push_back({std::move(bust), true, wool});
  }
  // The mouth's inside, seen through the parted lips: the skull's surface around the mouth (it
  // turns with the jaw), drawn dark.
  {
    auto inside = std::make_shared<TriMesh>();
    const std::size_t first = n;  // bone nodes follow the tissue's two layers: 2n + k
    // Between the lips: within an ellipse around the parting, as wide as the mouth.
    const double half = 0.5 * surface_.mouth_width, tall = 0.3 * surface_.mouth_width;
    std::vector<std::int64_t> index(n, -1);
    for (std::size_t t = 0; t + 2 < tris.size(); t += 3) {
      bool near = true;
      for (int c = 0; c < 3; ++c) {
        const Vec3 d = surface_.skin[tris[t + static_cast<std::size_t>(c)]] - surface_.mouth;
        near = near && d.z() > -half && (d.x() / half) * (d.x() / half) + (d.y() / tall) * (d.y() / tall) < 1.0;
      }
      if (!near) continue;
      for (int c = 0; c < 3; ++c) {
        const std::uint32_t k = tris[t + static_cast<std::size_t>(c)];
        if (index[k] < 0) {
          index[k] = static_cast<std::int64_t>(inside->vertexCount());
          inside->addVertex(x[2 * first + k], -(boneRotation(k) * tissue_.out[k]));
        }
        inside->indices.push_back(static_cast<std::uint32_t>(index[k]));
      }
    }
    DrawMaterial dark = plain(Vec3(0.14, 0.02, 0.02), 0.05);
    dark.double_sided = true;
    if (!inside->indices.empty()) out.meshes.push_back({std::move(inside), true, dark});
  }
  // Eyes, turned toward the gaze target (at most 35° from straight ahead).
  static const std::shared_ptr<const TriMesh> kEye = eyeMesh(Vec3(0.12, 0.22, 0.35));
  DrawInstances eyes;
  eyes.mesh = desc_.iris_color == Vec3(0.12, 0.22, 0.35) ? kEye : eyeMesh(desc_.iris_color);
  eyes.material = plain(Vec3(1, 1, 1), 0.6);
  eyes.material.shininess = 80;
  const Vec3 ahead = R_ * Vec3::UnitZ(), up = R_ * Vec3::UnitY();
  for (int e = 0; e < 2; ++e) {
    const Vec3 c = world(surface_.eye[static_cast<std::size_t>(e)]);
    Vec3 look = ahead;
    if (!desc_.gaze.empty()) {
      const Vec3 target = keyedLinear(desc_.gaze, t_, [](const FaceGazeKey& k) { return k.time; },
                                      [](const FaceGazeKey& k) { return k.target; });
      look = unitOr(target - c, ahead);
      const double angle = std::acos(std::clamp(look.dot(ahead), -1.0, 1.0)), most = 35.0 * kPi / 180.0;
      if (angle > most) {
        const Vec3 side = unitOr(look - look.dot(ahead) * ahead, up);
        look = std::cos(most) * ahead + std::sin(most) * side;
      }
    }
    const Vec3 X = unitOr(up.cross(look), R_ * Vec3::UnitX()), Y = look.cross(X);
    const double r = surface_.eye_radius;
    for (const Vec3& axis : {X, Y, look})
      for (int k = 0; k < 3; ++k) eyes.transforms.push_back(static_cast<float>(r * axis[k]));
    for (int k = 0; k < 3; ++k) eyes.transforms.push_back(static_cast<float>(c[k]));
  }
  out.instances.push_back(std::move(eyes));
  // Upper eyelids: shells just outside the eyes, down to the lid's edge. Open, the edge is at
  // 30° above the eye's centre (higher with eyelid_raise); a blink or the orbicularis oculi
  // brings it down.
  auto control = [&](const std::string& name) {
    const int i = activations_.index(name);
    return i < 0 ? 0.0 : act_[static_cast<std::size_t>(i)];
  };
  // The lids' colours: the skin's tone, a shade darker, and the lash line at their edges.
  const Vec3 lid_tone = 0.93 * Vec3(0.57, 0.36, 0.28), lash_tone(0.025, 0.018, 0.014);
  auto lids = std::make_shared<TriMesh>();
  auto vertex = [&](const Vec3& p, const Vec3& n, const Vec3& color) {
    lids->addVertex(world(p), R_ * n);
    for (int k = 0; k < 3; ++k) lids->colors.push_back(static_cast<float>(color[k]));
  };
  auto quads = [&](std::uint32_t base, int rows, int cols) {
    for (int j = 0; j < rows; ++j)
      for (int i = 0; i < cols; ++i) {
        const std::uint32_t a = base + static_cast<std::uint32_t>(j * (cols + 1) + i), b = a + 1, cc = a + cols + 1, d = cc + 1;
        lids->indices.insert(lids->indices.end(), {a, b, d, a, d, cc});
      }
  };
  for (int e = 0; e < 2; ++e) {
    const double squeeze = control(e == 0 ? "orbicularis_oculi_left" : "orbicularis_oculi_right");
    const double closure = std::clamp(std::max(control("blink"), 0.45 * squeeze), 0.0, 1.0);
    const double open = (9.0 + 22.0 * control("eyelid_raise")) * kPi / 180.0, shut = -40.0 * kPi / 180.0;
    const double edge = open + closure * (shut - open);
    const Vec3 c = surface_.eye[static_cast<std::size_t>(e)];
    const double r = 1.07 * surface_.eye_radius;
    constexpr int kA = 18, kE = 10;
    // The upper lid from its edge to the top; the lower lid from its edge, 23° below the centre
    // (higher as the orbicularis oculi squeezes), to the bottom.
    const double low_edge = (-23.0 + 16.0 * squeeze) * kPi / 180.0;
    auto at = [&](double el, double az) { return Vec3(std::cos(el) * std::sin(az), std::sin(el), std::cos(el) * std::cos(az)); };
    auto azimuth = [&](int i) { return (-80.0 + 160.0 * i / kA) * kPi / 180.0; };
    for (int lower = 0; lower < 2; ++lower) {
      const double from = lower ? low_edge : edge, to = lower ? -0.5 * kPi : 0.5 * kPi;
      auto base = static_cast<std::uint32_t>(lids->vertexCount());
      for (int j = 0; j <= kE; ++j) {
        const double el = from + (to - from) * j / kE;
        const double line = j == 0 ? (lower ? 0.35 : 0.85) : 0.0;
        for (int i = 0; i <= kA; ++i) vertex(c + r * at(el, azimuth(i)), at(el, azimuth(i)), lid_tone + line * (lash_tone - lid_tone));
      }
      quads(base, kE, kA);
      // The lashes: a fringe curving out and away from the eye from the lid's edge, longest
      // at the middle: a dark line seen from the front (2.6 mm above, 0.8 mm below).
      base = static_cast<std::uint32_t>(lids->vertexCount());
      const double length = (lower ? 0.0008 : 0.0026) * surface_.scale;
      const Vec3 away(0, lower ? -1 : 1, 0);
      for (int j = 0; j <= 2; ++j)
        for (int i = 0; i <= kA; ++i) {
          const double az = azimuth(i), fall = std::max(0.0, 1.0 - std::pow(std::abs(az) / 1.3, 4.0));
          const Vec3 d = at(from, az), dir = (0.75 * d + 0.65 * away).normalized();
          const double l = 0.5 * j * length * fall;
          vertex(c + r * d + l * dir + (0.3 * l * j) * away, dir.cross(Vec3(std::cos(az), 0, -std::sin(az))), lash_tone);
        }
      quads(base, 2, kA);
    }
  }
  DrawMaterial lid = drawMaterial(material_);
  lid.wrap = kSkinWrap;
  lid.double_sided = true;
  out.meshes.push_back({std::move(lids), true, lid});
}

void FaceBody::drawLayers(DrawList& out) const {
  const std::size_t n = surface_.size();
  const auto& x = net_.state.x;
  const double s = surface_.scale;
  // Only the front of the head: the figure of the lattice under the face.
  auto front = [&](std::size_t k) { return surface_.skin[k].z() > -0.01 * s; };
  DrawTubes skin, fascia, across;
  skin.radius = static_cast<float>(0.0004 * s);
  fascia.radius = skin.radius;
  across.radius = static_cast<float>(0.0003 * s);
  skin.material = plain(Vec3(0.9, 0.62, 0.45));
  fascia.material = plain(Vec3(0.75, 0.2, 0.2));
  across.material = plain(Vec3(0.3, 0.45, 0.75));
  const Springs& sp = net_.model.springs;
  for (std::size_t q = 0; q < sp.size(); ++q) {
    const auto a = static_cast<std::size_t>(sp.a[q]), b = static_cast<std::size_t>(sp.b[q]);
    if (!front(a % n) || !front(b % n)) continue;
    if (a < n && b < n) pushTube(skin, x[a], x[b]);
    else if (a >= n && b >= n && a < 2 * n && b < 2 * n) pushTube(fascia, x[a], x[b]);
    else if (b == a + n) pushTube(across, x[a], x[b]);
  }
  out.tubes.push_back(std::move(skin));
  out.tubes.push_back(std::move(fascia));
  out.tubes.push_back(std::move(across));
  // The skull: the bone surface.
  auto bone = smoothMesh(x, 2 * n, n, surface_.tris);
  out.meshes.push_back({std::move(bone), true, plain(Vec3(0.42, 0.42, 0.45), 0.2)});
  // Muscles: attachment to the centre of the nodes they pull (sphincters: their ellipse).
  for (std::size_t m = 0; m < muscles_.size(); ++m) {
    const FaceMuscle& mu = muscles_[m];
    const double a = std::clamp(act_[m], 0.0, 1.0);
    DrawTubes t;
    t.radius = static_cast<float>(0.0016 * s);
    t.material = plain((1 - a) * Vec3(1.0, 0.85, 0.15) + a * Vec3(0.9, 0.08, 0.04), 0.3);
    if (!mu.desc.sphincter) {
      Vec3 mid = Vec3::Zero();
      for (std::size_t j = 0; j < mu.nodes.size(); ++j) mid += mu.weight[j] * x[n + static_cast<std::size_t>(mu.nodes[j])];
      const Vec3 att = attachmentWorld(m);
      pushTube(t, att, mid);
    } else {
      Vec3 u, v;
      sphincterAxes(mu.desc.normal.normalized(), u, v);
      const double shrink = 1.0 - 0.25 * a;
      for (int i = 0; i < 24; ++i) {
        auto at = [&](int j) {
          const double ang = 2 * kPi * j / 24;
          return Vec3(desc_.position + R_ * (mu.desc.center + shrink * 0.6 *
                                                                (mu.desc.radii[0] * std::cos(ang) * u + mu.desc.radii[1] * std::sin(ang) * v)));
        };
        pushTube(t, at(i), at(i + 1));
      }
    }
    out.tubes.push_back(std::move(t));
  }
}

}  // namespace reel
