// The PLY part of the mesh scan (io/mesh_scan.h): the header against the caps, the body walked
// against the header, and a binary body Debian's assimp would misread rewritten as ASCII.
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>

#include "io/mesh_scan.h"
#include "io/mesh_scan_util.h"

namespace reel::io {
namespace scan {
namespace {

// PLY (Turk 1994): the header declares every element's count and layout, and the body is
// walked against it: ASCII values must be numbers and binary records must end within the file.
// What the walk refuses would otherwise reach assimp's reader, which leaks what it has read when
// it throws on a malformed body (found by fuzz_mesh) and has had overflows on binary ones.
struct PlyProperty {
  int size = 0;        // bytes of a scalar, or of a list's items
  int count_size = 0;  // a list: bytes of its count; 0: a scalar
  bool corners = false;  // a face's vertex indices: 3 or more (assimp aborts on an empty face)
  char kind = 'f';       // its values: 'i' signed, 'u' unsigned integers, 'f' floating point
};
struct PlyElement {
  std::string name;
  unsigned long long count = 0;
  std::vector<PlyProperty> props;
  std::size_t line = 0;
};

char plyTypeKind(std::string_view t) {
  if (t == "float" || t == "float32" || t == "double" || t == "float64") return 'f';
  if (t == "uchar" || t == "uint8" || t == "ushort" || t == "uint16" || t == "uint" || t == "uint32") return 'u';
  return 'i';
}

int plyTypeSize(std::string_view t) {
  if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
  if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
  if (t == "int" || t == "uint" || t == "int32" || t == "uint32" || t == "float" || t == "float32") return 4;
  if (t == "double" || t == "float64") return 8;
  return 0;
}


// ASCII: one element per line (as assimp reads them), holding exactly its values.
Status walkAsciiPly(const std::string& path, const std::string& body, std::size_t first_line, const std::vector<PlyElement>& elements) {
  std::size_t pos = 0, line_no = first_line - 1;
  auto nextLine = [&]() -> std::vector<std::string_view> {
    while (pos < body.size()) {
      std::size_t nl = body.find('\n', pos);
      if (nl == std::string::npos) nl = body.size();
      const std::string_view line(body.data() + pos, nl - pos);
      pos = nl + 1;
      ++line_no;
      auto w = words(line);
      if (!w.empty()) return w;
    }
    return {};
  };
  for (const PlyElement& e : elements)
    for (unsigned long long k = 0; k < e.count; ++k) {
      const auto w = nextLine();
      const std::string at = path + ":" + std::to_string(line_no) + ": " + e.name + " " + std::to_string(k);
      if (w.empty()) return Error(ErrorKind::BadInput, path + ": the file ends before " + e.name + " " + std::to_string(k));
      std::size_t t = 0;
      for (const PlyProperty& p : e.props) {
        if (t >= w.size()) return Error(ErrorKind::BadInput, at + ": too few values");
        unsigned long long items = 0;
        if (p.count_size > 0) {
          const auto n = count(w[t]);
          if (!n) return Error(ErrorKind::BadInput, at + ": expected a list's length, got \"" + std::string(w[t].substr(0, 20)) + "\"");
          items = *n;
          if (p.corners && items < 3)
            return bad(path, "face " + std::to_string(k) + " has " + std::to_string(items) + " corners; a face needs 3 or more");
          ++t;
        } else {
          items = 1;
        }
        if (items > w.size() - t) return Error(ErrorKind::BadInput, at + ": too few values");
        for (unsigned long long i = 0; i < items; ++i, ++t)
          if (!isNumber(w[t])) return Error(ErrorKind::BadInput, at + ": expected a number, got \"" + std::string(w[t].substr(0, 20)) + "\"");
      }
      if (t != w.size()) return Error(ErrorKind::BadInput, at + ": " + std::to_string(w.size()) + " values, the header gives " + std::to_string(t));
    }
  return {};
}

Status walkBinaryPly(const std::string& path, const std::string& body, bool big_endian, const std::vector<PlyElement>& elements) {
  std::size_t pos = 0;
  for (const PlyElement& e : elements)
    for (unsigned long long k = 0; k < e.count; ++k)
      for (const PlyProperty& p : e.props) {
        std::uint64_t items = 1;
        if (p.count_size > 0) {
          if (pos + static_cast<std::size_t>(p.count_size) > body.size()) return bad(path, e.name + " " + std::to_string(k) + ": the file ends inside it");
          unsigned char b[8] = {};
          std::memcpy(b, body.data() + pos, static_cast<std::size_t>(p.count_size));
          items = 0;
          for (int i = 0; i < p.count_size; ++i) items |= std::uint64_t{b[big_endian ? p.count_size - 1 - i : i]} << (8 * i);
          pos += static_cast<std::size_t>(p.count_size);
          if (p.corners && items < 3)
            return bad(path, "face " + std::to_string(k) + " has " + std::to_string(items) + " corners; a face needs 3 or more");
        }
        if (items > body.size() - pos || items * static_cast<std::uint64_t>(p.size) > body.size() - pos)
          return bad(path, e.name + " " + std::to_string(k) + ": the file ends inside it");
        pos += static_cast<std::size_t>(items) * static_cast<std::size_t>(p.size);
      }
  return {};
}

// A PLY header: its format (0 ASCII, 1 binary little-endian, 2 big-endian), elements, where the
// body starts, and its text.
struct PlyHeader {
  int format = -1;
  std::vector<PlyElement> elements;
  std::size_t body_at = 0;
  std::uintmax_t body_bytes = 0;
  std::string text;  // the first MiB of the file
  std::size_t end = 0;  // where "\nend_header" starts
};

Status readPlyHeader(const std::string& path, std::uintmax_t size, PlyHeader& out) {
  constexpr std::size_t kMaxHeader = 1u << 20;
  out.text = head(path, kMaxHeader);
  const std::string& text = out.text;
  if (text.rfind("ply\n", 0) != 0 && text.rfind("ply\r\n", 0) != 0) return bad(path, "not a PLY file (it must start with the line \"ply\")");
  // The header ends at a line that is exactly "end_header" ("end_headerel" is not one).
  std::size_t end = text.find("\nend_header");
  while (end != std::string::npos && trim(std::string_view(text).substr(end + 11, text.find('\n', end + 1) - end - 11)).size() != 0)
    end = text.find("\nend_header", end + 1);
  if (end == std::string::npos)
    return bad(path, size > kMaxHeader ? "the PLY header does not end within its first MiB (no end_header)"
                                       : "the PLY header does not end (no end_header line)");
  std::size_t body_at = text.find('\n', end + 1);
  body_at = body_at == std::string::npos ? text.size() : body_at + 1;
  const std::uintmax_t body_bytes = size - body_at;
  int& format = out.format;
  std::vector<PlyElement>& elements = out.elements;
  out.body_at = body_at;
  out.body_bytes = body_bytes;
  out.end = end;
  std::size_t line_no = 1, pos = 0;
  while (pos < end + 1) {
    const std::size_t nl = text.find('\n', pos);
    const std::string_view line(text.data() + pos, std::min(nl, end + 1) - pos);
    pos = nl + 1;
    const auto w = words(line);
    const std::string at = path + ":" + std::to_string(line_no++);
    if (w.empty() || w[0] == "ply" || w[0] == "comment" || w[0] == "obj_info") continue;
    if (w[0] == "format") {
      if (w.size() < 2 || (w[1] != "ascii" && w[1] != "binary_little_endian" && w[1] != "binary_big_endian"))
        return Error(ErrorKind::BadInput, at + ": unknown PLY format (ascii, binary_little_endian or binary_big_endian)");
      format = w[1] == "ascii" ? 0 : w[1] == "binary_little_endian" ? 1 : 2;
    } else if (w[0] == "element") {
      const auto n = w.size() == 3 ? count(w[2]) : std::nullopt;
      if (!n) return Error(ErrorKind::BadInput, at + ": expected \"element NAME COUNT\"");
      const bool faces = w[1] == "face";
      const std::size_t cap = faces ? kMaxMeshTriangles : kMaxMeshVertices;
      if (*n > cap)
        return Error(ErrorKind::BadInput, at + ": declares " + thousands(*n) + " " + std::string(w[1]) +
                                              " elements, more than the limit of " + thousands(cap));
      if (faces && std::none_of(elements.begin(), elements.end(), [](const PlyElement& e) { return e.name == "vertex"; }))
        return Error(ErrorKind::BadInput, at + ": the faces come before the vertices they name");
      elements.push_back({std::string(w[1]), *n, {}, line_no - 1});
    } else if (w[0] == "property") {
      if (elements.empty()) return Error(ErrorKind::BadInput, at + ": a property before any element");
      const bool list = w.size() == 5 && w[1] == "list";
      if (!list && w.size() != 3) return Error(ErrorKind::BadInput, at + ": expected \"property TYPE NAME\" or \"property list COUNT_TYPE TYPE NAME\"");
      const std::string_view type = list ? w[3] : w[1];
      if (plyTypeSize(type) == 0 || (list && plyTypeSize(w[2]) == 0))
        return Error(ErrorKind::BadInput, at + ": unknown property type \"" + std::string(plyTypeSize(type) == 0 ? type : w[2]) + "\"");
      const bool corners = list && elements.back().name == "face" && (w[4] == "vertex_indices" || w[4] == "vertex_index");
      elements.back().props.push_back({plyTypeSize(type), list ? plyTypeSize(w[2]) : 0, corners, plyTypeKind(type)});
    }
    // Any other line (a Blender export's "Created by ...") is read past, as PLY readers do: it
    // declares nothing the body's layout depends on. But a keyword with more after it
    // ("end_headerel") is refused: assimp takes it for the keyword and reads the body elsewhere.
    else if (w[0] != "end_header")
      for (const char* k : {"ply", "format", "element", "property", "comment", "obj_info", "end_header"})
        if (w[0].rfind(k, 0) == 0)
          return Error(ErrorKind::BadInput, at + ": unknown PLY header line \"" + std::string(w[0]).substr(0, 40) + "\"");
  }
  if (format < 0) return bad(path, "the PLY header has no format line");
  // Before reading the body: at least a digit and a separator (ASCII) or the fixed bytes (binary)
  // of each value must fit in it.
  unsigned long long need = 0;
  for (const PlyElement& e : elements) {
    if (e.props.empty() && e.count > 0) return bad(path + ":" + std::to_string(e.line), "element \"" + e.name + "\" has no properties");
    unsigned long long least = 0;
    for (const PlyProperty& p : e.props) least += format == 0 ? 2 : static_cast<unsigned long long>(p.count_size > 0 ? p.count_size : p.size);
    need += e.count * least;  // each term below 6e6 * 8 * props: no overflow
    if (need - (format == 0 && need > 0 ? 1 : 0) > body_bytes)  // (ASCII: the last value needs no separator)
      return Error(ErrorKind::BadInput, path + ":" + std::to_string(e.line) + ": declares " + thousands(e.count) + " " + e.name +
                                            " elements, more than its " + thousands(body_bytes) + " bytes of data can hold");
  }
  return {};
}

std::string plyBody(const std::string& path, const PlyHeader& h) {
  std::ifstream in(path, std::ios::binary);
  in.seekg(static_cast<std::streamoff>(h.body_at));
  std::string body(static_cast<std::size_t>(h.body_bytes), '\0');
  in.read(body.data(), static_cast<std::streamsize>(body.size()));
  return body;
}

}  // namespace

Status scanPly(const std::string& path, std::uintmax_t size) {
  // (the format scanners share the helpers of mesh_scan_util.h)
  PlyHeader h;
  if (Status st = readPlyHeader(path, size, h); !st) return st;
  const std::string body = plyBody(path, h);
  const std::size_t body_line =
      static_cast<std::size_t>(std::count(h.text.begin(), h.text.begin() + static_cast<std::ptrdiff_t>(h.body_at), '\n')) + 1;
  return h.format == 0 ? walkAsciiPly(path, body, body_line, h.elements) : walkBinaryPly(path, body, h.format == 2, h.elements);
}

// One binary value of `size` bytes and `kind` at p, as text.
std::string plyValue(const char* p, int size, char kind, bool big_endian) {
  unsigned char b[8] = {};
  for (int i = 0; i < size; ++i) b[i] = static_cast<unsigned char>(p[big_endian ? size - 1 - i : i]);
  std::uint64_t u = 0;
  for (int i = 0; i < size; ++i) u |= std::uint64_t{b[i]} << (8 * i);
  char out[40];
  if (kind == 'f') {
    if (size == 4) {
      float f;
      const auto v = static_cast<std::uint32_t>(u);
      std::memcpy(&f, &v, 4);
      std::snprintf(out, sizeof out, "%.9g", static_cast<double>(f));
    } else {
      double d;
      std::memcpy(&d, &u, 8);
      std::snprintf(out, sizeof out, "%.17g", d);
    }
  } else if (kind == 'u') {
    std::snprintf(out, sizeof out, "%llu", static_cast<unsigned long long>(u));
  } else {
    const int bits = 8 * size;
    const long long s = bits < 64 && (u >> (bits - 1)) ? static_cast<long long>(u) - (1LL << bits) : static_cast<long long>(u);
    std::snprintf(out, sizeof out, "%lld", s);
  }
  return out;
}


}  // namespace scan

std::optional<std::string> plyForAssimp(const std::string& path) {
  using namespace scan;
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  PlyHeader h;
  if (ec || !readPlyHeader(path, size, h).ok() || h.format == 0) return std::nullopt;
  const std::string body = plyBody(path, h);
  if (body.empty() || !std::isspace(static_cast<unsigned char>(body[0]))) return std::nullopt;
  // The header again, as ASCII: every line but the format's kept as it is.
  std::string out;
  for (std::size_t pos = 0; pos < h.end + 1;) {
    const std::size_t nl = h.text.find('\n', pos);
    const std::string line = h.text.substr(pos, nl - pos);
    pos = nl + 1;
    out += words(line).size() > 0 && words(line)[0] == "format" ? std::string("format ascii 1.0") : line;
    out += '\n';
  }
  out += "end_header\n";
  // The body, one element a line (its layout was checked by the scan).
  const bool big = h.format == 2;
  std::size_t at = 0;
  for (const PlyElement& e : h.elements)
    for (unsigned long long k = 0; k < e.count; ++k) {
      for (const PlyProperty& p : e.props) {
        std::uint64_t items = 1;
        if (p.count_size > 0) {
          const std::string n = plyValue(body.data() + at, p.count_size, 'u', big);
          at += static_cast<std::size_t>(p.count_size);
          items = std::stoull(n);
          out += n + ' ';
        }
        for (std::uint64_t i = 0; i < items; ++i, at += static_cast<std::size_t>(p.size))
          out += plyValue(body.data() + at, p.size, p.kind, big) + ' ';
      }
      out.back() = '\n';
    }
  return out;
}

}  // namespace reel::io
