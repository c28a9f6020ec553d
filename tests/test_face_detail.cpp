// reel's head drawn finer than it is simulated (SkinDetail): the fine skin holds the head's own
// shape where the simulated mesh is too coarse (the nose's tip, the lips), keeps the skin's
// topology (closed but for the lips' parting), and follows the tissue: carried rigidly with the
// head, a uniform move kept, the tissue's grid-long ripples smoothed out. And what is drawn around
// the openings: the lips' rims on curves, the eyes' gaze and the lids that follow it.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include "core/math.h"
#include "sim/face/head.h"
#include "face_scene.h"
#include "helpers.h"
#include "sim/face/face_body.h"
#include "sim/face/head_shape.h"
#include "sim/world.h"

using namespace reel;
using namespace reel::test;

namespace {

constexpr int kLevel = 3;

// The undirected edges used by one triangle only, and whether any directed edge is used twice.
std::pair<int, bool> openEdges(const std::vector<std::uint32_t>& tris) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  for (std::size_t t = 0; t + 2 < tris.size(); t += 3)
    for (int e = 0; e < 3; ++e) ++directed[{tris[t + static_cast<std::size_t>(e)], tris[t + static_cast<std::size_t>((e + 1) % 3)]}];
  int open = 0;
  bool twice = false;
  for (const auto& [e, count] : directed) {
    twice = twice || count > 1;
    if (!directed.count({e.second, e.first})) ++open;
  }
  return {open, twice};
}

std::vector<Vec3> placed(const SkinDetail& d, const FaceSurface& s, const std::vector<Vec3>& posed, const std::vector<Vec3>& now,
                         int smoothing = 2) {
  std::vector<Vec3> out;
  d.place(s.skin, posed, now, s.tris, smoothing, out);
  return out;
}

}  // namespace

TEST_CASE("face: the skin drawn finer holds the head's shape where the simulated mesh is too coarse") {
  const FaceSurface s = makeHead(0.24, {64, 40}, 0.008);
  const SkinDetail d = makeSkinDetail(s, kLevel);
  REQUIRE(!d.points.empty());
  // The skin's topology: no triangle turned over against its neighbour, closed but for the lips'
  // parting, whose every edge is split in kLevel.
  const auto [coarse_open, coarse_twice] = openEdges(s.tris);
  const auto [fine_open, fine_twice] = openEdges(d.tris);
  MESSAGE("edges open at the parting: " << coarse_open << " simulated, " << fine_open << " drawn; "
                                        << d.points.size() << " points drawn for " << s.size());
  REQUIRE(coarse_open > 0);
  CHECK(!coarse_twice);
  CHECK(!fine_twice);
  CHECK(fine_open == kLevel * coarse_open);
  // At rest, the nose in profile: the head's exact midline over the nose's lower half, its tip
  // and under it (sampled every 0.006°), and how far it passes from the polyline of the skin drawn
  // and from the simulated skin's (the chord's error falls with the square of the spacing, so
  // three times finer should miss by far less than half).
  const std::vector<Vec3> fine = placed(d, s, s.skin, s.skin);
  auto midline = [&](const std::vector<Vec3>& pts) {
    std::vector<Vec3> m;
    for (const Vec3& p : pts)
      if (std::abs(p.x()) < 1e-6 && p.z() > 0.05 * s.scale) m.push_back(p);
    std::sort(m.begin(), m.end(), [](const Vec3& a, const Vec3& b) { return a.y() < b.y(); });
    return m;
  };
  auto miss = [](const std::vector<Vec3>& line, const Vec3& q) {
    double best = 1e9;
    for (std::size_t i = 0; i + 1 < line.size(); ++i) {
      const Vec3 a = line[i], ab = line[i + 1] - a;
      const double t = std::clamp((q - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
      best = std::min(best, (a + t * ab - q).norm());
    }
    return best;
  };
  const std::vector<Vec3> fine_line = midline(fine), coarse_line = midline(s.skin);
  double drawn = 0, simulated = 0, tip = 0, tip_drawn = 0;
  for (double th = 1.3; th < 2.1; th += 1e-4) {
    const Vec3 dir = head::direction(th, 0.0);
    const Vec3 q = s.scale * head::skinPoint(head::baseRadius(dir, s.look) * dir, dir, s.parting_y, s.look);
    if (q.y() < -0.05 * s.scale || q.y() > -0.02 * s.scale) continue;
    drawn = std::max(drawn, miss(fine_line, q));
    simulated = std::max(simulated, miss(coarse_line, q));
    tip = std::max(tip, q.z());
  }
  for (const Vec3& p : fine_line) tip_drawn = std::max(tip_drawn, p.z());
  MESSAGE("the nose in profile: the skin drawn misses it by up to " << drawn * 1e3 << " mm, the simulated skin by "
                                                                    << simulated * 1e3 << " mm");
  // (The fine points lie on the exact surface: none beyond its tip.)
  CHECK(tip_drawn <= tip + 1e-9);
  CHECK(drawn < 0.5 * simulated);
  // Over the face, how far the simulated mesh (its triangles' blend) passes from the head's shape:
  // the detail it cannot hold (the nose's wings, nostrils, the lips' border).
  double missed = 0;
  for (std::size_t k = 0; k < fine.size(); ++k)
    if (fine[k].z() > 0.05) missed = std::max(missed, d.points[k].offset.norm());
  MESSAGE("the simulated mesh misses the face's shape by up to " << missed * 1e3 << " mm");
  CHECK(missed > 1e-3);
  // The simulated skin's own vertices are among the fine points, where they are.
  int found = 0;
  for (const Vec3& p : s.skin)
    for (const Vec3& q : fine)
      if ((p - q).norm() < 1e-9) {
        ++found;
        break;
      }
  CHECK(found == static_cast<int>(s.size()));
}

TEST_CASE("face: the skin drawn follows the tissue: rigidly with the head, a uniform move kept, ripples smoothed") {
  const FaceSurface s = makeHead(0.24, {48, 32}, 0.008);
  const SkinDetail d = makeSkinDetail(s, kLevel);
  const std::vector<Vec3> rest = placed(d, s, s.skin, s.skin);
  const Mat3 R = rotationFromEulerDeg(Vec3(20, -35, 10));
  const Vec3 t(0.3, -0.1, 2.0), shift(0.002, -0.001, 0.003);
  std::vector<Vec3> posed(s.size()), moved(s.size());
  for (std::size_t k = 0; k < s.size(); ++k) posed[k] = R * s.skin[k] + t, moved[k] = posed[k] + shift;
  // Carried with the head: each fine point where the head's motion takes it.
  const std::vector<Vec3> turned = placed(d, s, posed, posed);
  double rigid = 0, uniform = 0;
  const std::vector<Vec3> shifted = placed(d, s, posed, moved);
  for (std::size_t k = 0; k < rest.size(); ++k) {
    rigid = std::max(rigid, (turned[k] - (R * rest[k] + t)).norm());
    uniform = std::max(uniform, (shifted[k] - (R * rest[k] + t + shift)).norm());
  }
  MESSAGE("largest miss, turned with the head: " << rigid << " m; moved 3.7 mm with it: " << uniform << " m");
  CHECK(rigid < 1e-9);
  CHECK(uniform < 1e-9);
  // A ripple one column long (every other column 0.5 mm out, the rest 0.5 mm in, over the face):
  // drawn at under a quarter of it (rms) after two passes, and as it is without them.
  std::vector<Vec3> rippled = posed;
  for (std::size_t k = 1; k + 1 < s.size(); ++k) {
    const int column = static_cast<int>((k - 1) % static_cast<std::size_t>(s.columns));
    if (s.skin[k].z() > 0.03) rippled[k] += (column % 2 ? 5e-4 : -5e-4) * (R * s.skin[k].normalized());
  }
  auto rms = [&](const std::vector<Vec3>& a) {
    double sum = 0;
    for (std::size_t k = 0; k < a.size(); ++k) sum += (a[k] - turned[k]).squaredNorm();
    return std::sqrt(sum / static_cast<double>(a.size()));
  };
  const double raw = rms(placed(d, s, posed, rippled, 0)), smooth = rms(placed(d, s, posed, rippled, 2));
  MESSAGE("the ripple drawn: " << raw << " m rms as simulated, " << smooth << " m smoothed");
  CHECK(raw > 1e-4);
  CHECK(smooth < raw / 4);  // (4.5 times: the skin's diagonals in a checkerboard; 5 and more mirrored about the midline)
}

TEST_CASE("face: the skin's sheen: dulled on the hair and in the eyes' inner corners, the lips glossiest, the nose more than the cheek") {
  const double ym = -0.07;
  auto at = [&](double x, double y) {
    // The base point of the default head straight out from its centre toward (x, y, front).
    const Vec3 d = Vec3(x, y, 0.09).normalized();
    return head::skinGloss(head::baseRadius(d, FaceLook{}) * d, d, ym);
  };
  const double crown = head::skinGloss(Vec3(0, 0.11, 0), Vec3(0, 1, 0), ym);
  const double lips = at(0.0, ym - 0.005), nose = at(0.0, -0.03), cheek = at(0.045, -0.03);
  MESSAGE("gloss: crown " << crown << ", lips " << lips << ", nose " << nose << ", cheek " << cheek);
  CHECK(crown == -1.0);
  CHECK(lips > nose);
  // The inner corners' pits dulled (their sheen at grazing flashed white beside the eye), and the
  // nose's sides, where disgust's lines fold, duller than its ridge.
  const double canthus = at(head::kEyeX - 0.0135, -0.002), side = at(0.008, -0.006), ridge = at(0.0, -0.006);
  // Down to the wings too (their sheen under a rim light read as a white patch on a turned
  // head's nose), but not the tip.
  const double wing = at(0.012, -0.03), tip = at(0.0, -0.036);
  MESSAGE("gloss: inner corner " << canthus << ", nose's side " << side << ", its ridge " << ridge << ", wing " << wing << ", tip " << tip);
  CHECK(canthus < -0.3);
  CHECK(side < 0.5 * ridge);
  CHECK(wing < 0.5 * tip);
  CHECK(nose > cheek + 0.05);
  CHECK(cheek > 0.1);
}


TEST_CASE("face: the lips are rose against the skin, the nostrils dark, the philtrum's ridges stand out") {
  const double ym = -0.07;
  const FaceLook look{};
  auto color = [&](double x, double y) {
    const Vec3 d = Vec3(x, y, 0.09).normalized();
    return head::skinColor(head::baseRadius(d, look) * d, d, ym, look);
  };
  // Green over red: how rose a tone is (skin about 0.55, lips under 0.36: at 0.43 viewers found the
  // lips skin-coloured, and the upper lip read as long and bare).
  const Vec3 upper = color(0.0, ym + 0.003), lower = color(0.0, ym - 0.005), cheek = color(0.045, -0.03), lip_skin = color(0.0, -0.055);
  MESSAGE("g/r: upper lip " << upper.y() / upper.x() << ", lower " << lower.y() / lower.x() << ", cheek " << cheek.y() / cheek.x());
  CHECK(upper.y() / upper.x() < 0.36);
  CHECK(lower.y() / lower.x() < 0.36);
  CHECK(cheek.y() / cheek.x() > 0.48);
  CHECK(lip_skin.y() / lip_skin.x() > 0.48);
  // The nostril's middle under 0.3 of the skin's brightness beside the wing (at 0.34 it read as a smudge).
  CHECK(color(head::kNostril[0], head::kNostril[1]).sum() < 0.3 * color(0.03, -0.04).sum());
  // The philtrum: its ridges stand a millimetre proud of the groove between them.
  const Vec3 d_groove = Vec3(0, -0.056, 0.09).normalized(), d_ridge = Vec3(0.0045, -0.056, 0.09).normalized();
  auto relief = [&](const Vec3& d) { return head::features(head::baseRadius(d, look) * d, d, ym, look).soft; };
  CHECK(relief(d_ridge) - relief(d_groove) > 0.001);
}
TEST_CASE("face: wrinkles fold in as their muscles pull: the forehead in surprise, between the brows in anger, crow's feet in a smile, the nose in disgust") {
  // The deepest fold of the skin drawn in a region of the head's rest frame (x, y in m, at 0.24 m).
  struct Region {
    const char* name;
    double x0, x1, y0, y1;
  };
  const Region forehead{"forehead", -0.04, 0.04, 0.035, 0.065}, glabella{"glabella", -0.008, 0.008, 0.008, 0.03},
      crows{"crow's feet", 0.05, 0.065, -0.01, 0.012}, nose{"nose's side", 0.004, 0.014, -0.016, 0.0},
      nose_right{"nose's right side", -0.014, -0.004, -0.016, 0.0};
  auto deepest = [](const std::string& preset, const Region& r) {
    World w = worldFromText(test::faceSceneText(R"(, "activations": [{"time": 0, "preset": ")" + preset +
                                                    R"(", "amount": 0}, {"time": 0.4, "preset": ")" + preset + R"("}])",
                                                0.6, "[48, 32]", "1e-3"));
    run(w, 18);
    const FaceBody& f = *w.first<FaceBody>();
    std::vector<double> lost;
    const auto mesh = f.skinMesh(nullptr, &lost);
    const std::vector<double> depth = f.wrinkleDepth(lost);
    double most = 0;
    for (std::size_t k = 0; k < mesh->vertexCount(); ++k) {
      const Vec3 p = f.rotation().transpose() * Vec3(mesh->positions[3 * k], mesh->positions[3 * k + 1], mesh->positions[3 * k + 2]);
      if (p.z() > 0.03 && p.x() > r.x0 && p.x() < r.x1 && p.y() > r.y0 && p.y() < r.y1) most = std::max(most, depth[k]);
    }
    MESSAGE(preset << ": the " << std::string(r.name) << "'s deepest fold " << most);
    return most;
  };
  CHECK(deepest("surprise", forehead) > 0.7);
  CHECK(deepest("anger", glabella) > 0.7);
  CHECK(deepest("happiness", crows) > 0.7);
  CHECK(deepest("disgust", nose) > 0.7);
  CHECK(deepest("disgust", nose_right) > 0.7);
  // None where no muscle pulls and the skin has not shrunk: the forehead in a smile, between the
  // brows in surprise.
  CHECK(deepest("happiness", forehead) < 0.05);
  CHECK(deepest("surprise", glabella) < 0.1);
  CHECK(deepest("surprise", nose) < 0.1);
}

TEST_CASE("face: the nose's wrinkle lines: three to five down each side of its upper half, each its own depth, the same on both sides") {
  // Down a line on the nose's side (x = 8 mm, at 0.24 m, on its front) the lines' map peaks about
  // every 3.4 mm: count the peaks above a fifth, note each one's height, and compare with the
  // mirrored side. (Six alike, evenly spaced, read as a ladder, a texture's glitch.)
  std::vector<double> heights;
  double top = 0.0;
  bool above = false;
  double asymmetry = 0.0;
  for (double y = -0.022; y <= 0.008; y += 0.0001) {
    const double v = head::wrinkleLines(Vec3(0.008, y, 0.1)).nose;
    asymmetry = std::max(asymmetry, std::abs(v - head::wrinkleLines(Vec3(-0.008, y, 0.1)).nose));
    if (v > 0.2) top = std::max(top, v);
    if (!(v > 0.2) && above) heights.push_back(top), top = 0.0;
    above = v > 0.2;
  }
  REQUIRE(!heights.empty());
  const double high = *std::max_element(heights.begin(), heights.end()), low = *std::min_element(heights.begin(), heights.end());
  MESSAGE(heights.size() << " lines down the nose's side, their depths " << low << " to " << high);
  CHECK(heights.size() >= 3);
  CHECK(heights.size() <= 5);
  CHECK(high > 1.2 * low);
  CHECK(asymmetry < 1e-12);
  // None off the nose: on the cheek, and on the midline's ridge.
  CHECK(head::wrinkleLines(Vec3(0.03, -0.01, 0.09)).nose == 0.0);
  CHECK(head::wrinkleLines(Vec3(0.0, -0.01, 0.1)).nose == 0.0);
}

TEST_CASE("face: an open mouth's rims run on curves through the simulated vertices, not along a polygon of its edges") {
  World w = worldFromText(faceSceneText(R"(, "activations": [{"time": 0, "muscles": {"jaw_open": 0}}, {"time": 0.3, "muscles": {"jaw_open": 1}}])",
                                        1.0, "[64, 40]", "1e-3"));
  run(w, 12);
  const FaceBody& f = face(w);
  DrawList list;
  f.draw(list);
  // The rims' pieces (their outer edges), each coarse edge's three in a row, found by colour.
  std::vector<std::array<Vec3, 2>> pieces;
  for (const DrawMesh& m : list.meshes) {
    if (!(m.material.color - FaceBody::kMouthInside).isZero(1e-9)) continue;
    const TriMesh& t = *m.mesh;
    auto at = [&](std::size_t v) { return Vec3(t.positions[3 * v], t.positions[3 * v + 1], t.positions[3 * v + 2]); };
    for (std::size_t v = 0; v + 3 < t.vertexCount(); ++v)
      if (std::abs(t.colors[3 * v] - float(FaceBody::kLipRim.x())) < 1e-6f && std::abs(t.colors[3 * v + 1] - float(FaceBody::kLipRim.y())) < 1e-6f) {
        pieces.push_back({at(v), at(v + 1)});
        v += 3;
      }
  }
  REQUIRE(pieces.size() >= 12);
  REQUIRE(pieces.size() % 3 == 0);
  // The largest turn, seen from the front (x, y), at the joints of a chain of segments, away from
  // the mouth's corners.
  const double half = 0.5 * f.surface().mouth_width;
  auto worstTurn = [&](const std::vector<std::array<Vec3, 2>>& segs) {
    std::map<std::array<float, 3>, std::vector<Vec3>> ends;  // joint → the segments' other ends
    auto key = [](const Vec3& p) { return std::array<float, 3>{float(p.x()), float(p.y()), float(p.z())}; };
    for (const auto& s : segs) ends[key(s[0])].push_back(s[1]), ends[key(s[1])].push_back(s[0]);
    double worst = 0;
    for (const auto& [k, other] : ends) {
      const Vec3 p(k[0], k[1], k[2]);
      if (other.size() != 2 || std::abs(p.x()) > 0.8 * half) continue;
      const Vec3 a = Vec3(p.x() - other[0].x(), p.y() - other[0].y(), 0).normalized();
      const Vec3 b = Vec3(other[1].x() - p.x(), other[1].y() - p.y(), 0).normalized();
      worst = std::max(worst, std::acos(std::clamp(a.dot(b), -1.0, 1.0)));
    }
    return worst * 180 / kPi;
  };
  std::vector<std::array<Vec3, 2>> straight;  // each coarse edge as one segment
  for (std::size_t k = 0; k < pieces.size(); k += 3) straight.push_back({pieces[k][0], pieces[k + 2][1]});
  const double curved = worstTurn(pieces), polygon = worstTurn(straight);
  MESSAGE("the rims' sharpest turn from the front: " << curved << " deg in pieces on curves, " << polygon << " deg along the simulated edges");
  CHECK(polygon > 3.0);
  CHECK(curved < 0.7 * polygon);
}

TEST_CASE("face: a far gaze eases toward 30 degrees: the iris is not jammed into the lids' corner") {
  // Targets 10°, 45° and 80° to the side of straight ahead (1 m away): the eyes turn 10°, then
  // 20° + 10° tanh((θ − 20°)/10°): about 29.9° and 30°, never the old hard stop's 35°.
  for (const double deg : {10.0, 45.0, 80.0}) {
    const double x = 0.032 + std::tan(deg * kPi / 180.0);
    World w = worldFromText(faceSceneText(R"(, "gaze": [{"time": 0, "target": [)" + std::to_string(x) + R"(, 0, 1]}])", 1.0, "[64, 40]", "1e-3"));
    run(w, 3);
    const FaceBody& f = face(w);
    const FaceBody::Eye ey = f.eye(0);
    const Vec3 forward = f.rotation() * Vec3::UnitZ();
    const double turned = std::acos(std::clamp(ey.ahead.dot(forward), -1.0, 1.0)) * 180.0 / kPi;
    // (The target's angle as the eye's centre sees it.)
    const double seen = std::acos(std::clamp((Vec3(x, 0, 1) - ey.center).normalized().dot(forward), -1.0, 1.0)) * 180.0 / kPi;
    const double expected = seen <= 20.0 ? seen : 20.0 + 10.0 * std::tanh((seen - 20.0) / 10.0);
    CAPTURE(deg);
    CAPTURE(turned);
    CHECK(turned == doctest::Approx(expected).epsilon(0.03));
    CHECK(turned < 30.01);
  }
}

TEST_CASE("face: the lids follow the gaze up and down, the upper over the iris's top") {
  // Looking ahead, then at targets 30° down, then 30° up (1 m away; the eyes turn about 27.6°).
  World w = worldFromText(faceSceneText(R"(, "gaze": [{"time": 0, "target": [0.032, 0, 1]}, {"time": 0.3, "target": [0.032, -0.577, 1]},
      {"time": 0.6, "target": [0.032, -0.577, 1]}, {"time": 0.9, "target": [0.032, 0.577, 1]}])", 1.0, "[64, 40]", "1e-3"));
  const FaceBody& f = face(w);
  auto state = [&] {
    const FaceBody::Eye ey = f.eye(0);
    const double gaze = std::asin(std::clamp(ey.ahead.dot(f.rotation() * Vec3::UnitY()), -1.0, 1.0));
    return std::array<double, 3>{gaze, ey.upperEdge(0.0), ey.lowerEdge(0.0)};
  };
  const auto ahead = state();
  run(w, 15);  // 0.5 s: looking down
  const auto down = state();
  run(w, 12);  // 0.9 s: looking up
  const auto up = state();
  MESSAGE("gaze " << ahead[0] << ", " << down[0] << ", " << up[0] << " rad: upper margin " << ahead[1] << ", " << down[1] << ", "
                  << up[1] << "; lower " << ahead[2] << ", " << down[2] << ", " << up[2]);
  REQUIRE(down[0] < -0.4);
  REQUIRE(up[0] > 0.4);
  // The upper margin keeps to the iris's top (20° above the gaze when ahead): within 12° of it
  // looking down or up (a lid that stays leaves white above the iris, or covers the pupil).
  for (const auto& st : {down, up}) CHECK(std::abs((st[1] - st[0]) - (ahead[1] - ahead[0])) < 0.21);
  CHECK(down[2] < ahead[2]);
  CHECK(up[2] > ahead[2]);
}

TEST_CASE("face: reel's head has hair strands rooted on the cap and nowhere else, lying along it") {
  World w = worldFromText(faceSceneText("", 1.0, "[64, 40]", "1e-3"));
  const FaceSurface& s = face(w).surface();
  REQUIRE(s.hair);
  const TriMesh& hair = *s.hair;
  const std::size_t strands = hair.vertexCount() / 12;  // six pairs of points along each
  MESSAGE(strands << " strands");
  CHECK(strands > 3000);
  int bare = 0, standing = 0, hanging = 0;
  double highest = 0;
  for (std::size_t v = 0; v < hair.vertexCount(); ++v) {
    const Vec3 p = Vec3(hair.positions[3 * v], hair.positions[3 * v + 1], hair.positions[3 * v + 2]) / s.scale;
    const Vec3 d = p.normalized();
    // Each strand's root pair (its first two points) where the hair covers the skin.
    if (v % 12 < 2 && head::hairCover(p, d, 0.004) < 0.01) ++bare;
    // How far off the cap (the skin with the hair's thickness, along the same ray from the
    // head's centre): the strands lie along it, bending round it, their tips about a millimetre
    // off its surface, up to 11.7 mm as this measures on the coarse test mesh's sides (the ray is
    // not the cap's normal there, and a 22 mm strand spans a bend of the cap and its thinning
    // toward the temples); a full-length strand standing up would reach 12-22 mm.
    const Vec3 base = head::baseRadius(d, s.look) * d;
    const double off = p.norm() - head::skinPoint(base, d, s.parting_y, s.look).norm();
    highest = std::max(highest, off);
    if (off > 0.012) ++standing;
    // A tip (a strand's last pair) past the hairline lies on the skin: none hangs off it in the
    // air (long strands combed forward over the temples hung 10 mm out over the skin).
    if (v % 12 >= 10 && head::hairCover(p, d, 0.004) < 0.5 && off > 0.003) ++hanging;
  }
  MESSAGE(bare << " roots on bare skin, " << standing << " points over 12 mm off the cap (the highest " << highest * 1e3 << " mm)");
  MESSAGE(hanging << " tips past the hairline");
  CHECK(bare == 0);
  CHECK(standing == 0);
  CHECK(hanging == 0);
}

TEST_CASE("face: the brows' hairs root on the skin drawn, lie along it, and rise with it as the frontalis lifts the brows") {
  World w = worldFromText(test::faceSceneText(R"(, "activations": [{"time": 0, "preset": "surprise", "amount": 0}, {"time": 0.2, "preset": "surprise", "amount": 0}, {"time": 0.5, "preset": "surprise"}])",
                                              0.7, "[48, 32]", "1e-3"));
  const FaceBody& f = *w.first<FaceBody>();
  // The brows' hairs: the strands' mesh past the hair's own (four pairs a strand), three pairs
  // each: their roots' head-frame points, and how far each root lies from the skin drawn.
  struct Seen {
    std::size_t hairs = 0;
    // m: the roots' mean height, the farthest from its nearest point of the skin drawn and the
    // highest off that point's tangent plane; the largest share of a hair's length off that plane
    double mean_y = 0, farthest = 0, above = 0, steepest = 0;
  };
  auto look = [&] {
    DrawList list;
    f.draw(list);
    const std::size_t own = f.surface().hair->vertexCount();
    const auto skin = f.skinMesh();
    Seen s;
    for (const DrawMesh& m : list.meshes) {
      if (m.mesh->vertexCount() <= own || !m.material.double_sided || m.mesh->vertexCount() - own < 6) continue;
      const TriMesh& t = *m.mesh;
      auto at = [&](const std::vector<float>& a, std::size_t v) { return Vec3(a[3 * v], a[3 * v + 1], a[3 * v + 2]); };
      for (std::size_t v = own; v + 5 < t.vertexCount(); v += 6, ++s.hairs) {
        const Vec3 root = 0.5 * (at(t.positions, v) + at(t.positions, v + 1)), tip = 0.5 * (at(t.positions, v + 4) + at(t.positions, v + 5));
        double near = 1e9;
        std::size_t k = 0;
        for (std::size_t q = 0; q < skin->vertexCount(); ++q)
          if ((at(skin->positions, q) - root).norm() < near) near = (at(skin->positions, q) - root).norm(), k = q;
        const Vec3 n = at(skin->normals, k).normalized();
        s.farthest = std::max(s.farthest, near);
        s.above = std::max(s.above, std::abs((root - at(skin->positions, k)).dot(n)));
        s.steepest = std::max(s.steepest, std::abs((tip - root).normalized().dot(n)));
        s.mean_y += (f.rotation().transpose() * root).y();
      }
    }
    s.mean_y /= std::max<double>(1.0, static_cast<double>(s.hairs));
    return s;
  };
  run(w, 3);
  const Seen rest = look();
  run(w, 15);  // 0.6 s: surprise held
  const Seen raised = look();
  MESSAGE(rest.hairs << " hairs; roots within " << rest.farthest * 1e3 << " mm of a point of the skin drawn and " << rest.above * 1e3
                     << " mm off its plane, tips off it by at most "
                     << rest.steepest << " of their length; the brows' mean height " << rest.mean_y * 1e3 << " -> " << raised.mean_y * 1e3 << " mm");
  CHECK(rest.hairs > 200);  // (321 on this coarse head)
  CHECK(raised.hairs == rest.hairs);
  CHECK(rest.farthest < 0.0015);  // (each root within 1 mm of its point, on points 1.4 mm apart)
  CHECK(rest.above < 0.0002);     // on the skin (0.05 mm off it), not floating
  CHECK(rest.steepest < 0.3);     // lying along the skin (their tips lifted a quarter of their length at most)
  CHECK(raised.mean_y > rest.mean_y + 0.002);
}

TEST_CASE("face: the lips' rims are dim in a slit and lit in full when the mouth opens") {
  // In lips not quite closed the rims, lit in full, showed as a dotted line of bright flecks
  // (addLipRims): their colour goes from a quarter of kLipRim at 1 mm open to all of it at 6 mm.
  auto rimRed = [](const std::string& keys, int frames) {
    World w = worldFromText(faceSceneText(keys, 1.0, "[48, 32]", "1e-3"));
    run(w, frames);
    const FaceBody& f = face(w);
    DrawList list;
    f.draw(list);
    float red = -1.0f;
    for (const DrawMesh& m : list.meshes) {
      if (!(m.material.color - FaceBody::kMouthInside).isZero(1e-9)) continue;
      // The rims' quads follow the lining's vertices (one per skin vertex): outer two, inner two.
      for (std::size_t v = f.surface().size(); v + 3 < m.mesh->vertexCount(); v += 4) red = std::max(red, m.mesh->colors[3 * v]);
    }
    return std::pair{red, f.mouthOpening()};
  };
  const auto [closed, closed_gap] = rimRed("", 3);
  const auto [open, open_gap] = rimRed(R"(, "activations": [{"time": 0, "muscles": {"jaw_open": 0}}, {"time": 0.3, "muscles": {"jaw_open": 1}}])", 12);
  MESSAGE("rims' red " << closed << " at " << closed_gap * 1e3 << " mm open, " << open << " at " << open_gap * 1e3 << " mm");
  CHECK(closed_gap < 0.001);
  CHECK(open_gap > 0.006);
  CHECK(closed == doctest::Approx(0.25 * FaceBody::kLipRim.x()).epsilon(1e-4));
  CHECK(open == doctest::Approx(FaceBody::kLipRim.x()).epsilon(1e-4));
}
