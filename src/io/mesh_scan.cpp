#include "io/mesh_scan.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string_view>

#include <nlohmann/json.hpp>

#include "io/files.h"
#include "io/mesh_scan_util.h"

namespace reel::io {

namespace fs = std::filesystem;
using namespace scan;  // (the text helpers of mesh_scan_util.h)

namespace {

using Json = nlohmann::json;

// OBJ (Wavefront): vertices and faces counted line by line; a face needs three corners, each
// naming a vertex the file has (positive: from 1; negative: back from the last one read), and so
// do the corners of points and lines (assimp throws on them, leaking). A '\' line continuation is
// not supported.
Status scanObj(const std::string& path) {
  unsigned long long vertices = 0, triangles = 0;
  long long worst = 0;  // the largest positive vertex index, and its line
  std::size_t worst_line = 0;
  Status st = forEachLine(path, [&](std::string_view line, std::size_t number) -> Status {
    line = trim(line);
    if (line.size() < 2 || (line[1] != ' ' && line[1] != '\t')) return {};
    const std::string at = path + ":" + std::to_string(number);
    if (line[0] == 'v' && ++vertices > kMaxMeshVertices)
      return Error(ErrorKind::BadInput, at + ": more than the limit of " + thousands(kMaxMeshVertices) + " vertices");
    if (line[0] != 'f' && line[0] != 'l' && line[0] != 'p') return {};
    const auto w = words(line);
    const std::size_t corners = w.size() - 1;
    if (line[0] == 'f' && corners < 3)
      return Error(ErrorKind::BadInput, at + ": a face needs 3 or more corners, this one has " + std::to_string(corners));
    for (std::size_t c = 1; c < w.size(); ++c) {
      const std::string_view v = w[c].substr(0, w[c].find('/'));
      const bool minus = !v.empty() && v[0] == '-';
      const auto n = count(minus ? v.substr(1) : v);
      if (!n || *n == 0 || (minus && *n > vertices))
        return Error(ErrorKind::BadInput, at + ": corner \"" + std::string(w[c]).substr(0, 40) + "\" names no vertex (" +
                                              std::to_string(vertices) + " read so far)");
      if (!minus && static_cast<long long>(*n) > worst) {
        worst = static_cast<long long>(*n);
        worst_line = number;
      }
    }
    if (line[0] != 'f') return {};  // points and lines: named vertices checked, nothing drawn
    triangles += corners - 2;
    if (triangles > kMaxMeshTriangles)
      return Error(ErrorKind::BadInput, at + ": more than the limit of " + thousands(kMaxMeshTriangles) + " triangles");
    return {};
  });
  if (st && worst > static_cast<long long>(vertices))
    return Error(ErrorKind::BadInput, path + ":" + std::to_string(worst_line) + ": a face names vertex " + std::to_string(worst) +
                                          ", but the file has " + std::to_string(vertices));
  return st;
}


// STL: binary (an 80-byte header, a triangle count, 50 bytes per triangle) or ASCII ("solid").
Status scanStl(const std::string& path, std::uintmax_t size) {
  const std::string h = head(path, 84);
  if (size >= 84) {
    std::uint32_t n = 0;
    std::memcpy(&n, h.data() + 80, 4);  // little-endian, as x86 (reel's platform)
    if (84 + 50 * static_cast<std::uintmax_t>(n) == size) {
      if (n > kMaxMeshTriangles)
        return bad(path, "declares " + thousands(n) + " triangles, more than the limit of " + thousands(kMaxMeshTriangles));
      return {};
    }
  }
  if (trim(h).rfind("solid", 0) != 0)
    return bad(path, "neither a binary STL (84 + 50 bytes per triangle, here " + thousands(size) +
                         " bytes) nor an ASCII one (starting with \"solid\")");
  // ASCII, by its grammar: "solid [name]", then facets ("facet normal x y z", "outer loop",
  // three "vertex x y z", "endloop", "endfacet"), then "endsolid [name]". Assimp's reader leaks
  // what it has read when it throws on anything else (found by fuzz_mesh), so nothing else
  // reaches it.
  unsigned long long facets = 0;
  int state = 0;  // 0 before solid; 1 between facets; 2 after facet; 3 after outer loop; 4 after 3 vertices; 5 after endloop; 6 after endsolid
  int corners = 0;
  std::size_t opened = 0;
  auto numbers = [](const std::vector<std::string_view>& w, std::size_t from) {
    if (w.size() != from + 3) return false;
    for (std::size_t i = from; i < w.size(); ++i)
      if (!isNumber(w[i])) return false;
    return true;
  };
  Status st = forEachLine(path, [&](std::string_view line, std::size_t number) -> Status {
    const auto w = words(line);
    if (w.empty()) return {};
    const std::string at = path + ":" + std::to_string(number);
    auto expected = [&](const char* what) { return Error(ErrorKind::BadInput, at + ": expected " + std::string(what)); };
    if (state == 0) {
      if (w[0] != "solid") return expected("\"solid\"");
      state = 1;
    } else if (state == 1) {
      if (w[0] == "endsolid") {
        state = 6;
      } else {
        if (w[0] != "facet" || w.size() < 2 || w[1] != "normal" || !numbers(w, 2)) return expected("\"facet normal x y z\" or \"endsolid\"");
        if (++facets > kMaxMeshTriangles)
          return Error(ErrorKind::BadInput, at + ": more than the limit of " + thousands(kMaxMeshTriangles) + " triangles");
        state = 2;
        opened = number;
      }
    } else if (state == 2) {
      if (w.size() != 2 || w[0] != "outer" || w[1] != "loop") return expected("\"outer loop\"");
      state = 3;
      corners = 0;
    } else if (state == 3) {
      if (w[0] != "vertex" || !numbers(w, 1)) return expected("\"vertex x y z\"");
      if (++corners == 3) state = 4;
    } else if (state == 4) {
      if (w[0] == "vertex")
        return Error(ErrorKind::BadInput, at + ": the facet from line " + std::to_string(opened) + " has more than 3 vertices; an STL facet has 3");
      if (w.size() != 1 || w[0] != "endloop") return expected("\"endloop\"");
      state = 5;
    } else if (state == 5) {
      if (w.size() != 1 || w[0] != "endfacet") return expected("\"endfacet\"");
      state = 1;
    } else if (w[0] == "solid") {  // state 6: another solid may follow (assimp reads them all)
      state = 1;
    } else {
      return expected("\"solid\" or nothing after \"endsolid\"");
    }
    return {};
  });
  if (!st) return st;
  if (state == 3 && corners < 3)
    return bad(path + ":" + std::to_string(opened), "the facet has " + std::to_string(corners) + " vertices and does not end; an STL facet has 3");
  if (state != 6) return bad(path, "the file ends before \"endsolid\"");
  return {};
}

// glTF 2.0 (Khronos): buffers, views and accessors must fit inside each other and inside the
// bytes that exist; nodes must form a forest.
Status scanGltfJson(const std::string& path, const Json& j, std::uintmax_t bin_bytes, const std::vector<std::string>& roots) {
  if (!j.is_object()) return bad(path, "not a glTF file (its JSON is not an object)");
  auto list = [&](const char* key) -> const Json* {
    auto it = j.find(key);
    return it != j.end() && it->is_array() ? &*it : nullptr;
  };
  auto num = [](const Json& o, const char* key, double def) -> double {
    auto it = o.find(key);
    return it != o.end() && it->is_number() ? it->get<double>() : def;
  };
  auto field = [&](const char* what, std::size_t i, const char* key) {
    return path + ": " + what + "[" + std::to_string(i) + "]." + key;
  };
  if (auto a = j.find("asset"); a != j.end() && a->is_object()) {
    auto v = a->find("version");
    if (v != a->end() && v->is_string() && v->get<std::string>().rfind("2", 0) != 0)
      return bad(path, "glTF version " + v->get<std::string>().substr(0, 20) + " (reel reads glTF 2.0)");
  }
  std::vector<double> buffer_len;
  if (const Json* bs = list("buffers")) {
    for (std::size_t i = 0; i < bs->size(); ++i) {
      const Json& b = (*bs)[i];
      const double len = b.is_object() ? num(b, "byteLength", -1) : -1;
      if (!(len >= 0 && len <= static_cast<double>(kMaxMeshBytes)))
        return Error(ErrorKind::BadInput, field("buffers", i, "byteLength") + ": must be in [0, " + thousands(kMaxMeshBytes) + "]");
      double have = static_cast<double>(bin_bytes);
      if (auto u = b.find("uri"); u != b.end() && u->is_string()) {
        const std::string uri = u->get<std::string>();
        if (uri.rfind("data:", 0) == 0) {
          const std::size_t comma = uri.find(',');
          have = comma == std::string::npos ? 0.0 : static_cast<double>(uri.size() - comma - 1) * 0.75;
        } else {
          const std::string file = (fs::path(path).parent_path() / uri).string();
          std::error_code ec;
          if (!insideRoots(file, roots))
            return Error(ErrorKind::BadInput, field("buffers", i, "uri") + ": \"" + uri.substr(0, 200) + "\" lies outside the allowed folders");
          const auto s = fs::is_regular_file(file, ec) ? fs::file_size(file, ec) : 0;
          have = ec ? 0.0 : static_cast<double>(s);
        }
      }
      if (len > have)
        return Error(ErrorKind::BadInput, field("buffers", i, "byteLength") + ": " + thousands(static_cast<unsigned long long>(len)) +
                                              " bytes, more than its data holds (" + thousands(static_cast<unsigned long long>(have)) + ")");
      buffer_len.push_back(len);
    }
  }
  struct View {
    double len, stride;
  };
  std::vector<View> views;
  if (const Json* vs = list("bufferViews")) {
    for (std::size_t i = 0; i < vs->size(); ++i) {
      const Json& v = (*vs)[i];
      const bool obj = v.is_object();
      const double b = obj ? num(v, "buffer", -1) : -1, off = obj ? num(v, "byteOffset", 0) : -1,
                   len = obj ? num(v, "byteLength", -1) : -1, stride = obj ? num(v, "byteStride", 0) : -1;
      if (!(b >= 0 && b < static_cast<double>(buffer_len.size())) || !(off >= 0 && len >= 0 && stride >= 0) ||
          off + len > buffer_len[static_cast<std::size_t>(b)])
        return Error(ErrorKind::BadInput, field("bufferViews", i, "byteLength") + ": the view does not lie inside a buffer");
      views.push_back({len, stride});
    }
  }
  auto inView = [&](const Json& o, const std::string& where, double items, double item_bytes) -> Status {
    const double v = num(o, "bufferView", -1), off = num(o, "byteOffset", 0);
    if (!(v >= 0 && v < static_cast<double>(views.size())))
      return Error(ErrorKind::BadInput, where + ".bufferView: no such buffer view");
    const View& view = views[static_cast<std::size_t>(v)];
    const double stride = view.stride > 0 ? view.stride : item_bytes;
    if (!(off >= 0) || (items > 0 && off + (items - 1) * stride + item_bytes > view.len))
      return Error(ErrorKind::BadInput, where + ": " + thousands(static_cast<unsigned long long>(items)) +
                                            " elements, more than its buffer view holds");
    return {};
  };
  if (const Json* as = list("accessors")) {
    for (std::size_t i = 0; i < as->size(); ++i) {
      const Json& a = (*as)[i];
      const std::string at = path + ": accessors[" + std::to_string(i) + "]";
      if (!a.is_object()) return Error(ErrorKind::BadInput, at + ": expected an object");
      const double n = num(a, "count", -1);
      if (!(n >= 0 && n <= static_cast<double>(3 * kMaxMeshTriangles)))
        return Error(ErrorKind::BadInput, at + ".count: must be in [0, " + thousands(3 * kMaxMeshTriangles) + "]");
      // Bytes of one element: the component's size times the components of the type.
      const double component = num(a, "componentType", 0);
      const double csize = component == 5120 || component == 5121 ? 1 : component == 5122 || component == 5123 ? 2 : 4;
      const std::string type = a.contains("type") && a["type"].is_string() ? a["type"].get<std::string>() : "";
      const double comps = type == "VEC2" ? 2 : type == "VEC3" ? 3 : type == "VEC4" || type == "MAT2" ? 4
                         : type == "MAT3" ? 9 : type == "MAT4" ? 16 : 1;
      if (a.contains("bufferView"))
        if (Status st = inView(a, at, n, csize * comps); !st) return st;
      // Sparse values replace some elements: indices and values must lie in views of their own
      // (assimp reads them without checking).
      if (auto sp = a.find("sparse"); sp != a.end()) {
        const std::string w = at + ".sparse";
        const double sc = sp->is_object() ? num(*sp, "count", -1) : -1;
        if (!(sc >= 1 && sc <= n)) return Error(ErrorKind::BadInput, w + ".count: must be in [1, the accessor's count]");
        auto ix = sp->find("indices"), vs = sp->find("values");
        if (ix == sp->end() || vs == sp->end() || !ix->is_object() || !vs->is_object())
          return Error(ErrorKind::BadInput, w + ": needs indices and values");
        const double ic = num(*ix, "componentType", 0);
        if (ic != 5121 && ic != 5123 && ic != 5125)
          return Error(ErrorKind::BadInput, w + ".indices.componentType: must be 5121, 5123 or 5125");
        if (Status st = inView(*ix, w + ".indices", sc, ic == 5121 ? 1 : ic == 5123 ? 2 : 4); !st) return st;
        if (Status st = inView(*vs, w + ".values", sc, csize * comps); !st) return st;
      }
    }
  }
  if (const Json* ns = list("nodes")) {
    const std::size_t n = ns->size();
    std::vector<std::size_t> parent(n, n);
    for (std::size_t i = 0; i < n; ++i) {
      if (!(*ns)[i].is_object()) continue;
      auto c = (*ns)[i].find("children");
      if (c == (*ns)[i].end() || !c->is_array()) continue;
      for (const Json& k : *c) {
        const double x = k.is_number() ? k.get<double>() : -1;
        if (!(x >= 0 && x < static_cast<double>(n)) || parent[static_cast<std::size_t>(x)] != n || static_cast<std::size_t>(x) == i)
          return Error(ErrorKind::BadInput, field("nodes", i, "children") + ": the nodes do not form a tree (a child that does not exist, or has two parents)");
        parent[static_cast<std::size_t>(x)] = i;
      }
    }
    // Each node has at most one parent now; depth from the roots, once per node. A node never
    // reached lies on a cycle; a deep chain would overflow assimp's recursive node import.
    constexpr std::size_t kMaxDepth = 1000;
    std::vector<std::size_t> depth(n, 0), stack;
    for (std::size_t i = 0; i < n; ++i) {
      if (depth[i] != 0) continue;
      std::size_t at = i;
      stack.clear();
      while (depth[at] == 0 && parent[at] != n && stack.size() <= n) {
        stack.push_back(at);
        at = parent[at];
      }
      if (stack.size() > n || (depth[at] == 0 && parent[at] != n))
        return Error(ErrorKind::BadInput, field("nodes", i, "children") + ": the nodes form a cycle");
      std::size_t d = depth[at] == 0 ? 1 : depth[at];
      depth[at] = d;
      for (auto it = stack.rbegin(); it != stack.rend(); ++it) depth[*it] = ++d;
      if (d > kMaxDepth)
        return Error(ErrorKind::BadInput, field("nodes", i, "children") + ": nodes nested " + std::to_string(d) +
                                              " deep, more than the limit of " + std::to_string(kMaxDepth));
    }
  }
  return {};
}

Status scanGltf(const std::string& path, std::uintmax_t size, bool binary, const std::vector<std::string>& roots) {
  auto parse = [&](const std::string& text) -> std::optional<Json> {
    Json j = Json::parse(text, nullptr, /*allow_exceptions=*/false);
    if (j.is_discarded()) return std::nullopt;
    return j;
  };
  if (!binary) {
    auto text = readFile(path, kMaxMeshBytes);
    if (!text.ok()) return text.error();
    auto j = parse(text.value());
    if (!j) return bad(path, "not a glTF file (its JSON does not parse)");
    return scanGltfJson(path, *j, 0, roots);
  }
  // GLB: a 12-byte header (magic, version, length), a JSON chunk, an optional BIN chunk.
  const std::string h = head(path, 20);
  std::uint32_t word[5] = {};
  if (h.size() < 20 || h.compare(0, 4, "glTF") != 0) return bad(path, "not a binary glTF file (no glTF header)");
  std::memcpy(word, h.data(), 20);
  if (word[1] != 2) return bad(path, "binary glTF version " + std::to_string(word[1]) + " (reel reads glTF 2.0)");
  if (word[2] != size) return bad(path, "its header gives a length of " + thousands(word[2]) + " bytes, the file has " + thousands(size));
  const std::uintmax_t json_len = word[3];
  if (word[4] != 0x4E4F534Au || 20 + json_len > size) return bad(path, "the first chunk is not JSON, or passes the end of the file");
  std::uintmax_t bin = 0;
  if (20 + json_len + 8 <= size) {
    const std::string all = head(path, static_cast<std::size_t>(20 + json_len + 8));
    std::uint32_t chunk[2] = {};
    std::memcpy(chunk, all.data() + 20 + json_len, 8);
    if (chunk[1] != 0x004E4942u) return bad(path, "the second chunk is not BIN");
    if (20 + json_len + 8 + chunk[0] > size) return bad(path, "the BIN chunk passes the end of the file");
    bin = chunk[0];
  }
  auto j = parse(head(path, static_cast<std::size_t>(20 + json_len)).substr(20));
  if (!j) return bad(path, "not a glTF file (its JSON chunk does not parse)");
  return scanGltfJson(path, *j, bin, roots);
}

}  // namespace

Status scanMesh(const std::string& path, const std::vector<std::string>& roots) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return bad(path, "not a regular file");
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) return bad(path, "cannot read: " + ec.message());
  if (size > kMaxMeshBytes) return bad(path, "file is " + thousands(size) + " bytes, more than the limit of " + thousands(kMaxMeshBytes));
  std::string ext = fs::path(path).extension().string();
  for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".obj") return scanObj(path);
  if (ext == ".ply") return scanPly(path, size);
  if (ext == ".stl") return scanStl(path, size);
  if (ext == ".gltf" || ext == ".glb") return scanGltf(path, size, ext == ".glb", roots);
  return bad(path, "unsupported mesh type \"" + ext + "\" (.obj, .ply, .stl, .gltf, .glb)");
}

}  // namespace reel::io
