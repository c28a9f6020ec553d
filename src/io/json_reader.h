// Reading validated values out of parsed JSON while collecting every error of a file at once.
// Each error names the JSON path (/bodies/2/springs/7/stiffness) and, for a mistyped key or
// choice, the nearest valid one. nlohmann::json stays inside io.
#pragma once

#include <array>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/types.h"

namespace reel::io {

using Json = nlohmann::json;

// JSON text (comments allowed) as a tree; a syntax error as "file:line:col: reason" and duplicate
// keys with both places, as BadInput (defined with the scene loader).
Result<Json> parseJson(const std::string& text, const std::string& file);

class Diagnostics {
 public:
  explicit Diagnostics(std::string file) : file_(std::move(file)) {}
  void error(const std::string& path, const std::string& message);
  bool empty() const { return lines_.empty(); }
  const std::vector<std::string>& lines() const { return lines_; }
  const std::string& file() const { return file_; }

 private:
  std::string file_;
  std::vector<std::string> lines_;
};

// The candidate closest to `word` by edit distance, or "" when none is close enough to be a typo.
std::string nearest(const std::string& word, const std::vector<std::string>& candidates);

// An allowed interval for a number.
struct Range {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false, hi_open = false;
  static Range any() { return {}; }
  static Range positive() { return {0.0, std::numeric_limits<double>::infinity(), true, false}; }
  static Range nonNegative() { return {0.0, std::numeric_limits<double>::infinity(), false, false}; }
  static Range closed(double a, double b) { return {a, b, false, false}; }
  bool contains(double x) const;
  std::string describe() const;  // e.g. "must be > 0"
};

std::string typeName(const Json& j);
std::string childPath(const std::string& path, const std::string& key);
std::string childPath(const std::string& path, std::size_t index);

// A JSON object being read. Every accessor marks its key as known; finish() reports the keys
// that no accessor asked for, with the nearest known key.
class Obj {
 public:
  Obj(const Json& j, std::string path, Diagnostics& d);
  bool ok() const { return j_ != nullptr; }  // the value was an object
  const std::string& path() const { return path_; }
  Diagnostics& diag() const { return *d_; }

  bool has(const std::string& key);  // present (and marks it known)
  const Json* raw(const std::string& key);  // nullptr when absent
  std::optional<double> number(const std::string& key, Range r = {}, bool required = false);
  double number(const std::string& key, double def, Range r = {});
  std::optional<long long> integer(const std::string& key, long long lo, long long hi,
                                   bool required = false);
  int integer(const std::string& key, int def, int lo, int hi);
  bool boolean(const std::string& key, bool def);
  std::optional<std::string> string(const std::string& key, bool required = false);
  std::string choice(const std::string& key, const std::string& def,
                     const std::vector<std::string>& options);
  std::optional<Vec3> vec3(const std::string& key, Range r = {}, bool required = false);
  Vec3 vec3(const std::string& key, const Vec3& def, Range r = {});
  // A fixed-length list of numbers.
  template <std::size_t N>
  std::optional<std::array<double, N>> numbers(const std::string& key, Range r = {},
                                               bool required = false);
  // A fixed-length list of integers.
  template <std::size_t N>
  std::optional<std::array<long long, N>> integers(const std::string& key, long long lo,
                                                   long long hi, bool required = false);
  void finish();

 private:
  const Json* get(const std::string& key, bool required);
  const Json* j_ = nullptr;
  std::string path_;
  Diagnostics* d_;
  std::vector<std::string> known_;
};

// Free readers of single values at a path (also used for array elements).
std::optional<double> readNumber(const Json& j, const std::string& path, Diagnostics& d, Range r);
std::optional<long long> readInteger(const Json& j, const std::string& path, Diagnostics& d,
                                     long long lo, long long hi);
std::optional<Vec3> readVec3(const Json& j, const std::string& path, Diagnostics& d, Range r);

template <std::size_t N>
std::optional<std::array<double, N>> Obj::numbers(const std::string& key, Range r, bool required) {
  const Json* j = get(key, required);
  if (!j) return std::nullopt;
  const std::string p = childPath(path_, key);
  if (!j->is_array() || j->size() != N) {
    d_->error(p, "expected a list of " + std::to_string(N) + " numbers, got " + typeName(*j));
    return std::nullopt;
  }
  std::array<double, N> out{};
  bool good = true;
  for (std::size_t i = 0; i < N; ++i) {
    auto v = readNumber((*j)[i], childPath(p, i), *d_, r);
    if (v) out[i] = *v; else good = false;
  }
  if (!good) return std::nullopt;
  return out;
}

template <std::size_t N>
std::optional<std::array<long long, N>> Obj::integers(const std::string& key, long long lo,
                                                      long long hi, bool required) {
  const Json* j = get(key, required);
  if (!j) return std::nullopt;
  const std::string p = childPath(path_, key);
  if (!j->is_array() || j->size() != N) {
    d_->error(p, "expected a list of " + std::to_string(N) + " integers, got " + typeName(*j));
    return std::nullopt;
  }
  std::array<long long, N> out{};
  bool good = true;
  for (std::size_t i = 0; i < N; ++i) {
    auto v = readInteger((*j)[i], childPath(p, i), *d_, lo, hi);
    if (v) out[i] = *v; else good = false;
  }
  if (!good) return std::nullopt;
  return out;
}

}  // namespace reel::io
