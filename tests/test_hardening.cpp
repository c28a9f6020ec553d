// Hostile input (DESIGN 9): mesh files that would hang or exhaust the importer, assets that refer
// outside the allowed folders, outputs that are not regular files, counts and times that overflow,
// duplicate keys, a full disk, and threads that wait without spinning. Each case failed before
// the hardening it tests.
#include <doctest/doctest.h>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "capture.h"
#include "helpers.h"
#include "sanitizers.h"
#include "io/files.h"
#include "io/mesh_import.h"
#include "io/xml.h"

using namespace reel;
using reel::test::runReel;
namespace fs = std::filesystem;

namespace {

std::string put(const fs::path& dir, const std::string& name, const std::string& text) {
  std::ofstream(dir / name, std::ios::binary) << text;
  return (dir / name).string();
}

// The import's error, or "" when it succeeds.
std::string importError(const std::string& path, double budget_s = io::kMeshImportSeconds) {
  auto m = io::importMesh(path, {}, budget_s);
  return m.ok() ? std::string() : m.error().headline();
}

bool has(const std::string& text, const std::string& part) {
  INFO(text);
  return text.find(part) != std::string::npos;
}

const char* kTriangleObj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
const char* kPlyHeader = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n";

}  // namespace

TEST_CASE("a PLY header that never ends is refused at once (assimp's reader looped forever)") {
  const fs::path d = test::freshDir("hardening_ply_header");
  CHECK(has(importError(put(d, "a.ply", "ply\nformat ascii 1.0\n")), "the PLY header does not end"));
  CHECK(has(importError(put(d, "b.ply", "not a ply\n")), "not a PLY file"));
  CHECK(has(importError(put(d, "d.ply", std::string("ply\nformat ascii 1.0\nend_headerel\n") + kPlyHeader + "end_header\n")),
            "d.ply:3: unknown PLY header line \"end_headerel\""));  // (fuzz_mesh: assimp read on and leaked)
  // A line that is no PLY keyword at all is read past, as readers do (a Blender export's "Created").
  const std::string bogus = importError(put(d, "c.ply", std::string(kPlyHeader) + "element face 1\nproperty list uchar int vertex_indices\nbogus\nend_header\n"));
  CHECK(!has(bogus, "bogus"));
  CHECK(has(bogus, "c.ply"));  // (refused for its missing body instead)
}

TEST_CASE("PLY counts are checked against the caps and the file's bytes before import") {
  const fs::path d = test::freshDir("hardening_ply_counts");
  // 190 bytes declaring 10^8 faces took 60 s and 3 GB; 4e9 vertices ended in std::bad_alloc.
  const std::string faces = std::string(kPlyHeader) + "element face 100000000\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  CHECK(has(importError(put(d, "faces.ply", faces)), "faces.ply:7: declares 100,000,000 face elements, more than the limit of 2,000,000"));
  CHECK(has(importError(put(d, "verts.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\nend_header\n")),
            "verts.ply:3: declares 4,000,000,000 vertex elements, more than the limit of 6,000,000"));
  // Within the caps, but more than the data can hold: 1,000 faces in 20 bytes.
  const std::string short_body = std::string(kPlyHeader) + "element face 1000\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  CHECK(has(importError(put(d, "short.ply", short_body)), "declares 1,000 face elements, more than its"));
  // One-digit values with no newline at the end fit exactly.
  CHECK_FALSE(has(importError(put(d, "tight.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0")),
                  "bytes of data can hold"));
  // The same file with its true count imports.
  const std::string good = std::string(kPlyHeader) + "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  CHECK(importError(put(d, "good.ply", good)).empty());
}

TEST_CASE("an OBJ over the triangle cap is refused while it is counted, not after import") {
  const fs::path d = test::freshDir("hardening_obj_cap");
  {
    std::ofstream f(d / "big.obj");
    f << "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    const std::string face = "f 1 2 3\n";
    std::string block;
    for (int i = 0; i < 100'000; ++i) block += face;
    for (int k = 0; k < 21; ++k) f << block;  // 2,100,000 triangles, 16.8 MB
  }
  CHECK(has(importError((d / "big.obj").string()), "big.obj:2000004: more than the limit of 2,000,000 triangles"));
}

TEST_CASE("OBJ faces with too few corners or missing vertices are named by line, in plain words") {
  const fs::path d = test::freshDir("hardening_obj_faces");
  CHECK(has(importError(put(d, "line.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n")), "line.obj:4: a face needs 3 or more corners, this one has 2"));
  CHECK(has(importError(put(d, "far.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n")), "far.obj:4: a face names vertex 9, but the file has 3"));
  CHECK(has(importError(put(d, "neg.obj", "v 0 0 0\nf -1 -2 -3\n")), "neg.obj:2: corner \"-2\" names no vertex"));
  // An ASCII STL facet with 2 vertices: assimp threw and leaked the meshes it had read (fuzz_mesh).
  CHECK(has(importError(put(d, "bad.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\nendfacet\nendsolid\n")),
            "bad.stl:6: expected \"vertex x y z\""));
  CHECK(has(importError(put(d, "open.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n")), "open.stl:2: the facet has 1 vertices and does not end"));
  CHECK(has(importError(put(d, "word.stl", "solid x\nfacet normal 1!1 1\n")), "word.stl:2: expected \"facet normal x y z\" or \"endsolid\""));
  CHECK(has(importError(put(d, "after.stl", "solid x\nendsolid x\nfacet normal 1!1 1\n")), "after.stl:3: expected \"solid\" or nothing after"));
  // PLY bodies are walked against their header (assimp leaked what it had read when it threw).
  CHECK(has(importError(put(d, "noverts.ply", std::string("ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n3 0 1 2\n"))),
            "noverts.ply:3: the faces come before the vertices they name"));
  CHECK(has(importError(put(d, "word.ply", std::string(kPlyHeader) + "end_header\n0 0 0\n1 0 0\n0 1 oops\n")), "word.ply:10: vertex 2: expected a number, got \"oops\""));
  // One element per line, as assimp reads them: a line of 6 values for 4 properties is refused.
  CHECK(has(importError(put(d, "wide.ply", "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nend_header\n0 0 0\n1 0 0\n")),
            "wide.ply:7: vertex 0: 3 values, the header gives 2"));
  const std::string bin_header = "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  CHECK(has(importError(put(d, "cut.ply", bin_header + std::string("\0\0\0\0\x09\0\0\0\0", 9))), "cut.ply: face 0: the file ends inside it"));
  // Assimp's own wording ("aiMesh::mFaces[0]::mIndices[2] is out of range") becomes a sentence.
  CHECK(has(importError(put(d, "range.ply", std::string(kPlyHeader) + "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n")),
            "range.ply: face 0 refers to a vertex that does not exist"));
  CHECK(has(importError(put(d, "lines.ply", std::string(kPlyHeader) + "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n")),
            "lines.ply: face 0 has 2 corners; a face needs 3 or more"));
}

TEST_CASE("what the mesh fuzzer found is refused cleanly (tests/fuzz/regressions)") {
  // Each file: the first byte picks the format, as in fuzz_mesh; under the asan preset a leak or
  // overflow here fails the suite.
  const fs::path d = test::freshDir("hardening_fuzz_regressions");
  int files = 0;
  for (const auto& e : fs::directory_iterator(fs::path(REEL_SOURCE_DIR) / "tests" / "fuzz" / "regressions")) {
    if (e.path().filename().string().rfind("mesh-", 0) != 0) continue;
    std::ifstream in(e.path(), std::ios::binary);
    const std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    REQUIRE(!data.empty());
    const std::string ext = io::kMeshExtensions[static_cast<unsigned char>(data[0]) % std::size(io::kMeshExtensions)];
    INFO(e.path().filename().string());
    CHECK_FALSE(importError(put(d, "mesh" + ext, data.substr(1))).empty());
    ++files;
  }
  CHECK(files >= 2);
}

TEST_CASE("files an asset refers to must lie in the allowed folders (OBJ mtllib, glTF buffer uri)") {
  const fs::path root = test::freshDir("hardening_refs");
  const fs::path d = root / "scene";
  fs::create_directories(d);
  put(root, "secret.mtl", "newmtl x\nKd 1 0 0\n");
  const std::string esc = put(d, "esc.obj", std::string("mtllib ../secret.mtl\n") + kTriangleObj);
  CHECK(has(importError(esc), "esc.obj: refers to \""));
  CHECK(has(importError(esc), "secret.mtl\", which lies outside the allowed folders"));
  // The same reference inside the folder is read.
  put(d, "ok.mtl", "newmtl x\nKd 1 0 0\n");
  CHECK(importError(put(d, "ok.obj", std::string("mtllib ok.mtl\n") + kTriangleObj)).empty());
  // A glTF buffer outside: refused before assimp opens it.
  const std::string gltf = R"({"asset": {"version": "2.0"}, "buffers": [{"uri": "../../../../etc/passwd", "byteLength": 10}]})";
  CHECK(has(importError(put(d, "esc.gltf", gltf)), "buffers[0].uri: \"../../../../etc/passwd\" lies outside the allowed folders"));
  // Through a scene: the scene's folder and assets/ are the roots.
  put(d, "s.json", R"({"format": "reel/1", "duration": 1, "objects": [{"type": "mesh", "file": "esc.obj"}]})");
  const auto r = runReel("check " + (d / "s.json").string());
  CHECK(r.code == 2);
  CHECK(has(r.out, "/objects/0/file: \"esc.obj\""));
  CHECK(has(r.out, "outside the allowed folders"));
}

TEST_CASE("glTF and GLB: buffers, views and accessors must fit the bytes that exist") {
  const fs::path d = test::freshDir("hardening_gltf");
  // One triangle in a data URI (36 bytes of float positions).
  const std::string data = "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA";
  auto doc = [&](const std::string& byte_length, const std::string& count) {
    return R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
      "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
      "buffers": [{"uri": ")" + data + R"(", "byteLength": )" + byte_length + R"(}],
      "bufferViews": [{"buffer": 0, "byteLength": 36}],
      "accessors": [{"bufferView": 0, "componentType": 5126, "count": )" + count + R"(, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}]})";
  };
  CHECK(importError(put(d, "tri.gltf", doc("36", "3"))).empty());
  CHECK(has(importError(put(d, "big_buffer.gltf", doc("4000000", "3"))), "buffers[0].byteLength: 4,000,000 bytes, more than its data holds (36)"));
  CHECK(has(importError(put(d, "big_count.gltf", doc("36", "1000"))), "accessors[0]: 1,000 elements, more than its buffer view holds"));
  CHECK(has(importError(put(d, "huge_count.gltf", doc("36", "4000000000"))), "accessors[0].count: must be in [0, 6,000,000]"));
  const std::string cycle = R"({"asset": {"version": "2.0"}, "nodes": [{"children": [1]}, {"children": [0]}]})";
  CHECK(has(importError(put(d, "cycle.gltf", cycle)), "cycle.gltf: nodes[0].children: the nodes form a cycle"));
  std::string chain = R"({"asset": {"version": "2.0"}, "nodes": [)";  // 2,000 nodes deep
  for (int i = 0; i < 2000; ++i) chain += (i ? ", " : "") + (i + 1 < 2000 ? "{\"children\": [" + std::to_string(i + 1) + "]}" : std::string("{}"));
  CHECK(has(importError(put(d, "deep.gltf", chain + "]}")), "deep, more than the limit of 1000"));
  // Sparse values: the indices' view must hold them (assimp read past it).
  std::string sparse = doc("36", "3");
  sparse.insert(sparse.find(R"("min")"), R"("sparse": {"count": 2, "indices": {"bufferView": 0, "byteOffset": 34, "componentType": 5125},
                                                   "values": {"bufferView": 0}}, )");
  CHECK(has(importError(put(d, "sparse.gltf", sparse)), "accessors[0].sparse.indices: 2 elements, more than its buffer view holds"));
  CHECK(has(importError(put(d, "len.glb", std::string("glTF\x02\0\0\0\xff\0\0\0\x04\0\0\0JSON{}  ", 24))), "its header gives a length of 255 bytes, the file has 24"));
}

TEST_CASE("STL: a binary count that does not match the file, and the import's time budget") {
  const fs::path d = test::freshDir("hardening_stl");
  std::string bin(84, '\0');
  bin[80] = '\x10';  // 16 triangles declared, none present
  CHECK(has(importError(put(d, "short.stl", bin)), "neither a binary STL"));
  // The budget cancels an import that runs past it (assimp asks between its steps).
  CHECK(has(importError(put(d, "tri.obj", kTriangleObj), 0.0), "import took longer than the budget of 0 s"));
  CHECK(importError((d / "tri.obj").string()).empty());
}

TEST_CASE("a scene name with a path in it keeps the default output inside render_out/") {
  const fs::path d = test::freshDir("hardening_name");
  fs::create_directories(d / "work");
  put(d / "work", "s.json", R"({"format": "reel/1", "name": "../../../escaped", "duration": 0.1, "fps": 10,
    "render": {"width": 16, "height": 16, "samples": 1}})");
  const auto r = runReel("render s.json", "cd " + (d / "work").string() + " && ");
  CHECK(r.code == 0);
  INFO(r.out);
  CHECK(fs::exists(d / "work" / "render_out" / "_escaped.mp4"));
  CHECK_FALSE(fs::exists(d / "escaped.mp4"));
  CHECK_FALSE(fs::exists(d.parent_path() / "escaped.mp4"));
}

TEST_CASE("an output that is a FIFO, a folder or a device is refused with exit 4, never replaced") {
  const fs::path d = test::freshDir("hardening_outputs");
  const std::string scene = put(d, "s.json", R"({"format": "reel/1", "duration": 0.1, "fps": 10, "render": {"width": 16, "height": 16}})");
  const fs::path fifo = d / "pipe.json";
  REQUIRE(mkfifo(fifo.c_str(), 0600) == 0);
  auto r = runReel("simulate " + scene + " --dump " + fifo.string());
  CHECK(r.code == 4);
  CHECK(has(r.out, "pipe.json: is a FIFO, not a regular file"));
  CHECK(fs::is_fifo(fifo));  // still the FIFO
  fs::create_directories(d / "folder.png");
  r = runReel("still " + scene + " --frame 0 -o " + (d / "folder.png").string());
  CHECK(r.code == 4);
  CHECK(has(r.out, "folder.png: is a folder"));
  CHECK(fs::is_directory(d / "folder.png"));
  const fs::path video = d / "v.mp4";
  REQUIRE(mkfifo(video.c_str(), 0600) == 0);
  r = runReel("render " + scene + " -o " + video.string());
  CHECK(r.code == 4);
  CHECK(has(r.out, "v.mp4: is a FIFO"));
  // A device is only checked here, never opened.
  CHECK(io::checkOutputTarget("/dev/null").error().kind == ErrorKind::Output);
  CHECK(has(io::checkOutputTarget("/dev/null").error().headline(), "/dev/null: is a device"));
  CHECK(io::checkOutputTarget((d / "new.json").string()).ok());
}

TEST_CASE("an output that is a symbolic link is written through it, never renamed over") {
  // `-o /dev/stdout > f.png` as root replaced the system's /dev/stdout link with the PNG: the
  // part file was renamed onto the link. The same with links of the test's own.
  const fs::path d = test::freshDir("hardening_links");
  const std::string scene = put(d, "s.json", R"({"format": "reel/1", "duration": 0.1, "fps": 10, "render": {"width": 16, "height": 16}})");
  fs::create_directories(d / "real");
  fs::create_symlink(d / "real" / "target.json", d / "link.json");  // dangling until written
  auto r = runReel("simulate " + scene + " --dump " + (d / "link.json").string());
  CHECK(r.code == 0);
  CHECK(fs::is_symlink(d / "link.json"));
  CHECK(fs::is_regular_file(d / "real" / "target.json"));
  CHECK(has(test::fileBytes(d / "real" / "target.json"), "reel-dump/1"));
  CHECK_FALSE(fs::exists(d / "real" / "target.json.part"));
  // A link to the process's own standard output, which the shell sent to a file: that file gets
  // the still, the link stays.
  fs::create_symlink("/proc/self/fd/1", d / "stdout.png");
  r = runReel("still " + scene + " --frame 0 -q -o " + (d / "stdout.png").string() + " > " + (d / "f.png").string(), "");
  CHECK(r.code == 0);
  CHECK(fs::is_symlink(d / "stdout.png"));
  CHECK(test::fileBytes(d / "f.png").substr(1, 3) == "PNG");
  // A link to a FIFO is refused like the FIFO, and stays a link.
  REQUIRE(mkfifo((d / "pipe").c_str(), 0600) == 0);
  fs::create_symlink(d / "pipe", d / "to_pipe.json");
  r = runReel("simulate " + scene + " --dump " + (d / "to_pipe.json").string());
  CHECK(r.code == 4);
  CHECK(has(r.out, "is a FIFO, not a regular file"));
  CHECK(fs::is_symlink(d / "to_pipe.json"));
}

TEST_CASE("a UTF-8 byte-order mark is read past; a DOCTYPE with declarations is refused in plain words") {
  const fs::path d = test::freshDir("hardening_bom");
  // A scene an editor saved with a byte-order mark loads; an error in it keeps its position.
  const std::string scene = put(d, "bom.json", "\xEF\xBB\xBF{\"format\": \"reel/1\", \"duration\": 0.1, \"fps\": 10}");
  auto r = runReel("check " + scene);
  CHECK(r.code == 0);
  r = runReel("check " + put(d, "bom_bad.json", "\xEF\xBB\xBF{\"format\": \"reel/1\",\n  \"duration\": }"));
  CHECK(r.code == 2);
  CHECK(has(r.out, "bom_bad.json:2:"));
  // Robot files: the mark is read past; a bare DOCTYPE is skipped; one that declares entities is
  // refused as such, not as a syntax error further on.
  CHECK(io::parseXml("\xEF\xBB\xBF<robot name=\"r\"/>").ok());
  CHECK(io::parseXml("<?xml version=\"1.0\"?>\n<!DOCTYPE robot>\n<robot/>").ok());
  const auto bomb = io::parseXml("<!DOCTYPE r [<!ENTITY a \"aaaa\"><!ENTITY b \"&a;&a;\">]>\n<r x=\"&b;\"/>");
  REQUIRE_FALSE(bomb.ok());
  CHECK(has(bomb.error().headline(), "line 1: a DOCTYPE with declarations (entities) is not supported"));
}

TEST_CASE("join names what a chunk that is not a file is: a folder, a FIFO, a device") {
  const fs::path d = test::freshDir("hardening_join_inputs");
  fs::create_directories(d / "folder.mp4");
  REQUIRE(mkfifo((d / "pipe.mp4").c_str(), 0600) == 0);
  for (const auto& [chunk, what] : std::vector<std::pair<std::string, std::string>>{
           {(d / "folder.mp4").string(), "is a folder"}, {(d / "pipe.mp4").string(), "is a FIFO"},
           {"/dev/zero", "is a device"}, {(d / "missing.mp4").string(), "no such file"}}) {
    CAPTURE_BINDING(chunk);
    const auto r = runReel("join " + chunk + " -o " + (d / "out.mp4").string());
    CHECK(r.code == 2);
    CHECK(has(r.out, chunk + ": " + what));
    CHECK_FALSE(fs::exists(d / "out.mp4"));
  }
}

TEST_CASE("a full disk during --dump names the file and leaves no dump behind") {
  const fs::path d = test::freshDir("hardening_full");
  const std::string rope = std::string(REEL_SOURCE_DIR) + "/scenes/rope.json";
  const fs::path out = d / "dump.json";
  // A file size limit of 64 KiB stands in for a full disk (SIGXFSZ ignored: writes fail EFBIG).
  const auto r = runReel("simulate " + rope + " --dump " + out.string(), "ulimit -f 128; trap '' XFSZ; ");
  CHECK(r.code == 4);
  CHECK(has(r.out, out.string() + ": write failed: File too large"));
  CHECK_FALSE(fs::exists(out));
  CHECK_FALSE(fs::exists(out.string() + ".part"));
  // The same limit without the shell's trap: reel itself ignores SIGXFSZ (it was killed by the
  // signal, rc 153, with no word).
  const auto plain = runReel("simulate " + rope + " --dump " + out.string(), "ulimit -f 128; ");
  CHECK(plain.code == 4);
  CHECK(has(plain.out, out.string() + ": write failed: File too large"));
  CHECK_FALSE(fs::exists(out));
}

TEST_CASE("counts and times from doubles are checked before they are converted") {
  const fs::path d = test::freshDir("hardening_overflow");
  // A block from 0 to 1e10 m at 1e-9 m spacing became one particle.
  put(d, "block.json", R"({"format": "reel/1", "duration": 1, "bodies": [{"type": "fluid", "name": "f",
    "species": [{"name": "w"}], "blocks": [{"min": [0, 0, 0], "max": [1e10, 1e10, 1e10], "spacing": 1e-9}]}]})");
  auto r = runReel("check " + (d / "block.json").string());
  CHECK(r.code == 2);
  CHECK(has(r.out, "/bodies/0/blocks/0: holds over 10^15 particles"));
  const std::string scene = put(d, "s.json", R"({"format": "reel/1", "duration": 1, "fps": 10, "render": {"width": 16, "height": 16}})");
  for (const char* t : {"1e20", "1e9", "1.2"}) {
    r = runReel("still " + scene + " --time " + t + " -o " + (d / "x.png").string());
    CHECK(r.code == 2);
    CHECK(has(r.out, "s is outside the film (0 to 0.9 s)"));
  }
  CHECK(runReel("still " + scene + " --time 0.9 -o " + (d / "x.png").string()).code == 0);
  // Past the GL limits or reel's framebuffer cap: which limit, before anything is allocated.
  r = runReel("still " + scene + " --frame 0 --size 16384x16384 --samples 4 -o " + (d / "y.png").string());
  CHECK(r.code == 2);
  CHECK(has(r.out, "16384x16384 at 4 samples needs 9216 MiB of framebuffer, more than the limit of 3072 MiB"));
}

TEST_CASE("a key given twice in one object is an error with both locations") {
  const fs::path d = test::freshDir("hardening_dup");
  put(d, "top.json", "{\"format\": \"reel/1\",\n \"duration\": 1,\n \"duration\": 2}");
  auto r = runReel("check " + (d / "top.json").string());
  CHECK(r.code == 2);
  CHECK(has(r.out, "top.json:3:2: /duration: duplicate key \"duration\" (first at 2:2)"));
  // Nested, after a comment holding a brace and an escaped key; the same key in two objects is fine.
  put(d, "nested.json", "{\"format\": \"reel/1\", \"duration\": 1, // { \"x\"\n \"bodies\": [{\"type\": \"rope\", \"name\": \"a\"},\n"
                        " {\"type\": \"rope\", \"name\": \"b\", \"n\\u0061me\": \"c\"}]}");
  r = runReel("check " + (d / "nested.json").string());
  CHECK(r.code == 2);
  CHECK(has(r.out, "nested.json:3:32: /bodies/1/name: duplicate key \"name\" (first at 3:19)"));
  CHECK_FALSE(has(r.out, "/bodies/0/name: duplicate"));
  // A comment ends at a carriage return too (old Mac line ends), as the parser reads it.
  put(d, "cr.json", "{\"format\": \"reel/1\", // note\r \"duration\": 1, \"duration\": 2}");
  r = runReel("check " + (d / "cr.json").string());
  CHECK(has(r.out, "/duration: duplicate key \"duration\""));
}

TEST_CASE("auto_substeps already on: the refusal does not advise it, and says the limit") {
  const fs::path d = test::freshDir("hardening_substeps");
  put(d, "stiff.json", R"({"format": "reel/1", "duration": 1, "fps": 30, "substeps": 1, "auto_substeps": true,
    "integrator": "symplectic_euler",
    "bodies": [{"type": "rope", "name": "r", "start": [0, 0, 0], "end": [1, 0, 0], "segments": 4, "mass": 1e-9, "stiffness": 1e12}]})");
  const auto r = runReel("check " + (d / "stiff.json").string());
  CHECK(r.code == 2);
  CHECK(has(r.out, "steps a frame, more than the limit of 1e+07; use implicit_euler"));
  CHECK_FALSE(has(r.out, "\"auto_substeps\": true"));
}

TEST_CASE("OpenMP threads spin briefly, then sleep: a loaded machine is not made slower by spinning") {
  // The runtime reports its settings: 1000 spins (libgomp's default is 300,000).
  const auto r = runReel("info", "OMP_DISPLAY_ENV=verbose ");
  CHECK(r.code == 0);
  if (r.out.find("GOMP_SPINCOUNT =") != std::string::npos) CHECK(has(r.out, "GOMP_SPINCOUNT = '1000'"));
  CHECK(has(r.out, "waiting: 1000 spins, then sleep"));
  CHECK(has(runReel("info", "GOMP_SPINCOUNT=0 ").out, "waiting: 0 spins, then sleep"));
  // A user's own choice is kept.
  CHECK(has(runReel("info", "OMP_WAIT_POLICY=active ").out, "waiting: active"));
}

TEST_CASE("two writers of one cache file at once each write their own part file; the last rename wins, whole") {
  // The simulation cache may be filled by two processes or two threads (`reel test -j 2` on one
  // scene) at the same frame: one shared PATH.part made the second rename fail and the cache off.
  const std::filesystem::path d = reel::test::freshDir("shared_part");
  const std::string path = (d / "frame_000004.sim").string();
  reel::io::AtomicFile a, b;
  REQUIRE(a.open(path, /*shared=*/true).ok());
  REQUIRE(b.open(path, /*shared=*/true).ok());
  REQUIRE(a.write("first writer").ok());
  REQUIRE(b.write("second writer").ok());
  CHECK(a.commit().ok());
  CHECK(b.commit().ok());
  CHECK(reel::test::fileBytes(path) == "second writer");
  int left = 0;
  for (const auto& e : std::filesystem::directory_iterator(d)) left += e.path().string() != path;
  CHECK(left == 0);  // no part file left behind
}


TEST_CASE("a scene that needs more memory than the process may use: exit 2, said as such") {
  // 100,000 fish (the documented maximum) under a 500 MB address-space limit (not under
  // AddressSanitizer, whose shadow memory alone is larger).
  if (reel::test::kSanitizerAddressSpace) return;
  const std::filesystem::path d = reel::test::freshDir("oom");
  std::ofstream(d / "fish.json") << R"({ "format": "reel/1", "duration": 1, "fps": 30, "substeps": 10, "auto_substeps": true,
    "bodies": [ { "type": "fish", "name": "f", "count": 100000 } ] })";
  const auto r = reel::test::runReel("check " + (d / "fish.json").string(), "ulimit -v 500000; ");
  CAPTURE(r.out);
  CHECK(r.code == 2);
  CHECK(r.out.find("reel: out of memory: the scene or the options") != std::string::npos);
}

TEST_CASE("a step too long for a fish is refused before its 100,000 fish are built") {
  // Every fish of a body is the same template: one is built to find the bound. Under a 500 MB
  // address-space limit the whole body could not be built (it took 1.1 GB and 10 s to be refused).
  if (reel::test::kSanitizerAddressSpace) return;
  const std::filesystem::path d = reel::test::freshDir("fish_refused");
  std::ofstream(d / "fish.json") << R"({ "format": "reel/1", "duration": 1, "fps": 30, "substeps": 10,
    "bodies": [ { "type": "fish", "name": "f", "count": 100000 } ] })";
  std::ofstream(d / "two.json") << R"({ "format": "reel/1", "duration": 1, "fps": 30, "substeps": 10,
    "bodies": [ { "type": "fish", "name": "f", "count": 2 } ] })";
  const auto many = reel::test::runReel("check " + (d / "fish.json").string(), "ulimit -v 500000; ");
  const auto two = reel::test::runReel("check " + (d / "two.json").string());
  CAPTURE(many.out);
  CHECK(many.code == 2);
  CHECK(many.out.find("is above the stability bound") != std::string::npos);
  // The same bound, node and advice as for two fish.
  CHECK(many.out.substr(many.out.find("/substeps")) == two.out.substr(two.out.find("/substeps")));
}
