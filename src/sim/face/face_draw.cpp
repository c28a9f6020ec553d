// What a face gives the renderer: its skin (per-vertex colours: skin, lips, brows, hair) with
// eyes that look at the gaze target, eyelids that blink, and the mouth's inside; the layers
// mode's figure is face_layers.cpp's.
#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "core/keys.h"
#include "core/math.h"
#include "core/random.h"
#include "sim/draw_material.h"
#include "sim/face/face_body.h"
#include "sim/face/head_shape.h"

namespace reel {
namespace {

// How far a lid's margin stands from the corners' line at v across the opening (-1 the inner
// corner, 0 its highest (or lowest) point, 1 the outer corner): a cosine lobe, full in the middle
// and pinched at the corners, so the opening is an almond rather than a slot.
double lidLobe(double v) { return std::abs(v) >= 1.0 ? 0.0 : std::pow(std::cos(0.5 * kPi * v), 0.65); }

// v for the position u across the opening (-1 inner corner .. 1 outer), the lobe's peak at `peak`.
double acrossLobe(double u, double peak) { return u < peak ? (u - peak) / (1.0 + peak) : (u - peak) / (1.0 - peak); }

// Skin scatters light beneath it (pre-integrated skin shading, DrawMaterial::scatter), with skin's
// own profile at the head's scale.
constexpr double kSkinScatter = 1.0;
// The ears are thin enough that light from behind shows through them, red.
constexpr double kEarTranslucency = 0.25;
// How finely reel's head is drawn: each quad of the simulated skin split 3 x 3 (about 1.4 mm on
// the face at the default resolution; 4 x 4 looked the same and drew 17% slower).
constexpr int kSkinDetailLevel = 3;
// Passes that relax the tissue's ripples out of the skin drawn (SkinDetail::place).
constexpr int kSkinSmoothing = 4;


// A unit eye looking along +z: white, an iris and a pupil by the angle from +z. The iris has
// its anatomy's pattern (radial fibres, a paler collarette round the pupil, a dark limbal ring
// at its edge): a flat disc of colour read as glass, the eyes dead.
std::shared_ptr<const TriMesh> eyeMesh(const Vec3& iris) {
  auto m = std::make_shared<TriMesh>(makeUvSphere(1.0, 96, 96));
  // Its pole turned from +y to +z: the rings of latitude circle the gaze, the iris's edge is one.
  m->transform(Eigen::AngleAxisd(0.5 * kPi, Vec3::UnitX()).toRotationMatrix(), Vec3::Zero());
  m->colors.resize(m->positions.size());
  // Smooth noise round the iris (64 cells, wrapping) at a ring's fraction t of the way out.
  auto fibres = [](double around, double t) {
    const double f = (around / (2 * kPi) + 0.5) * 64.0 + 3.0 * t;
    const double i = std::floor(f), w = f - i;
    auto at = [](double k) { return uniformAt(0, 7, static_cast<std::uint64_t>((static_cast<std::int64_t>(k) % 64 + 64) % 64)); };
    return at(i) + smoothstep(0.0, 1.0, w) * (at(i + 1) - at(i));
  };
  for (std::size_t v = 0; v < m->vertexCount(); ++v) {
    const double x = m->positions[3 * v], y = m->positions[3 * v + 1], z = m->positions[3 * v + 2];
    // The sclera: off-white, greying toward the back (less lit, veined), warmer and pinker toward
    // the corners, where the conjunctiva's vessels show (white all over, at 0.68, 0.64, 0.6, a
    // viewer saw a doll's eyes).
    const double from = std::acos(std::clamp(z, -1.0, 1.0));
    Vec3 c = Vec3(0.74, 0.71, 0.68) * (0.75 + 0.25 * std::clamp(z + 0.3, 0.0, 1.0));
    c = c + 0.35 * smoothstep(0.6, 1.3, from) * smoothstep(0.3, 0.9, std::abs(x) / std::max(std::hypot(x, y), 1e-9)) *
                (Vec3(0.6, 0.4, 0.37) - c);
    if (from < 0.17) {
      c = Vec3(0.012, 0.012, 0.012);
    } else if (from < 0.5) {
      const double t = (from - 0.17) / 0.33, around = std::atan2(y, x);
      c = iris * (0.7 + 0.5 * t) * (0.7 + 0.6 * fibres(around, t));
      c = c + 0.18 * std::exp(-0.5 * head::sq((t - 0.22) / 0.1)) * (Vec3(0.55, 0.45, 0.25) - c);  // the collarette
      c *= 1.0 - 0.6 * smoothstep(0.78, 0.97, t);                                           // the limbal ring
    }
    for (int k = 0; k < 3; ++k) m->colors[3 * v + static_cast<std::size_t>(k)] = static_cast<float>(c[k]);
  }
  return m;
}



}  // namespace

void FaceBody::drawBust(DrawList& out) const {
  if (!surface_.bust || !desc_.shoulders) return;
  auto bust = std::make_shared<TriMesh>(*surface_.bust);
  // It turns a third as far as the head, about the neck's axis at the collar, which stays where
  // the head carries that point (the head turns about its own centre: turned about the head's,
  // the collar slid off the neck's axis and the neck poked through it, 2 mm at 35°).
  const Mat3 turn = Eigen::Quaterniond::Identity().slerp(1.0 / 3.0, Eigen::Quaterniond(R_)).toRotationMatrix();
  const Vec3 collar = surface_.scale * Vec3(0.0, head::kCollarY, head::kNeckAxisZ);
  bust->transform(turn, Vec3(desc_.position + R_ * collar - turn * collar));
  DrawMaterial wool = plainMaterial(Vec3(0.07, 0.1, 0.12), 0.2);
  wool.roughness = 0.85;
  wool.sheen = 0.6;
  wool.double_sided = true;
  out.meshes.push_back({std::move(bust), true, wool});
}

void FaceBody::draw(DrawList& out) const {
  // The key in force, and the mode before it.
  bool layers = false, before = false;
  double since = 0.0, fade = 0.0;
  for (const FaceDrawKey& k : desc_.draw)
    if (k.time <= t_ + 1e-9) before = layers, layers = k.layers, since = t_ - k.time, fade = k.fade;
  // The shoulders in every mode, solid through a dissolve (the layers' head on a bare pole,
  // the sweater fading away under it, read as a debug view).
  drawBust(out);
  if (before == layers || since >= fade - 1e-9) {
    if (layers) drawLayers(out);
    else drawSkin(out);
    return;
  }
  // A dissolve: the layers drawn solid and the skin over them, blended (the renderer draws the
  // blended after the solid, depth-tested: the layers fading over a solid skin would hide
  // behind it), fading out into the layers or in from them, the layers growing in as it fades
  // (drawLayers' reveal). The skin's share casts no shadow, and is blended as one solid, its
  // nearest surface alone: every surface blended, what lies under the skin showed through it as
  // the fade began (the lids' shells round the eyes as skin-coloured balls, the mouth's cavity),
  // and with the mouth's inside left out the lips' rims went with it and the mouth gaped open.
  const double s = smoothstep(0.0, 1.0, since / fade), opacity = layers ? 1.0 - s : s;
  drawLayers(out, 1.0 - opacity);
  DrawList skin;
  drawSkin(skin);
  for (DrawMesh& m : skin.meshes) {
    m.material.opacity *= opacity;
    m.material.casts_shadow = false;
    m.material.front_only = true;
    out.meshes.push_back(std::move(m));
  }
}

namespace {

// Each vertex's share of area lost from rest (the mean over its triangles, area-weighted).
std::vector<double> areaLost(std::span<const Vec3> now, std::span<const Vec3> rest, const std::vector<std::uint32_t>& tris) {
  std::vector<double> a(now.size(), 0.0), r(now.size(), 0.0);
  for (std::size_t t = 0; t + 2 < tris.size(); t += 3) {
    const std::uint32_t i = tris[t], j = tris[t + 1], k = tris[t + 2];
    const double an = (now[j] - now[i]).cross(now[k] - now[i]).norm(), ar = (rest[j] - rest[i]).cross(rest[k] - rest[i]).norm();
    for (std::uint32_t v : {i, j, k}) a[v] += an, r[v] += ar;
  }
  for (std::size_t v = 0; v < a.size(); ++v) a[v] = r[v] > 0 ? 1.0 - a[v] / r[v] : 0.0;
  return a;
}

}  // namespace

const SkinDetail& FaceBody::detail() const {
  std::call_once(detail_once_, [&] {
    detail_ = makeSkinDetail(surface_, kSkinDetailLevel);
    detail_.place(surface_.skin, surface_.skin, surface_.skin, surface_.tris, 0, detail_rest_);
    detail_regions_.resize(detail_rest_.size());
    for (std::size_t k = 0; k < detail_rest_.size(); ++k) detail_regions_[k] = head::wrinkleRegions(detail_rest_[k] / surface_.scale);
  });
  return detail_;
}

std::shared_ptr<TriMesh> FaceBody::skinMesh(std::vector<Vec3>* relaxed, std::vector<double>* lost, std::vector<double>* lines) const {
  const std::size_t n = surface_.size();
  const auto& x = net_.state.x;
  if (!surface_.generated) {
    if (lost) *lost = areaLost(std::span<const Vec3>(x.data(), n), surface_.skin, surface_.tris);
    if (lines) lines->assign(n, 0.0);
    return smoothMesh(x, 0, n, surface_.tris);
  }
  // reel's head is drawn finer than it is simulated (SkinDetail), made once when first drawn,
  // with its wrinkles' regions at rest.
  const SkinDetail& d = detail();
  std::vector<Vec3> p, posed(n);
  for (std::size_t k = 0; k < n; ++k) posed[k] = boneToWorld(k, surface_.skin[k]);
  d.place(surface_.skin, posed, std::span<const Vec3>(x.data(), n), surface_.tris, kSkinSmoothing, p, relaxed);
  // Wrinkles: how deep the wrinkle map sinks at each vertex (wrinkleDepth). (They used to fold
  // the mesh itself in, 0.5 mm; its vertices, a millimetre or more apart, drew them as blobs.)
  std::vector<double> shrunk = areaLost(p, detail_rest_, d.tris);
  std::vector<double> folds = wrinkleDepth(shrunk);
  auto mesh = smoothMesh(p, 0, p.size(), d.tris);
  mesh->wrinkle.assign(folds.begin(), folds.end());
  for (std::size_t k = 0; k < p.size(); ++k) mesh->uvs[2 * k] = d.points[k].uv[0], mesh->uvs[2 * k + 1] = d.points[k].uv[1];
  if (lost) *lost = std::move(shrunk);
  if (lines) *lines = std::move(folds);
  return mesh;
}

std::vector<double> FaceBody::wrinkleDepth(const std::vector<double>& lost) const {
  if (!surface_.generated) return {};
  detail();
  REEL_CHECK(lost.size() == detail_regions_.size(), "wrinkleDepth: one area lost per vertex of the skin drawn");
  auto control = [&](const std::string& name) {
    const int i = activations_.index(name);
    return i < 0 ? 0.0 : std::clamp(act_[static_cast<std::size_t>(i)], 0.0, 1.0);
  };
  // Each region's muscles, the left side's (+x) and the right's.
  std::array<head::Wrinkles, 2> pull;
  for (int side = 0; side < 2; ++side) {
    const std::string s = side == 0 ? "_left" : "_right";
    pull[static_cast<std::size_t>(side)] = {std::max(control("frontalis_inner" + s), control("frontalis_outer" + s)),
                                            std::max(control("corrugator_left"), control("corrugator_right")),
                                            std::max(control("orbicularis_oculi" + s), control("zygomatic_major" + s)),
                                            std::max(control("zygomatic_major" + s), control("levator_labii" + s)),
                                            control("levator_labii" + s)};
  }
  std::vector<double> out(detail_regions_.size(), 0.0);
  for (std::size_t k = 0; k < out.size(); ++k) {
    const head::Wrinkles& w = detail_regions_[k];
    const head::Wrinkles& a = pull[detail_rest_[k].x() >= 0 ? 0 : 1];
    out[k] = std::max({w.forehead * a.forehead, w.glabella * a.glabella, w.crows * a.crows, w.fold * a.fold, w.nose * a.nose,
                       w.most() * smoothstep(0.02, 0.15, lost[k])});
  }
  return out;
}

// Eyes, turned toward the gaze target, each shaded by its lids: the lids, their lashes and the
// brow above keep light from the eyeball near their edges and in the eye's corners (a white
// sclera lit evenly right up to the lids reads as a ball pasted on the face).
void FaceBody::drawEyes(DrawList& out) const {
  static const std::shared_ptr<const TriMesh> kEye = eyeMesh(Vec3(0.12, 0.22, 0.35));
  const std::shared_ptr<const TriMesh> eye_mesh = desc_.iris_color == Vec3(0.12, 0.22, 0.35) ? kEye : eyeMesh(desc_.iris_color);
  // The tear film over the cornea is a mirror: a small, crisp catchlight (at roughness 0.4, a
  // Blinn–Phong 80, the highlight spread over the pupil as a grey haze a viewer read as cataracts).
  DrawMaterial wet_eye = plainMaterial(Vec3(1, 1, 1), 0.6);
  wet_eye.roughness = 0.12;
  for (int e = 0; e < 2; ++e) {
    const Eye ey = eye(e);
    Mat3 B;
    B << ey.right, ey.up, ey.ahead;
    auto ball = std::make_shared<TriMesh>(*eye_mesh);
    ball->gloss.assign(ball->vertexCount(), 0.0f);
    for (std::size_t v = 0; v < ball->vertexCount(); ++v) {
      const Vec3 q(ball->positions[3 * v], ball->positions[3 * v + 1], ball->positions[3 * v + 2]);
      const Vec3 d = B * q, h = R_.transpose() * d;  // the direction from the eye's centre, world and head
      const double el = std::asin(std::clamp(h.y(), -1.0, 1.0)), az = std::atan2(h.x(), h.z());
      // The lids' shadows on the eyeball: the upper lid's and its lashes' deepest (they overhang
      // it), the lower's faint, and the corners' (at 0.4 under the upper lid and 0.7 in the
      // corners the white ran bright to the lids, as if painted on).
      const double cornered = smoothstep(ey.corner - 0.7, ey.corner, std::abs(az));  // 0 mid-eye, 1 in a corner
      const double shade = (0.25 + 0.75 * smoothstep(0.0, 0.6, ey.upperEdge(az) - el)) *
                           (0.7 + 0.3 * smoothstep(0.0, 0.3, el - ey.lowerEdge(az))) * (1.0 - 0.5 * cornered);
      // The corners keep the lights' reflections off the eyeball, too: dulled there (a negative
      // gloss; by the corners alone, not the lids' shade, which would dull the catchlight under
      // the upper lid), the inner corner's wet white no
      // longer flashes as a white streak beside the nose, lit by the rim and the bounce where the
      // eye turns away from the camera.
      ball->gloss[v] = static_cast<float>(-cornered);
      for (int k = 0; k < 3; ++k) {
        ball->positions[3 * v + static_cast<std::size_t>(k)] = static_cast<float>(ey.center[k] + ey.radius * d[k]);
        ball->normals[3 * v + static_cast<std::size_t>(k)] = static_cast<float>(d[k]);
        ball->colors[3 * v + static_cast<std::size_t>(k)] *= static_cast<float>(shade);
      }
    }
    out.meshes.push_back({std::move(ball), true, wet_eye});
  }
}

double FaceBody::mouthLight(double closed, double from, double over) const {
  // (Dimmer as the lips close: little light reaches into a closed mouth.)
  const double open = mouthOpening() / surface_.scale;
  return closed + (1.0 - closed) * std::clamp((open - from) / over, 0.0, 1.0);
}

void FaceBody::drawSkin(DrawList& out) const {
  std::vector<Vec3> relaxed;
  std::vector<double> lost;
  std::shared_ptr<TriMesh> mesh = skinMesh(&relaxed, &lost);
  const bool fine = surface_.generated;
  DrawMesh skin;
  skin.material = drawMaterial(material_);
  skin.material.scatter = kSkinScatter * surface_.scale;
  const std::size_t nv = mesh->vertexCount();
  if (surface_.generated) {
    // reel's head: its skin's texture and relief, made once when first drawn.
    std::call_once(skin_once_, [&] {
      skin_texture_ = skinTexture(surface_);
      skin_relief_ = skinRelief(surface_);
      skin_wrinkles_ = skinWrinkles(surface_);
    });
    skin.material.texture = skin_texture_;
    skin.material.bump = skin_relief_;
    skin.material.bump_depth = kSkinReliefDepth * surface_.scale;
  }
  // reel's head: a sheen over the skin, more on the T-zone and the lips (per-vertex gloss smooths
  // the surface and adds to its reflectance), and where hair covers it dulled (gloss −1: rougher,
  // 1 with the material's 0.7, its reflection in its own colour).
  if (fine) {
    mesh->gloss.resize(nv);
    for (std::size_t k = 0; k < nv; ++k) mesh->gloss[k] = static_cast<float>(detail_.blend(detail_.points[k], surface_.gloss));
  }
  // Wrinkles, a wrinkle map weighted by the muscles and the tissue's strain (after Oat 2007,
  // "Animated wrinkle maps", SIGGRAPH course): the map holds the lines (head::wrinkleLines) as
  // relief 1 mm deep, their floors up to 20% darker, and each vertex says how far they sink
  // there now (wrinkleDepth, in the mesh's wrinkle weights). Where the skin drawn has shrunk in
  // area (the brows drawn together, the cheeks pushed up against the eyes) it shades darker too,
  // by up to 15% at 30% of area lost. (At 35% for the area lost, the broad shade read as brown
  // smudges and bruises beside the eyes: the lines should carry a wrinkle, not the patch around
  // them; drawn by the mesh's vertices, the lines read as blobs.)
  if (fine) {
    skin.material.wrinkles = skin_wrinkles_;
    skin.material.wrinkle_depth = kWrinkleDepth * surface_.scale;
    skin.material.wrinkle_shade = 0.2;
  }
  for (std::size_t k = 0; k < nv; ++k) {
    const double crease = 1.0 - 0.15 * smoothstep(0.06, 0.3, lost[k]);
    // (reel's head: its tint, which differs from side to side where the texture is mirrored.)
    const Vec3 c = (fine ? Vec3(detail_.points[k].tint[0], detail_.points[k].tint[1], detail_.points[k].tint[2]) : surface_.color[k]) * crease;
    for (int i = 0; i < 3; ++i) mesh->colors.push_back(static_cast<float>(c[i]));
  }
  const TriMesh& drawn = *mesh;  // (the brows' hairs root on it; the draw list keeps it)
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
    ear.bump.reset();
    ear.wrinkles.reset();
    ear.double_sided = true;
    ear.translucency = kEarTranslucency;
    out.meshes.push_back({std::move(ears), true, ear});
  }
  if (surface_.hair && surface_.hair->vertexCount() > 0) {
    auto hair = std::make_shared<TriMesh>(*surface_.hair);
    hair->transform(R_, desc_.position);
    addBrowHairs(*hair, drawn);
    // Dulled as the cap is (gloss −1): their sheen in their own colour, none white at grazing (with a
    // white Fresnel sheen, at 0.3 the strands on the outline, seen edge-on, made a grey rim; at 0.06
    // they glinted there as white specks a viewer saw as a blotchy patch on the crown).
    hair->gloss.assign(hair->vertexCount(), -1.0f);
    DrawMaterial strands = plainMaterial(Vec3(1, 1, 1), 0.06);
    strands.roughness = 0.5;
    strands.double_sided = true;
    strands.casts_shadow = false;  // (the cap under them casts the head's shadow)
    out.meshes.push_back({std::move(hair), true, strands});
  }
  // The mouth's inside, seen through the parted lips: the skin's inner side, drawn near black
  // but red at the lips, so whatever one sees past the lips is the mouth's cavity; the teeth, the upper row on the
  // skull, the lower on the jaw; and the tongue.
  {
    // (The simulated skin's triangles, not the nine times as many drawn: 1.5 mm in, and
    // further where the skin drawn dips below them, so it never shows through the skin.)
    auto inside = smoothMesh(relaxed, 0, relaxed.size(), surface_.tris);
    // How much of the lips' inner faces each vertex is: near the parting, across the mouth, at
    // the front (rest positions).
    const double yp = surface_.mouth.y(), half = 0.5 * surface_.mouth_width, sc = surface_.scale;
    std::vector<double> lip(inside->vertexCount());
    for (std::size_t v = 0; v < lip.size(); ++v) {
      const Vec3& q = surface_.skin[v];
      lip[v] = std::exp(-std::max(0.0, std::abs(q.y() - yp) - 0.002 * sc) / (0.003 * sc)) *
               smoothstep(half + 0.004 * sc, half - 0.004 * sc, std::abs(q.x())) *
               smoothstep(surface_.mouth.z() - 0.02 * sc, surface_.mouth.z() - 0.01 * sc, q.z());
    }
    // (The lips' lining 4 mm in, so they part with their thickness (addLipRims).)
    for (std::size_t v = 0; v < inside->vertexCount(); ++v)
      for (int k = 0; k < 3; ++k)
        inside->positions[3 * v + static_cast<std::size_t>(k)] -=
            static_cast<float>((0.0015 + 0.0025 * lip[v]) * sc + detail_.dip[v]) * inside->normals[3 * v + static_cast<std::size_t>(k)];
    for (float& v : inside->normals) v = -v;
    for (std::size_t t = 0; t + 2 < inside->indices.size(); t += 3) std::swap(inside->indices[t + 1], inside->indices[t + 2]);
    inside->uvs.clear();
    // The lips' inner faces a wet red, 3 mm in from the parting; past them the mouth is near
    // black (little light reaches far into it: lit evenly all through, the cavity read as a red
    // box, and the head's inside seen through the lips as a maroon wall).
    inside->colors.resize(3 * inside->vertexCount());
    for (std::size_t v = 0; v < inside->vertexCount(); ++v) {
      const Vec3 c = Vec3(0.08, 0.016, 0.015) + lip[v] * (Vec3(0.4, 0.12, 0.11) - Vec3(0.08, 0.016, 0.015));
      for (int k = 0; k < 3; ++k) inside->colors[3 * v + static_cast<std::size_t>(k)] = static_cast<float>(c[k]);
    }
    addLipRims(*inside, relaxed);
    DrawMaterial dark = plainMaterial(kMouthInside, 0.1);
    dark.casts_shadow = false;
    out.meshes.push_back({std::move(inside), true, dark});
    const double k = surface_.scale, ym = surface_.mouth.y();
    const double front = surface_.mouth.z() - 0.0085 * k;
    const double lit = mouthLight();
    drawTeeth(out, lit);
    // The tongue: a flattened ellipsoid on the mouth's floor behind the lower teeth, its back
    // about 6 mm below their edges, with the jaw; wet, but with little to reflect inside a mouth.
    const Vec3 centre(0.0, ym - 0.0115 * k, front - 0.027 * k);
    auto tongue = std::make_shared<TriMesh>(
        placeMesh(makeUvSphere(1.0, 24, 12), k * Vec3(0.019, 0.0045, 0.024), jawRotation(1.0), world(jawMoved(1.0, centre))));
    // (Its papillae break a wet sheen up: as a smooth 0.35 the key's highlight lay over the tip as a
    // grey-white film, and the tongue read as plastic.)
    DrawMaterial wet = plainMaterial(lit * Vec3(0.36, 0.085, 0.08), 0.01);
    wet.roughness = 0.55;
    wet.casts_shadow = false;
    out.meshes.push_back({std::move(tongue), true, wet});
  }
  drawEyes(out);
  // The lids' colours: the skin's tone, a shade darker, and the lash line at their edges.
  // (A shade darker and warmer than the skin: the skin round the eyes is thin; in the skin's
  // own tone the upper lids, catching the key, read as pale ovals stuck on; greyer, at (0.41,
  // 0.24, 0.2), a shut lid read as a grey disc pasted on.)
  const Vec3 lid_tone(0.47, 0.26, 0.2), lash_tone(0.07, 0.05, 0.04);
  const Vec3 caruncle(0.52, 0.22, 0.2), rim(0.44, 0.27, 0.23);  // (at 0.5, 0.27, 0.24 viewers saw sore, red-rimmed eyes)
  auto lids = std::make_shared<TriMesh>(), lashes = std::make_shared<TriMesh>();
  auto vertex = [&](const Vec3& p, const Vec3& normal, const Vec3& color) {
    lids->addVertex(world(p), R_ * normal);
    for (int k = 0; k < 3; ++k) lids->colors.push_back(static_cast<float>(color[k]));
  };
  auto lash = [&](const Vec3& p, const Vec3& normal) { lashes->addVertex(world(p), R_ * normal); };
  for (int e = 0; e < 2; ++e) {
    const Eye ey = eye(e);
    const double r = ey.lid_radius, span = ey.lid_azimuth;
    const Vec3 c = surface_.eye[static_cast<std::size_t>(e)];
    constexpr int kA = 18, kE = 24;
    auto at = [&](double el, double az) { return Vec3(std::cos(el) * std::sin(az), std::sin(el), std::cos(el) * std::cos(az)); };
    auto azimuth = [&](int i) { return span * (2.0 * i / kA - 1.0); };
    for (int lower = 0; lower < 2; ++lower) {
      const double to = lower ? -0.5 * kPi : 0.5 * kPi;
      auto from = [&](double az) { return lower ? ey.lowerEdge(az) : ey.upperEdge(az); };
      auto base = static_cast<std::uint32_t>(lids->vertexCount());
      for (int j = 0; j <= kE; ++j) {
        const double line = j == 0 ? (lower ? 0.3 : 0.75) : 0.0;
        for (int i = 0; i <= kA; ++i) {
          const double az = azimuth(i), el = from(az) + (to - from(az)) * j / kE;
          // The upper lid's fold (the supratarsal crease, where the lid tucks under the skin
          // above it when open), a shade darker at a fixed height, 43° above the eye's centre;
          // a fainter one under the lower lid.
          // (Shut, the upper lid's skin is drawn down smooth over the eye and its fold all but
          // goes: kept, it ringed a shut eye with a dark outline, a cap set on the face.)
          const double fold = lower ? 0.12 * std::exp(-0.5 * std::pow((el + 0.75) / 0.1, 2))
                                    : 0.3 * (1.0 - 0.8 * ey.closure) * std::exp(-0.5 * std::pow((el - 0.75) / 0.07, 2));
          // The upper lid's skin in its lashes' shade, darkest at their roots.
          const double shade = lower ? 0.0 : 0.3 * std::exp(-std::abs(el - from(az)) / 0.2);
          Vec3 tone = (1.0 - fold) * (1.0 - shade) * lid_tone;
          // The inner corner's caruncle and fold, pink where the lids meet (a lid there in the
          // skin's tone read as a notch cut into the face).
          const double inner = smoothstep(0.7, 1.0, -ey.outward * az / ey.corner) * std::exp(-std::abs(el - from(az)) / 0.25);
          tone = tone + 0.8 * inner * (caruncle - tone);
          vertex(c + r * at(el, az), at(el, az), tone + (1.0 - inner) * line * (lash_tone - tone));
        }
      }
      gridTriangles(*lids, base, kE, kA);
      // The lid's margin: its thickness, from the shell down to the eyeball (a strip facing the
      // opening), dark under the upper lashes, the lower lid's wet rim pink. Without it the
      // lids were paper-thin and the eye read as painted on.
      base = static_cast<std::uint32_t>(lids->vertexCount());
      for (int q = 0; q < 2; ++q)
        for (int i = 0; i <= kA; ++i) {
          const double az = azimuth(i), el = from(az), rq = q == 0 ? r : 1.004 * surface_.eye_radius;
          const Vec3 facing = lower ? Vec3(-std::sin(el) * std::sin(az), std::cos(el), -std::sin(el) * std::cos(az))
                                    : Vec3(std::sin(el) * std::sin(az), -std::cos(el), std::sin(el) * std::cos(az));
          vertex(c + rq * at(el, az), facing, lower ? rim : lash_tone);
        }
      gridTriangles(*lids, base, 1, kA);
      // The lashes, one by one: ribbons tapering from 0.17 mm at the root (0.12 below) along the
      // margin, curving out and then up (down below), longer in the middle and toward the outer
      // corner, each its own length and slant; 5.2 mm above and 2.2 mm below (real lashes are 8-12
      // and 6-8 mm, but thinner: at 0.26 and 6.2 mm a close-up showed a doll's false lashes; the
      // lower lie against the lid). As a solid fringe cut into points they read as a comb.
      const double outer = ey.outward;  // the side the eye's outer corner lies (head +x for the left eye)
      const int count = lower ? 24 : 90;
      const double length = (lower ? 0.0022 : 0.0052) * surface_.scale, width = (lower ? 0.00012 : 0.00017) * surface_.scale;
      const Vec3 away(0, lower ? -1 : 1, 0);
      // The lash line: where the lashes root, densely, a dark band along the margin 0.7 mm out
      // (0.3 mm below), thinning to nothing at the corners. At a film's distance a lash is far
      // under a pixel and they read only as this line and a soft fringe beyond it.
      {
        constexpr int kM = 40;
        base = static_cast<std::uint32_t>(lashes->vertexCount());
        const double band = (lower ? 0.0003 : 0.0007) * surface_.scale;
        for (int i = 0; i <= kM; ++i) {
          const double u = 0.98 * (2.0 * i / kM - 1.0), az = outer * u * ey.corner;
          const Vec3 d = at(from(az), az), dir = (d + 0.3 * away).normalized();
          const Vec3 normal = dir.cross(Vec3(std::cos(az), 0, -std::sin(az))).normalized();
          lash(c + r * d, normal);
          lash(c + r * d + band * std::sqrt(lidLobe(u)) * dir, normal);
        }
        ribbonTriangles(*lashes, base, kM);
      }
      for (int k = 0; k < count; ++k) {
        const auto rnd = [&](int stream) { return uniformAt(static_cast<std::uint64_t>(e * 2 + lower), static_cast<std::uint64_t>(stream), static_cast<std::uint64_t>(k)); };
        const double u = 0.94 * (2.0 * (k + 0.2 + 0.6 * rnd(0)) / count - 1.0);  // across: -1 inner .. 1 outer corner
        const double az = outer * u * ey.corner;
        const double l = length * (0.45 + 0.55 * lidLobe(u)) * (0.8 + 0.2 * std::max(u, 0.0)) * (0.7 + 0.45 * rnd(1));
        const Vec3 d = at(from(az), az), side(std::cos(az), 0, -std::sin(az));
        // Out from the eye, tipped away from it, leaning toward the nearer corner.
        const Vec3 out0 = (d + 0.12 * away + (0.3 * u + 0.15 * (rnd(2) - 0.5)) * outer * side).normalized();
        const Vec3 root = c + (r + 0.0002 * surface_.scale * rnd(3)) * d;
        base = static_cast<std::uint32_t>(lashes->vertexCount());
        constexpr int kS = 4;  // segments
        for (int q = 0; q <= kS; ++q) {
          const double t = static_cast<double>(q) / kS;
          // The curl: the tangent turns from out0 toward `away` along its length.
          const Vec3 p = root + l * (t * out0 + (0.3 + 0.2 * rnd(4)) * t * t * away);
          const Vec3 tangent = (out0 + 2.0 * (0.3 + 0.2 * rnd(4)) * t * away).normalized();
          const double w = 0.5 * width * (1.0 - 0.85 * t);
          lash(p - w * side, tangent.cross(side).normalized());
          lash(p + w * side, tangent.cross(side).normalized());
        }
        ribbonTriangles(*lashes, base, kS);
      }
    }
  }
  DrawMaterial lid = drawMaterial(material_);
  lid.scatter = kSkinScatter * surface_.scale;
  lid.double_sided = true;
  out.meshes.push_back({std::move(lids), true, lid});
  // The lashes: dark, matt and with no Fresnel sheen (seen edge-on a ribbon's grazing reflection
  // lit the fringe up pale, which read as mould).
  DrawMaterial lash_material = plainMaterial(Vec3(0.025, 0.018, 0.014), 0.0);  // near black: lit by the key, lash_tone read mid-brown
  lash_material.roughness = 0.8;
  lash_material.double_sided = true;
  lash_material.casts_shadow = false;
  out.meshes.push_back({std::move(lashes), true, lash_material});
}

FaceBody::Eye FaceBody::eye(int e) const {
  Eye out;
  const Vec3 ahead = R_ * Vec3::UnitZ(), up = R_ * Vec3::UnitY();
  out.center = desc_.position + R_ * surface_.eye[static_cast<std::size_t>(e)];
  out.radius = surface_.eye_radius;
  // The gaze: toward its target, straight up to 20° from ahead, then easing toward 30°
  // (θ' = 20° + 10° tanh((θ − 20°)/10°)):
  // eyes turned to a hard 35° stop jammed the iris into the lids' corner and bulged the white past
  // them, which viewers read as glued-on marbles; a person turns the head before the eyes go so far.
  Vec3 look = ahead;
  if (!desc_.gaze.empty()) {
    const Vec3 target = keyedLinear(desc_.gaze, t_, [](const FaceGazeKey& k) { return k.time; },
                                    [](const FaceGazeKey& k) { return k.target; });
    look = unitOr(target - out.center, ahead);
    const double angle = std::acos(std::clamp(look.dot(ahead), -1.0, 1.0)), straight = 20.0 * kPi / 180.0, ease = 10.0 * kPi / 180.0;
    if (angle > straight) {
      const double eased = straight + ease * std::tanh((angle - straight) / ease);
      const Vec3 side = unitOr(look - look.dot(ahead) * ahead, up);
      look = std::cos(eased) * ahead + std::sin(eased) * side;
    }
  }
  out.ahead = look;
  out.right = unitOr(up.cross(look), R_ * Vec3::UnitX());
  out.up = look.cross(out.right);
  // The lids: open, the upper margin's top 20° above the centre, just over the iris's top (30°
  // with eyelid_raise: white shows above it), the lower's bottom 21° below, just over the iris's
  // bottom (at 24° white showed under the iris, a stare; higher as the
  // orbicularis oculi squeezes); both follow the gaze up and down, the upper 0.7 and the lower
  // 0.4 of its elevation (the levator and the lower lid's retractors move with the eye: with
  // lids that stayed, eyes looking down showed a band of white above the iris, as if rolled
  // back). A blink, or the orbicularis oculi in part, brings the upper margin down past the lower.
  auto control = [&](const std::string& name) {
    const int i = activations_.index(name);
    return i < 0 ? 0.0 : act_[static_cast<std::size_t>(i)];
  };
  const double squeeze = control(e == 0 ? "orbicularis_oculi_left" : "orbicularis_oculi_right");
  constexpr double deg = kPi / 180.0;
  // (The squeeze brings the upper lid a fifth of the way to shut: at 0.45, a smile's eyes, narrowed
  // from above as much as from below, read as a wince.)
  out.closure = std::clamp(std::max(control("blink"), 0.2 * squeeze), 0.0, 1.0);
  const double gaze = std::asin(std::clamp(look.dot(up), -1.0, 1.0));  // the gaze's elevation in the head
  out.upper = (20.0 + 10.0 * control("eyelid_raise")) * deg + 0.7 * gaze;
  out.lower = (-21.0 + 14.0 * squeeze) * deg + 0.4 * gaze;
  // The corners 72° to each side on the lids' shell (the opening about 26.4 mm wide at 0.24 m, a
  // little short of Farkas 1994's palpebral fissure, 28-30 mm, whose inner end lies past the
  // eyeball; at 61°, 23 mm, viewers found the eyes small), the outer 8° above the inner.
  out.corner = head::kEyeCorner;
  out.corners = head::kEyeCorners;
  out.tilt = head::kCanthalTilt;
  out.outward = e == 0 ? 1.0 : -1.0;
  out.lid_radius = head::kLidShell * surface_.eye_radius;
  out.lid_azimuth = head::kLidAzimuth;
  return out;
}


// The upper margin is highest a little inside the middle, the lower lowest a little outside it
// (the eyelids' shape in Farkas 1994 and any portrait): the lobes' peaks at u = -0.12 and 0.18.
double FaceBody::Eye::lowerEdge(double az) const {
  const double u = outward * az / corner, c = corners + 0.5 * tilt * std::clamp(u, -1.0, 1.0);
  return c + (lower - c) * lidLobe(acrossLobe(u, 0.18));
}

double FaceBody::Eye::upperEdge(double az) const {
  const double u = outward * az / corner, c = corners + 0.5 * tilt * std::clamp(u, -1.0, 1.0);
  const double open = c + (upper - c) * lidLobe(acrossLobe(u, -0.12));
  // Shut, it comes down 3° past the lower margin.
  return open + closure * (lowerEdge(az) - 3.0 * kPi / 180.0 - open);
}

}  // namespace reel
