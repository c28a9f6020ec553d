// Scene loading and every bad-input row of DESIGN 9 that applies to scenes.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>

#include "helpers.h"
#include "io/png.h"
#include "sim/world.h"

using namespace reel;
using namespace reel::test;

namespace {

// Errors of a scene text, one line each ("" when it loads).
std::vector<std::string> errorsOf(const std::string& text, const std::string& file = "s.json") {
  auto r = app::parseScene(text, file);
  if (r.ok()) return {};
  CHECK(r.error().kind == ErrorKind::BadInput);
  return r.error().messages;
}

bool contains(const std::vector<std::string>& lines, const std::string& part) {
  for (const auto& l : lines)
    if (l.find(part) != std::string::npos) return true;
  return false;
}

const char* kHead = R"("format": "reel/1", "duration": 1, )";

std::string scene(const std::string& rest) { return std::string("{") + kHead + rest + "}"; }

std::string springBody(const std::string& node1, const std::string& spring) {
  return scene(R"("bodies": [{"type": "mass_spring", "name": "b", "nodes": [
      {"position": [0,0,0], "mass": 1, "fixed": true}, )" + node1 + R"(],
      "springs": [)" + spring + "]}]");
}

}  // namespace

TEST_CASE("every shipped scene loads, validates and builds a world") {
  for (const auto& e : std::filesystem::directory_iterator(REEL_SOURCE_DIR "/scenes")) {
    if (e.path().extension() != ".json") continue;  // scenes/meshes/: the assets they import
    CAPTURE(e.path().string());
    auto s = app::loadScene(e.path().string());
    REQUIRE_MESSAGE(s.ok(), (s.ok() ? "" : s.error().headline()));
    CHECK(app::makeWorld(s.value()).ok());
  }
}

TEST_CASE("defaults and values are read as documented") {
  const SceneDesc s = sceneFromText(R"(
    // comments are allowed
    { "format": "reel/1", "duration": 2.0, /* block comments too */
      "bodies": [ { "type": "rope", "start": [0,0,0], "end": [1,0,0], "stiffness": 50,
                    "pinned": ["start", -1] } ] })",
                                    "dir/chain.json");
  CHECK(s.name == "chain");  // from the file name
  CHECK(s.fps == 30);
  CHECK(s.substeps == 10);
  CHECK(s.frameCount() == 60);
  CHECK(s.gravity == Vec3(0, -9.78, 0));
  CHECK(s.integrator == IntegratorKind::SymplecticEuler);
  REQUIRE(s.bodies.size() == 1);
  CHECK(s.bodies[0].name == "rope_0");
  const auto& r = s.bodies[0].as<RopeDesc>();
  CHECK(r.segments == 10);
  CHECK(r.pinned == std::vector<int>{0, 10});
  CHECK(r.spring.damping == 0.0);
}

TEST_CASE("malformed JSON: file:line:col and what was expected") {
  const auto e = errorsOf("{\n  \"format\": \"reel/1\",\n  \"duration\": 1,,\n}", "bad.json");
  REQUIRE(e.size() == 1);
  CHECK(e[0].rfind("bad.json:3:17:", 0) == 0);
  CHECK(e[0].find("expected") != std::string::npos);
  CHECK(errorsOf("[1, 2", "t.json")[0].rfind("t.json:1:", 0) == 0);
  CHECK(contains(errorsOf("[1, 2]"), "expected an object"));
}

TEST_CASE("unknown keys and values name the path and the nearest valid key") {
  auto e = errorsOf(scene(R"("fsp": 30, "integrator": "symplectic_eulr")"));
  CHECK(contains(e, "s.json: /fsp: unknown key; did you mean \"fps\"?"));
  CHECK(contains(e, "/integrator: unknown value \"symplectic_eulr\"; did you mean \"symplectic_euler\"?"));
  e = errorsOf(springBody(R"({"position": [1,0,0], "mass": 1})", R"({"nodes": [0,1], "stifness": 3})"));
  CHECK(contains(e, "/bodies/0/springs/0/stifness: unknown key; did you mean \"stiffness\"?"));
  CHECK(contains(e, "/bodies/0/springs/0/stiffness: missing required key"));
  e = errorsOf(scene(R"("bodies": [{"type": "rop", "name": "r"}])"));
  CHECK(contains(e, "/bodies/0/type: unknown value \"rop\"; did you mean \"rope\"?"));
  e = errorsOf(scene(R"("objects": [{"type": "sphere", "radius": 1, "centre": [0,0,0]}])"));
  CHECK(contains(e, "/objects/0/centre: unknown key; did you mean \"center\"?"));
  CHECK(contains(errorsOf(scene(R"("zzzzzz": 1)")), "/zzzzzz: unknown key"));
  e = errorsOf(scene(R"("objects": [{"type": "plane", "pattern": "sandd"}])"));
  CHECK(contains(e, "/objects/0/pattern: unknown value \"sandd\"; did you mean \"sand\"? (one of: rug, sand, wood, concrete)"));
}

TEST_CASE("wrong types name the path and what was expected") {
  auto e = errorsOf(scene(R"("fps": "thirty", "gravity": [0, -9.8], "render": {"samples": 3})"));
  CHECK(contains(e, "/fps: expected an integer, got the string \"thirty\""));
  CHECK(contains(e, "/gravity: expected a list of 3 numbers, got a list of 2"));
  CHECK(contains(e, "/render/samples: must be 1, 2 or 4"));
  CHECK(contains(errorsOf(R"({"format": "reel/2", "duration": 1})"), "/format: unsupported format"));
  CHECK(contains(errorsOf(R"({"format": "reel/1"})"), "/duration: missing required key"));
}

TEST_CASE("non-positive mass, negative stiffness or damping, zero rest length, non-finite numbers") {
  CHECK(contains(errorsOf(springBody(R"({"position": [1,0,0], "mass": 0})", R"({"nodes": [0,1], "stiffness": 1})")),
                 "/bodies/0/nodes/1/mass: must be > 0, got 0"));
  CHECK(contains(errorsOf(springBody(R"({"position": [1,0,0], "mass": -2})", R"({"nodes": [0,1], "stiffness": 1})")),
                 "/bodies/0/nodes/1/mass: must be > 0, got -2"));
  CHECK(contains(errorsOf(springBody(R"({"position": [1,0,0], "mass": 1})", R"({"nodes": [0,1], "stiffness": -5})")),
                 "/bodies/0/springs/0/stiffness: must be >= 0, got -5"));
  CHECK(contains(errorsOf(springBody(R"({"position": [1,0,0], "mass": 1})", R"({"nodes": [0,1], "stiffness": 5, "damping": -1})")),
                 "/bodies/0/springs/0/damping: must be >= 0, got -1"));
  CHECK(contains(errorsOf(springBody(R"({"position": [1,0,0], "mass": 1})", R"({"nodes": [0,1], "stiffness": 5, "rest_length": 0})")),
                 "/bodies/0/springs/0/rest_length: must be > 0, got 0"));
  CHECK(contains(errorsOf(springBody(R"({"position": [0,0,0], "mass": 1})", R"({"nodes": [0,1], "stiffness": 5})")),
                 "/bodies/0/springs/0: nodes 0 and 1 start at the same point"));
  CHECK(contains(errorsOf(springBody(R"({"position": [1,0,0], "mass": 1})", R"({"nodes": [0,7], "stiffness": 5})")),
                 "/bodies/0/springs/0/nodes/1: must be an integer in [0, 1]"));
  CHECK(contains(errorsOf(springBody(R"({"position": [1,0,0], "mass": 1})", R"({"nodes": [1,1], "stiffness": 5})")),
                 "two different nodes"));
  // JSON has no NaN or Inf; a number too large for a double is refused.
  CHECK(contains(errorsOf("{\"format\": \"reel/1\",\n \"gravity\": [0, -1e999, 0]}"),
                 "s.json:2:17: number -1e999 is too large (numbers must be finite)"));
  CHECK(!errorsOf(scene(R"("gravity": [0, NaN, 0])")).empty());
  CHECK(contains(errorsOf(scene(R"("bodies": [{"type": "net", "stiffness": 1, "resolution": [1, 5], "mass": -1}])")),
                 "/bodies/0/resolution/0: must be an integer in [2, 65536]"));
  CHECK(contains(errorsOf(scene(R"("bodies": [{"type": "net", "stiffness": 1, "mass": -1}])")),
                 "/bodies/0/mass: must be > 0, got -1"));
  CHECK(contains(errorsOf(scene(R"("bodies": [{"type": "lattice", "stiffness": 1, "resolution": [4000, 4000, 4000]}])")),
                 "more than the limit"));
}

TEST_CASE("scene totals and per-node masses keep a scene inside the machine") {
  std::string many = R"("bodies": [)";
  for (int i = 0; i < 5; ++i)
    many += std::string(i ? "," : "") + R"({"type": "lattice", "stiffness": 1, "resolution": [100, 100, 100]})";
  auto e = errorsOf(scene(many + "]"));
  CHECK(contains(e, "/bodies: 5000000 nodes in all, more than the limit"));
  CHECK(contains(e, "springs in all, more than the limit"));
  CHECK(contains(errorsOf(scene(R"("bodies": [{"type": "net", "stiffness": 1, "mass": 1e-320}])")),
                 "/bodies/0/mass: gives each of the 100 nodes less than 1e-12 kg"));
  CHECK(contains(errorsOf(springBody(R"({"position": [1,0,0], "mass": 1e-300})", R"({"nodes": [0,1], "stiffness": 1})")),
                 "/bodies/0/nodes/1/mass: must be at least 1e-12 kg"));
}

TEST_CASE("pins that name missing nodes") {
  auto e = errorsOf(scene(R"("bodies": [{"type": "net", "stiffness": 1, "resolution": [4, 3],
                                          "pinned": [12, [4, 0], "corner_02", [0, -3]]}])"));
  CHECK(contains(e, "/bodies/0/pinned/0: must be an integer in [-12, 11]"));
  CHECK(contains(e, "/bodies/0/pinned/1/0: must be an integer in [-4, 3]"));
  CHECK(contains(e, "/bodies/0/pinned/2: unknown node name \"corner_02\"; did you mean \"corner_00\"?"));
  const SceneDesc s = sceneFromText(scene(R"("bodies": [{"type": "net", "stiffness": 1, "resolution": [4, 3],
                                                       "pinned": [-1, [1, 2], "corner_10"]}])"));
  CHECK(s.bodies[0].as<NetDesc>().pinned == std::vector<int>{11, 9, 3});
}

TEST_CASE("at most 8 lights, at most 2 casting shadows") {
  std::string many = R"("lights": [)";
  for (int i = 0; i < 9; ++i) many += std::string(i ? "," : "") + R"({"type": "ambient"})";
  CHECK(contains(errorsOf(scene(many + "]")), "/lights: at most 8 lights, got 9"));
  std::string shadows = R"("lights": [)";
  for (int i = 0; i < 3; ++i) shadows += std::string(i ? "," : "") + R"({"type": "directional", "shadows": true})";
  CHECK(contains(errorsOf(scene(shadows + "]")), "/lights: at most 2 lights may cast shadows"));
}

TEST_CASE("duplicate names") {
  auto e = errorsOf(scene(R"("objects": [{"type": "plane", "name": "a"}],
                             "bodies": [{"type": "rope", "name": "a", "start": [0,0,0], "end": [1,0,0], "stiffness": 1}])"));
  CHECK(contains(e, "/bodies/0/name: duplicate name \"a\""));
}

TEST_CASE("every error of a file is reported at once") {
  auto e = errorsOf(scene(R"("fps": 0, "substeps": -1, "gravity": "down", "colour": 1,
                             "bodies": [{"type": "rope", "start": [0,0,0], "end": [1,0,0], "stiffness": -1, "mass": 0}])"));
  CHECK(e.size() == 6);
  CHECK(contains(e, "/fps"));
  CHECK(contains(e, "/substeps"));
  CHECK(contains(e, "/gravity"));
  CHECK(contains(e, "/colour"));
  CHECK(contains(e, "/bodies/0/stiffness"));
  CHECK(contains(e, "/bodies/0/mass"));
}

TEST_CASE("assets: missing, wrong type, oversized or escaping the allowed folders") {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / "reel_test_assets";
  fs::create_directories(dir / "sub");
  REQUIRE(io::writePng((dir / "outside.png").string(), Image(2, 2)).ok());
  REQUIRE(io::writePng((dir / "sub" / "ok.png").string(), Image(2, 2)).ok());
  std::ofstream(dir / "sub" / "fake.png") << "not a png";
  std::ofstream(dir / "sub" / "notes.txt") << "txt";
  const std::string file = (dir / "sub" / "scene.json").string();
  auto tex = [&](const std::string& t) {
    return scene(R"("objects": [{"type": "sphere", "radius": 1, "texture": ")" + t + R"("}])");
  };
  CHECK(errorsOf(tex("ok.png"), file).empty());
  CHECK(contains(errorsOf(tex("nope.png"), file), "/objects/0/texture: \"nope.png\": no such file"));
  CHECK(contains(errorsOf(tex("notes.txt"), file), "unsupported file type"));
  CHECK(contains(errorsOf(tex("fake.png"), file), "/objects/0/texture: \"fake.png\": "));
  CHECK(contains(errorsOf(tex("fake.png"), file), "not a PNG file"));
  CHECK(contains(errorsOf(tex("../outside.png"), file), "escapes the allowed folders"));
  CHECK(contains(errorsOf(tex("/etc/hostname.png"), file), "/objects/0/texture: \"/etc/hostname.png\": no such file"));
  {
    std::ofstream big(dir / "sub" / "big.png", std::ios::binary);
    big.seekp(static_cast<std::streamoff>(io::kMaxTextureBytes) + 1);
    big.put('x');
  }
  CHECK(contains(errorsOf(tex("big.png"), file), "larger than the limit"));
  fs::remove_all(dir);
  // A missing or unreadable scene file is a clean error too.
  auto r = app::loadScene("/nonexistent/scene.json");
  REQUIRE(!r.ok());
  CHECK(r.error().kind == ErrorKind::BadInput);
  CHECK(r.error().headline() == "/nonexistent/scene.json: no such file");
}

TEST_CASE("a step above an explicit bound is refused with the bound, or subdivided on request") {
  const std::string body = R"("bodies": [{"type": "rope", "name": "r", "start": [0,0,0], "end": [1,0,0],
                                "segments": 10, "mass": 0.1, "stiffness": 1e5, "pinned": [0]}])";
  auto w = app::makeWorld(sceneFromText(scene(R"("substeps": 1, )" + body)));
  REQUIRE(!w.ok());
  CHECK(w.error().kind == ErrorKind::BadInput);
  CHECK(w.error().headline().find("test.json: /substeps: step h = 1/(fps·substeps) = 0.0333 s is above the "
                                  "stability bound") == 0);
  CHECK(w.error().headline().find("\"substeps\": ") != std::string::npos);
  auto sub = app::makeWorld(sceneFromText(scene(R"("substeps": 1, "auto_substeps": true, )" + body)));
  REQUIRE(sub.ok());
  CHECK(sub.value().stepsPerFrame() > 1);
  CHECK(sub.value().stepSize() < sub.value().bodies()[0]->stepLimit(IntegratorKind::SymplecticEuler).bound.h_max);
  for (int i = 0; i < 30; ++i) REQUIRE(sub.value().advanceFrame().ok());
  // Implicit Euler takes the big step as it is.
  auto im = app::makeWorld(sceneFromText(scene(R"("substeps": 1, "integrator": "implicit_euler", )" + body)));
  REQUIRE(im.ok());
  CHECK(im.value().stepsPerFrame() == 1);
  // Explicit Euler on undamped springs has no stable step at all.
  auto ee = app::makeWorld(sceneFromText(scene(R"("integrator": "explicit_euler", )" + body)));
  REQUIRE(!ee.ok());
  CHECK(ee.error().headline().find("/integrator: explicit_euler is unstable") != std::string::npos);
}

TEST_CASE("a runaway state stops with the frame, time, body, node and quantity") {
  auto w = app::makeWorld(sceneFromText(scene(R"("bodies": [{"type": "mass_spring", "name": "rocket",
      "nodes": [{"position": [0,0,0], "mass": 1}, {"position": [0,1,0], "mass": 1, "velocity": [0, 2e4, 0]}]}])")));
  REQUIRE(w.ok());
  Status st = w.value().advanceFrame();
  REQUIRE(!st.ok());
  CHECK(st.error().kind == ErrorKind::Unstable);
  CHECK(st.error().headline().find("unstable at frame 1 (t = 0.00333 s): body 'rocket' node 1 speed") == 0);
}

TEST_CASE("a background's glow: bad keys and values refused with their paths") {
  const auto e = errorsOf(R"({"format": "reel/1", "duration": 0.1, "render": {"background": {"top": [0, 0, 0],
      "glow": {"color": [0.5, -0.5, 0.5], "radius": 0, "size": 1}}}})");
  CHECK(contains(e, "/render/background/glow/color"));
  CHECK(contains(e, "/render/background/glow/radius"));
  CHECK(contains(e, "/render/background/glow/size"));
  CHECK(errorsOf(R"({"format": "reel/1", "duration": 0.1, "render": {"background": {"top": [0, 0, 0],
      "glow": {"color": [0.5, 0.5, 0.5], "x": 0.2, "y": 0.9, "radius": 0.3}}}})").empty());
}
