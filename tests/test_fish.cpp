// The artificial fish: the body's structure, internal forces (no water: the centre of mass stays),
// swimming (forward, faster with the beat), turning, perception (occlusion, the blind angle),
// behaviour (eating, fleeing, schooling, the hook), water currents, determinism, bad input.
#include <doctest/doctest.h>

#include <cmath>
#include <set>

#include "core/parallel.h"
#include "helpers.h"
#include "sim/fish/fish_body.h"
#include "sim/fish/food.h"
#include "sim/fish/seaweed.h"
#include "sim/school/school.h"
#include "sim/water.h"
#include "sim/world.h"

using namespace reel;
using namespace reel::test;

namespace {

const FishBody& fishOf(const World& w, const std::string& name) {
  for (const auto& b : w.bodies())
    if (b->name() == name) return dynamic_cast<const FishBody&>(*b);
  FAIL("no fish body " << name);
  throw 0;
}

Vec3 centerOfMass(const FishBody& f, std::size_t i = 0) {
  const auto& net = f.network();
  Vec3 c{0, 0, 0};
  double m = 0;
  for (std::size_t k = kFishNodes * i; k < kFishNodes * (i + 1); ++k) c += net.model.mass[k] * net.state.x[k], m += net.model.mass[k];
  return c / m;
}

// One driven fish of 0.5 m heading +z, in water unless `density` is 0.
std::string driven(const std::string& drive, double duration, double density = 1000, const std::string& integrator = "implicit_euler",
                   int substeps = 10) {
  return R"({"format": "reel/1", "fps": 30, "substeps": )" + std::to_string(substeps) + R"(, "duration": )" +
         std::to_string(duration) + R"(, "integrator": ")" + integrator +
         R"(", "implicit": {"cg_tolerance": 1e-13}, "water": {"density": )" +
         std::to_string(density) + R"(}, "bodies": [{"type": "fish", "name": "f", "behaviour": "none", "length": 0.5, "drive": )" +
         drive + "}]}";
}

// The heading of a fish's path: where its centre of mass went over the last `window` frames.
double pathAngle(World& w, const FishBody& f, int window) {
  const Vec3 a = centerOfMass(f);
  run(w, window);
  const Vec3 d = centerOfMass(f) - a;
  return std::atan2(d.x(), d.z());
}

}  // namespace

TEST_CASE("the fish body: 23 nodes, 91 units, 12 distinct lengthwise muscles, a closed outward surface") {
  const FishTemplate t = makeFishTemplate(0.5, 1000);
  CHECK(t.springs.size() == 91);
  CHECK(t.x.size() == 23);
  std::set<int> muscles(t.muscle.begin(), t.muscle.end());
  CHECK(muscles.size() == 12);
  for (int k = 0; k < kFishMuscles; ++k) {
    const auto s = static_cast<std::size_t>(t.muscle[static_cast<std::size_t>(k)]);
    const Vec3 d = t.x[static_cast<std::size_t>(t.springs.b[s])] - t.x[static_cast<std::size_t>(t.springs.a[s])];
    CHECK(std::abs(d.normalized().z()) > 0.95);  // lengthwise
    // Left muscles (side 0) on the +x flank.
    const double side = t.x[static_cast<std::size_t>(t.springs.a[s])].x();
    CHECK((k / 2) % 2 == (side > 0 ? 0 : 1));
  }
  // Closed: the area vectors sum to zero; outward: the enclosed volume (divergence theorem) is positive.
  Vec3 area{0, 0, 0};
  double volume = 0;
  for (const auto& tri : t.surface) {
    const Vec3 &a = t.x[static_cast<std::size_t>(tri[0])], &b = t.x[static_cast<std::size_t>(tri[1])], &c = t.x[static_cast<std::size_t>(tri[2])];
    area += 0.5 * (b - a).cross(c - a);
    volume += a.dot(b.cross(c)) / 6;
  }
  CHECK(area.norm() < 1e-12);
  CHECK(volume > 0);
  double mass = 0;
  for (double m : t.mass) mass += m;
  CHECK(mass == doctest::Approx(1000 * volume).epsilon(0.5));  // about neutrally buoyant
}

TEST_CASE("without water the muscles are internal forces: the centre of mass stays, under any pattern") {
  const std::string drive = R"({"swim": {"frequency": 3, "amplitude": 1}, "turn": {"side": "right", "start": 0.2, "stop": 0.7},
      "muscles": [{"muscle": "front_left", "contraction": 0.8, "frequency": 3.3, "phase_deg": 40},
                  {"muscle": "rear_right_lower", "contraction": 0.5, "frequency": 1.7},
                  {"muscle": "middle_left_upper", "contraction": 1, "start": 0.3, "stop": 0.6}]})";
  for (const char* integrator : {"symplectic_euler", "implicit_euler"}) {
    CAPTURE(integrator);
    World w = worldFromText(driven(drive, 1, 0, integrator, std::string(integrator) == "implicit_euler" ? 10 : 600));
    const FishBody& f = fishOf(w, "f");
    const Vec3 c0 = centerOfMass(f);
    double bend = 0;
    for (int k = 0; k < 30; ++k) {
      run(w, 1);
      CHECK((centerOfMass(f) - c0).norm() < 1e-9);
      bend = std::max(bend, std::abs(f.network().state.x[21].x()));
    }
    CHECK(bend > 0.01);  // and the body did move: the tail swung
  }
}

TEST_CASE("in water a swim cycle moves the fish forward, faster with a faster beat") {
  std::vector<double> dist;
  for (double hz : {1.0, 2.0, 3.0}) {
    World w = worldFromText(driven(R"({"swim": {"frequency": )" + std::to_string(hz) + R"(, "amplitude": 1}})", 3));
    const FishBody& f = fishOf(w, "f");
    const Vec3 c0 = centerOfMass(f);
    run(w, 90);
    const Vec3 d = centerOfMass(f) - c0;
    CAPTURE(hz);
    CHECK(d.z() > 0.1);                   // forward (+z), at least a fifth of a length
    CHECK(std::abs(d.x()) < 0.3 * d.z());  // and roughly straight
    dist.push_back(d.z());
  }
  CHECK(dist[1] > 1.3 * dist[0]);
  CHECK(dist[2] > 1.2 * dist[1]);
}

// How far a driven fish of `length` swims: its centre of mass from `from` to `to` seconds.
double swum(double length, double hz, int substeps, const std::string& integrator, double from, double to) {
  const std::string text = R"({"format": "reel/1", "fps": 30, "substeps": )" + std::to_string(substeps) + R"(, "duration": )" +
                           std::to_string(to + 0.1) + R"(, "integrator": ")" + integrator +
                           R"(", "water": {"density": 1000}, "bodies": [{"type": "fish", "name": "f", "behaviour": "none", "length": )" +
                           std::to_string(length) + R"(, "drive": {"swim": {"frequency": )" + std::to_string(hz) + R"(, "amplitude": 1}}}]})";
  World w = worldFromText(text);
  const FishBody& f = fishOf(w, "f");
  run(w, static_cast<int>(std::lround(from * 30)));
  const Vec3 a = centerOfMass(f);
  run(w, static_cast<int>(std::lround((to - from) * 30)));
  return (centerOfMass(f) - a).norm();
}

TEST_CASE("a fish swims as far at any step and with any integrator (within 5% over 5 s)") {
  // The 1 m fish at 2 beats a second. Before the springs' force was taken at the predicted
  // positions it swam 2.3 m at 6 substeps and 3.3 m at 20.
  const double ref = swum(1.0, 2.0, 800, "symplectic_euler", 0, 5);
  CAPTURE(ref);
  CHECK(ref > 5.0);
  for (const char* integrator : {"implicit_euler", "bdf2"})
    for (int substeps : {6, 10, 20}) {
      CAPTURE(integrator);
      CAPTURE(substeps);
      CHECK(swum(1.0, 2.0, substeps, integrator, 0, 5) == doctest::Approx(ref).epsilon(0.05));
    }
}

TEST_CASE("a fish's steady stride is 0.6-0.8 of its length a beat, as real fish keep (Videler 1993)") {
  // From 2 s (speed reached) to 5 s, fish of 0.3 and 1 m from 1 to 4 beats a second.
  for (double length : {0.3, 1.0})
    for (double hz = 1.0; hz <= 4.0; hz += 1.0) {
      CAPTURE(length);
      CAPTURE(hz);
      const double stride = swum(length, hz, 10, "implicit_euler", 2, 5) / (length * hz * 3.0);
      CHECK(stride > 0.6);
      CHECK(stride < 0.8);
    }
}

TEST_CASE("the turn command turns the fish toward the side asked") {
  for (const char* side : {"left", "right"}) {
    CAPTURE(side);
    World w = worldFromText(driven(std::string(R"({"swim": {"frequency": 2.5, "amplitude": 1}, "turn": {"side": ")") + side +
                                       R"(", "start": 1, "stop": 2.5}})",
                                   4));
    const FishBody& f = fishOf(w, "f");
    const double before = pathAngle(w, f, 30);
    run(w, 60);
    const double after = pathAngle(w, f, 30);
    const double turned = (after - before) * 180 / 3.14159265358979;
    CAPTURE(turned);
    // Left is +x for a fish heading +z: a left turn raises atan2(x, z).
    if (std::string(side) == "left") CHECK(turned > 20);
    else CHECK(turned < -20);
  }
}

TEST_CASE("the pectoral fins: pitched they raise or lower a swimming fish, one opened yaws it to its side") {
  // What fins set this way do in 5 s: the rise of the centre of mass (m) and the turn of the course (°, left +).
  auto swim = [](const std::string& fins) {
    World w = worldFromText(driven(R"({"swim": {"frequency": 2.5, "amplitude": 1}, )" + fins + "}", 6));
    const FishBody& f = fishOf(w, "f");
    const Vec3 c0 = centerOfMass(f);
    run(w, 138);
    // The course, from +z: where the centre of mass went over the last whole beat (0.4 s), so
    // the body's wiggle does not count.
    const double course = pathAngle(w, f, 12) * 180 / 3.14159265358979;
    return std::make_pair(Vec3(centerOfMass(f) - c0).y(), course);
  };
  CHECK(swim(R"("pitch_deg": 20)").first > 0.1);
  CHECK(swim(R"("pitch_deg": -20)").first < -0.1);
  const double straight = swim(R"("yaw_deg": 0)").second;
  const double left = swim(R"("yaw_deg": 60)").second, right = swim(R"("yaw_deg": -60)").second;
  CAPTURE(straight);
  CAPTURE(left);
  CAPTURE(right);
  // The left fin brakes: a left turn (about 11° a second, some 50° either way here; weak beside the body's bend).
  CHECK(left > straight + 3);
  CHECK(right < straight - 3);
}

TEST_CASE("asked to turn 90° a fish turns about that much, either way") {
  for (int side : {1, -1}) {
    CAPTURE(side);
    World w = worldFromText(driven(std::string(R"({"swim": {"frequency": 2.5, "amplitude": 1}, "turn": {"side": ")") +
                                       (side > 0 ? "left" : "right") + R"(", "start": 1, "angle_deg": 90}})",
                                   12));
    const FishBody& f = fishOf(w, "f");
    const double before = pathAngle(w, f, 30);
    run(w, 270);
    const double after = pathAngle(w, f, 30);
    double turned = (after - before) * 180 / 3.14159265358979;
    if (turned > 180) turned -= 360;
    if (turned < -180) turned += 360;
    CAPTURE(turned);
    CHECK(side * turned == doctest::Approx(90).epsilon(0.3));
    CHECK(f.motor(0).turn_done == 1);
  }
}

TEST_CASE("the swim controller reaches the speed the behaviour asks") {
  // A wandering fish in open water, nothing else: its speed settles near its cruise speed.
  World w = worldFromText(R"({"format": "reel/1", "fps": 30, "substeps": 10, "duration": 8, "integrator": "implicit_euler",
      "bodies": [{"type": "fish", "name": "f", "species": "pacifist", "length": 0.5, "cruise_speed": 0.6,
                  "mental": {"hunger": 0, "libido": 0}}]})");
  const FishBody& f = fishOf(w, "f");
  run(w, 150);
  const Vec3 a = centerOfMass(f);
  run(w, 60);
  const double speed = (centerOfMass(f) - a).norm() / 2.0;
  CHECK(speed == doctest::Approx(0.3).epsilon(0.3));  // 0.6 lengths a second of 0.5 m
}

TEST_CASE("perception: another fish is seen out to its reach from the mouth (twice the radius for one twice as long), wherever the grid's cells fall") {
  // The viewer (0.3 m, radius 2 m) at the origin heading +z. A fish's position is its centre of
  // mass; it looks from its mouth (the nose) and is seen at its rings' mean. In sight: one of its
  // size 1.95 m ahead of the mouth, one twice as long (reach 4 m) 3.95 m ahead and 1 m aside; out
  // of sight: one of its size 2.1 m away, ahead and aside. The scene is shifted along z in steps,
  // so that the perception grid's cells fall differently about the viewer each time.
  // Offsets from a fish's position (heading +z): its mouth, and the centre it is seen at.
  const FishTemplate small = makeFishTemplate(0.3, 1000.0), large = makeFishTemplate(0.6, 1000.0);
  auto seenCentre = [](const FishTemplate& t) {
    Vec3 rings = Vec3::Zero();
    for (int i = 1; i <= 20; ++i) rings += t.x[static_cast<std::size_t>(i)] / 20.0;
    return Vec3(rings - t.center_of_mass);
  };
  const Vec3 mouth = small.x[0] - small.center_of_mass, small_centre = seenCentre(small), big_centre = seenCentre(large);
  for (double shift = 0.0; shift < 4.0; shift += 0.45) {
    CAPTURE(shift);
    // The position that puts a fish's seen centre at `at` from the viewer's mouth.
    auto place = [&](const Vec3& at, const Vec3& centre) {
      const Vec3 p = mouth + at - centre + Vec3(0, 0, shift);
      return "[" + std::to_string(p.x()) + ", " + std::to_string(p.y()) + ", " + std::to_string(p.z()) + "]";
    };
    const double aside = std::sqrt(2.1 * 2.1 - 1.2 * 1.2), big = std::sqrt(3.95 * 3.95 - 1.0);
    World w = worldFromText(R"({"format": "reel/1", "fps": 30, "substeps": 4, "duration": 1, "integrator": "implicit_euler", "bodies": [
        {"type": "fish", "name": "viewer", "species": "pacifist", "length": 0.3, "position": )" + place(-mouth, Vec3::Zero()) +
                            R"(, "heading": [0, 0, 1], "perception": {"vision_radius": 2}, "mental": {"hunger": 0, "libido": 0}},
        {"type": "fish", "name": "near", "species": "pacifist", "length": 0.3, "behaviour": "none", "position": )" +
                            place(Vec3(0, 0, 1.95), small_centre) + R"(, "heading": [0, 0, 1]},
        {"type": "fish", "name": "far", "species": "pacifist", "length": 0.3, "behaviour": "none", "position": )" +
                            place(Vec3(1.2, 0, aside), small_centre) + R"(, "heading": [0, 0, 1]},
        {"type": "fish", "name": "big", "species": "pacifist", "length": 0.6, "behaviour": "none", "position": )" +
                            place(Vec3(1.0, 0, big), big_centre) + R"(, "heading": [0, 0, 1]}]})");
    run(w, 4);
    bool seen[4] = {false, false, false, false};
    for (const Seen& s : fishOf(w, "viewer").percept(0).seen)
      if (s.kind == Seen::Kind::Fish) {
        CAPTURE(s.body);
        CAPTURE(s.distance);
        seen[s.body] = true;
        CHECK(s.distance < (s.body == 3 ? 4.0 : 2.0));
      }
    CHECK(seen[1]);
    CHECK(!seen[2]);
    CHECK(seen[3]);
  }
}

TEST_CASE("perception: a fish behind an object or in the blind angle is not seen") {
  auto scene = [](bool wall) {
    return std::string(R"({"format": "reel/1", "fps": 30, "substeps": 4, "duration": 1, "integrator": "implicit_euler",
      "objects": [)") + (wall ? R"({"type": "box", "center": [1.5, 0, 0], "size": [0.3, 2, 2]})" : "") +
           R"(], "bodies": [
        {"type": "fish", "name": "viewer", "species": "pacifist", "position": [0, 0, 0], "heading": [0, 0, 1], "mental": {"hunger": 0, "libido": 0}},
        {"type": "fish", "name": "ahead", "behaviour": "none", "position": [0, 0, 3]},
        {"type": "fish", "name": "behind", "behaviour": "none", "position": [0, 0, -3]},
        {"type": "fish", "name": "aside", "behaviour": "none", "position": [3, 0, 0]}]})";
  };
  auto seen = [](const World& w, int body) {
    for (const Seen& s : fishOf(w, "viewer").percept(0).seen)
      if (s.kind == Seen::Kind::Fish && s.body == body) return true;
    return false;
  };
  World open = worldFromText(scene(false));
  run(open, 4);
  CHECK(seen(open, 1));
  CHECK(!seen(open, 2));  // straight behind: in the 60° blind cone
  CHECK(seen(open, 3));   // to the side: within 300°
  World walled = worldFromText(scene(true));
  run(walled, 4);
  CHECK(seen(walled, 1));
  CHECK(!seen(walled, 3));  // the box stands between
}

TEST_CASE("behaviour: a hungry fish with food in view eats it") {
  World w = worldFromText(R"({"format": "reel/1", "fps": 30, "substeps": 6, "duration": 12, "integrator": "implicit_euler",
      "bodies": [{"type": "fish", "name": "f", "species": "pacifist", "position": [0, 0, 0], "heading": [0, 0, 1],
                  "mental": {"hunger": 0.9, "libido": 0}, "digestion": 0},
                 {"type": "food", "name": "plankton", "region": {"min": [-0.3, -0.2, 0.8], "max": [0.3, 0.2, 1.6]},
                  "initial": 8, "rate": 0, "sink_speed": 0, "jitter": 0}]})");
  const FishBody& f = fishOf(w, "f");
  const auto* food = w.first<FoodBody>();
  const double hunger0 = f.mind(0).hunger;
  run(w, 300);
  CHECK(food->particles().size() < 8);
  CHECK(f.mind(0).hunger < hunger0);
}

TEST_CASE("behaviour: a fish that sees a predator flees, and prey of one body school") {
  World w = worldFromText(R"({"format": "reel/1", "fps": 30, "substeps": 10, "duration": 10, "integrator": "implicit_euler", "seed": 3,
      "bodies": [{"type": "fish", "name": "shark", "species": "predator", "behaviour": "none", "position": [0, 0, -1.5], "heading": [0, 0, 1]},
                 {"type": "fish", "name": "prey", "species": "prey", "position": [0, 0, 0], "heading": [1, 0, 0], "mental": {"hunger": 0}}]})");
  const FishBody& prey = fishOf(w, "prey");
  const FishBody& shark = fishOf(w, "shark");
  const double d0 = (centerOfMass(prey) - centerOfMass(shark)).norm();
  run(w, 15);
  CHECK(prey.mind(0).fear > 0.2);
  CHECK(prey.mind(0).intention == static_cast<int>(Intention::Escape));
  run(w, 135);
  CHECK((centerOfMass(prey) - centerOfMass(shark)).norm() > d0 + 0.5);

  // Twelve prey with random headings line up.
  World s = worldFromText(R"({"format": "reel/1", "fps": 30, "substeps": 6, "duration": 20, "integrator": "implicit_euler", "seed": 5,
      "bodies": [{"type": "fish", "name": "prey", "count": 12, "start": {"center": [0, 0, 0], "radius": 1}, "mental": {"hunger": 0}}]})");
  const FishBody& school = fishOf(s, "prey");
  auto polarization = [&] {
    std::vector<Vec3> x, v;
    for (std::size_t i = 0; i < school.count(); ++i) {
      const auto& h = school.motor(i).heading;  // the course, without the swim's wiggle
      x.push_back(school.frame(i).center), v.push_back(Vec3(h[0], h[1], h[2]));
    }
    return schoolOrder(x, v).polarization;
  };
  const double p0 = polarization();
  run(s, 420);
  // At the end, each fish's course over its last second (the motor's heading still carries
  // some of a slow beat's wiggle).
  std::vector<Vec3> x0, x, v;
  for (std::size_t i = 0; i < school.count(); ++i) x0.push_back(school.frame(i).center);
  run(s, 30);
  for (std::size_t i = 0; i < school.count(); ++i) x.push_back(school.frame(i).center), v.push_back(school.frame(i).center - x0[i]);
  int schooling = 0;
  for (std::size_t i = 0; i < school.count(); ++i) schooling += school.mind(i).intention == static_cast<int>(Intention::School);
  CHECK(schooling >= 8);
  CHECK(schoolOrder(x, v).polarization > std::max(0.6, p0 + 0.2));
}

TEST_CASE("a hungry fish bites the hook and is caught: it hangs from the line as the hook rises") {
  World w = worldFromText(R"({"format": "reel/1", "fps": 30, "substeps": 6, "duration": 8, "integrator": "implicit_euler",
      "objects": [{"type": "sphere", "name": "hook", "center": [0, 0, 1.2], "radius": 0.02,
                   "motion": {"keys": [{"time": 0, "position": [0, 0, 1.2]}, {"time": 5, "position": [0, 0, 1.2]}, {"time": 8, "position": [0, 2, 1.2]}]}}],
      "bodies": [{"type": "fish", "name": "f", "species": "pacifist", "position": [0, 0, 0], "heading": [0, 0, 1],
                  "mental": {"hunger": 0.9, "libido": 0}, "hook": "hook"}]})");
  const FishBody& f = fishOf(w, "f");
  run(w, 150);
  REQUIRE(f.caught(0));
  run(w, 90);
  CHECK(f.network().state.x[0].y() > 1.5);  // the mouth went up with the hook
}

TEST_CASE("water currents: uniform with its variation, and a source's flow through any sphere equals its rate") {
  WaterDesc d;
  CurrentDesc u;
  u.velocity = Vec3(1, 0, 0), u.amplitude = Vec3(0, 0.5, 0), u.period = 4;
  d.currents.push_back(u);
  Water w(d);
  std::vector<Collider> none;
  CHECK((w.at(Vec3(3, 2, 1), 1.0, none) - Vec3(1, 0.5, 0)).norm() < 1e-12);
  WaterDesc s;
  CurrentDesc src;
  src.kind = CurrentDesc::Kind::Source, src.collider = 0, src.rate = 2.0, src.core = 0.1;
  s.currents.push_back(src);
  Water ws(s);
  ObjectDesc o;
  o.shape = SphereShape{Vec3(1, 1, 1), 0.05};
  std::vector<Collider> cs = {makeCollider(o)};
  // Flux through a sphere of radius 0.7 around the source: 4π r² u_r = rate.
  const Vec3 p = Vec3(1, 1, 1) + 0.7 * Vec3(0.6, 0, 0.8);
  CHECK(4 * 3.14159265358979 * 0.49 * ws.at(p, 0, cs).norm() == doctest::Approx(2.0).epsilon(1e-9));
  CHECK(ws.at(p, 0, cs).dot(Vec3(0.6, 0, 0.8)) > 0);  // outward
}

TEST_CASE("seaweed sways with the current and food drifts with it") {
  World w = worldFromText(R"({"format": "reel/1", "fps": 30, "substeps": 20, "duration": 4,
      "water": {"currents": [{"type": "uniform", "velocity": [0.4, 0, 0]}]},
      "bodies": [{"type": "seaweed", "name": "kelp", "bases": [[0, 0, 0]], "height": 1, "segments": 8},
                 {"type": "food", "name": "p", "region": {"min": [0, 1, 0], "max": [0.01, 1.01, 0.01]}, "initial": 1, "rate": 0,
                  "sink_speed": 0, "jitter": 0}]})");
  run(w, 90);
  const auto& kelp = dynamic_cast<const SeaweedBody&>(*w.bodies()[0]);
  World many = worldFromText(R"({"format": "reel/1", "duration": 1, "bodies": [{"type": "seaweed", "name": "k", "count": 7,
      "region": {"min": [0, 0, 0], "max": [3, 0, 3]}, "segments": 4}]})");
  CHECK(dynamic_cast<const SeaweedBody&>(*many.bodies()[0]).strands() == 7);
  const Vec3 tip = kelp.network().state.x.back();
  CHECK(tip.x() > 0.2);   // leaning downstream
  CHECK(tip.y() > 0.3);   // but still standing (buoyant)
  CHECK(w.first<FoodBody>()->particles()[0].x() == doctest::Approx(1.2).epsilon(0.02));  // 0.4 m/s for 3 s
}

TEST_CASE("fish are bit-identical for 1 and 2 threads") {
  const std::string text = R"({"format": "reel/1", "fps": 30, "substeps": 4, "duration": 1, "integrator": "implicit_euler", "seed": 2,
      "objects": [{"type": "sphere", "center": [0, 0, 3], "radius": 0.6}],
      "bodies": [{"type": "fish", "name": "shark", "species": "predator", "position": [0, 0, -3]},
                 {"type": "fish", "name": "prey", "count": 40, "start": {"center": [0, 0, 0], "radius": 2}},
                 {"type": "food", "name": "p", "region": {"min": [-1, -1, -1], "max": [1, 1, 1]}}]})";
  CHECK(runHash(text, 1, 20) == runHash(text, 2, 20));
}

TEST_CASE("bad fish scenes: a clear error with the JSON path") {
  auto error = [](const std::string& body) { return badInputError(R"({"format": "reel/1", "duration": 1, "bodies": [)" + body + "]}"); };
  auto has = checkHas;
  has(error(R"({"type": "fish", "name": "f", "length": 0})"), "/bodies/0/length");
  has(error(R"({"type": "fish", "name": "f", "length": -1})"), "/bodies/0/length");
  has(error(R"({"type": "fish", "name": "f", "behaviour": "none", "drive": {"muscles": [{"muscle": "tail_left", "contraction": 1}]}})"),
      "/bodies/0/drive/muscles/0/muscle");
  has(error(R"({"type": "fish", "name": "f", "mental": {"hunger": 1.5}})"), "/bodies/0/mental/hunger");
  has(error(R"({"type": "fish", "name": "f", "mental": {"fear": -0.1}})"), "/bodies/0/mental/fear");
  has(error(R"({"type": "fish", "name": "f", "species": "shark"})"), "/bodies/0/species");
  has(error(R"({"type": "fish", "name": "f", "hook": "nowhere"})"), "/bodies/0/hook");
  has(error(R"({"type": "fish", "name": "f", "drive": {"swim": {"frequency": 2}}})"), "/bodies/0/drive");
  has(error(R"({"type": "food", "name": "p"})"), "/bodies/0/region");
  has(error(R"({"type": "food", "name": "p", "region": {"min": [0, 0, 0], "max": [0, 1, 1]}})"), "/bodies/0/region/max");
  has(error(R"({"type": "seaweed", "name": "k", "count": 0})"), "/bodies/0/count");
  auto r = app::parseScene(R"({"format": "reel/1", "duration": 1, "water": {"density": -1, "currents": [{"type": "sink", "object": "x", "rate": 1}]}})", "s.json");
  REQUIRE(!r.ok());
  has(r.error().messages.front(), "/water/density");
  has(r.error().messages.back(), "/water/currents/0/object");
}
