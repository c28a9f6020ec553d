#include "io/test_suite.h"

#include <cstdio>
#include <filesystem>
#include <set>

#include "io/files.h"
#include "io/json_reader.h"

namespace reel::io {
namespace {

namespace fs = std::filesystem;

// "WxH", 16..16384 each (as `--size`).
void readSize(Obj& o, int& w, int& h) {
  const auto s = o.string("size");
  if (!s) return;
  int a = 0, b = 0, used = 0;
  char x = 0;
  if (std::sscanf(s->c_str(), "%d%c%d%n", &a, &x, &b, &used) != 3 || x != 'x' || used != static_cast<int>(s->size()) ||
      a < 16 || b < 16 || a > 16384 || b > 16384) {
    o.diag().error(childPath(o.path(), "size"), "expected \"WxH\" with 16..16384 pixels each, got \"" + *s + "\"");
    return;
  }
  w = a;
  h = b;
}

int readSamples(Obj& o, int def) {
  const auto s = o.integer("samples", 1, 4);
  if (!s) return def;
  if (*s == 3) {
    o.diag().error(childPath(o.path(), "samples"), "MSAA samples must be 1, 2 or 4, got 3");
    return def;
  }
  return static_cast<int>(*s);
}

// The limits a case or the suite sets, over `t`.
void readTolerance(const Json& j, const std::string& path, Diagnostics& d, Tolerance& t) {
  Obj o(j, path, d);
  if (!o.ok()) return;
  t.threshold = o.integer("threshold", t.threshold, 0, 255);
  t.max_mean = o.number("max_mean", t.max_mean, Range::closed(0.0, 255.0));
  t.max_fraction = o.number("max_fraction", t.max_fraction, Range::closed(0.0, 1.0));
  t.min_ssim = o.number("min_ssim", t.min_ssim, Range::closed(-1.0, 1.0));
  t.max_flip = o.number("max_flip", t.max_flip, Range::closed(0.0, 1.0));
  o.finish();
}

bool safeName(const std::string& s) {
  if (s.empty() || s.size() > 100 || s[0] == '.') return false;
  for (char c : s)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.')) return false;
  return true;
}

// A list of at least one and at most kMaxCaseFrames values, each read by `one`.
template <class T, class F>
std::vector<T> readList(const Json& j, const std::string& path, Diagnostics& d, F&& one) {
  std::vector<T> out;
  if (!j.is_array() || j.empty() || j.size() > kMaxCaseFrames) {
    d.error(path, "expected a list of 1 to " + std::to_string(kMaxCaseFrames) + " values, got " +
                      (j.is_array() ? std::to_string(j.size()) + " values" : typeName(j)));
    return out;
  }
  for (std::size_t i = 0; i < j.size(); ++i)
    if (auto v = one(j[i], childPath(path, i))) out.push_back(static_cast<T>(*v));
  return out;
}

void readCase(const Json& j, const std::string& path, const fs::path& base, const TestCase& defaults, Diagnostics& d,
              std::set<std::string>& names, std::vector<TestCase>& out) {
  Obj o(j, path, d);
  if (!o.ok()) return;
  TestCase c = defaults;
  c.where = path;
  if (auto n = o.string("name", true)) {
    if (!safeName(*n))
      d.error(childPath(path, "name"), "\"" + *n + "\" cannot name a file: use letters, digits, '_', '-' and '.' (not first), at most 100");
    else if (!names.insert(*n).second)
      d.error(childPath(path, "name"), "a second case named \"" + *n + "\" (names must be unique: they name the golden files)");
    c.name = *n;
  }
  if (auto s = o.string("scene", true)) {
    const fs::path p = fs::path(*s).is_absolute() ? fs::path(*s) : base / *s;
    c.scene = p.lexically_normal().string();
    std::error_code ec;
    if (!fs::exists(p, ec))
      d.error(childPath(path, "scene"), "no such file: " + c.scene);
    else if (!fs::is_regular_file(p, ec))
      d.error(childPath(path, "scene"), c.scene + " is " + kindInWords(fs::status(p, ec)) + ", not a scene file");
  }
  const Json* frames = o.raw("frames");
  const Json* times = o.raw("times");
  if (frames && times)
    d.error(path, "give \"frames\" or \"times\", not both");
  else if (!frames && !times)
    d.error(path, "missing \"frames\" (a list of frame numbers) or \"times\" (a list of times, s)");
  if (frames)
    c.frames = readList<int>(*frames, childPath(path, "frames"), d, [&](const Json& v, const std::string& p) {
      return readInteger(v, p, d, 0, 100000000);
    });
  if (times)
    c.times = readList<double>(*times, childPath(path, "times"), d, [&](const Json& v, const std::string& p) {
      return readNumber(v, p, d, Range::closed(0.0, 1e7));
    });
  readSize(o, c.width, c.height);
  c.samples = readSamples(o, c.samples);
  if (auto s = o.integer("seed", 0, (1LL << 53) - 1)) c.seed = static_cast<std::uint64_t>(*s);
  if (const Json* t = o.raw("tolerance")) readTolerance(*t, childPath(path, "tolerance"), d, c.tolerance);
  o.finish();
  out.push_back(std::move(c));
}

}  // namespace

Result<TestSuite> loadTestSuite(const std::string& path) {
  std::error_code ec;
  if (fs::exists(path, ec) && !fs::is_regular_file(path, ec))
    return Error(ErrorKind::BadInput, path + " is " + kindInWords(fs::status(path, ec)) + ", not a test suite");
  auto text = readFile(path, kMaxSuiteBytes);
  if (!text.ok()) return text.error();
  auto root = parseJson(text.value(), path);
  if (!root.ok()) return root.error();
  Diagnostics d(path);
  Obj o(root.value(), "", d);
  if (!o.ok()) return Error(ErrorKind::BadInput, d.lines());
  TestSuite s;
  s.file = path;
  const fs::path base = fs::path(path).parent_path();
  if (auto f = o.string("format", true); f && *f != "reel-test/1")
    d.error("/format", "unsupported format \"" + *f + "\" (this reel reads \"reel-test/1\")");
  s.name = o.string("name").value_or(fs::path(path).stem().string());
  const std::string goldens = o.string("goldens").value_or(fs::path(path).stem().string());
  s.goldens = (fs::path(goldens).is_absolute() ? fs::path(goldens) : base / goldens).lexically_normal().string();
  TestCase defaults;
  readSize(o, defaults.width, defaults.height);
  defaults.samples = readSamples(o, 0);
  if (const Json* t = o.raw("tolerance")) readTolerance(*t, "/tolerance", d, defaults.tolerance);
  if (const Json* cases = o.raw("cases")) {
    if (!cases->is_array() || cases->empty() || cases->size() > kMaxSuiteCases)
      d.error("/cases", "expected a list of 1 to " + std::to_string(kMaxSuiteCases) + " cases, got " +
                            (cases->is_array() ? std::to_string(cases->size()) + " cases" : typeName(*cases)));
    else {
      std::set<std::string> names;
      for (std::size_t i = 0; i < cases->size(); ++i) readCase((*cases)[i], childPath("/cases", i), base, defaults, d, names, s.cases);
    }
  } else {
    d.error("/cases", "missing: the list of cases ({\"name\", \"scene\", \"frames\" or \"times\"})");
  }
  o.finish();
  if (!d.empty()) return Error(ErrorKind::BadInput, d.lines());
  return s;
}

}  // namespace reel::io
