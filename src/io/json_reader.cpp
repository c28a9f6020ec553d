#include "io/json_reader.h"

#include <algorithm>
#include <cmath>

#include "core/format.h"

namespace reel::io {

void Diagnostics::error(const std::string& path, const std::string& message) {
  lines_.push_back(file_ + ": " + (path.empty() ? "/" : path) + ": " + message);
}

namespace {

std::size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> prev(b.size() + 1), cur(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t sub = prev[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1);
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, sub});
    }
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

std::string inQuotes(const std::string& s) { return "\"" + s + "\""; }

}  // namespace

std::string nearest(const std::string& word, const std::vector<std::string>& candidates) {
  std::string best;
  std::size_t best_d = std::string::npos;
  for (const auto& c : candidates) {
    const std::size_t d = editDistance(word, c);
    if (d < best_d) {
      best_d = d;
      best = c;
    }
  }
  // A typo: at most a third of the word (and at least 2 edits) away.
  const std::size_t allowed = std::max<std::size_t>(2, word.size() / 3);
  return best_d <= allowed ? best : std::string();
}

bool Range::contains(double x) const {
  if (lo_open ? !(x > lo) : !(x >= lo)) return false;
  if (hi_open ? !(x < hi) : !(x <= hi)) return false;
  return true;
}

std::string Range::describe() const {
  const bool has_lo = std::isfinite(lo), has_hi = std::isfinite(hi);
  if (has_lo && has_hi)
    return "must be in " + std::string(lo_open ? "(" : "[") + formatNumber(lo, 6) + ", " + formatNumber(hi, 6) +
           (hi_open ? ")" : "]");
  if (has_lo) return std::string("must be ") + (lo_open ? "> " : ">= ") + formatNumber(lo, 6);
  if (has_hi) return std::string("must be ") + (hi_open ? "< " : "<= ") + formatNumber(hi, 6);
  return "must be finite";
}

std::string typeName(const Json& j) {
  if (j.is_array()) return "a list of " + std::to_string(j.size());
  if (j.is_object()) return "an object";
  if (j.is_string()) return "the string " + inQuotes(j.get<std::string>());
  if (j.is_boolean()) return j.get<bool>() ? "true" : "false";
  if (j.is_null()) return "null";
  if (j.is_number()) return formatNumber(j.get<double>(), 6);
  return j.type_name();
}

std::string childPath(const std::string& path, const std::string& key) {
  std::string k;
  for (char c : key) {  // JSON Pointer escapes (RFC 6901)
    if (c == '~') k += "~0";
    else if (c == '/') k += "~1";
    else k += c;
  }
  return path + "/" + k;
}

std::string childPath(const std::string& path, std::size_t index) {
  return path + "/" + std::to_string(index);
}

std::optional<double> readNumber(const Json& j, const std::string& path, Diagnostics& d, Range r) {
  if (!j.is_number()) {
    d.error(path, "expected a number, got " + typeName(j));
    return std::nullopt;
  }
  const double x = j.get<double>();
  if (!std::isfinite(x)) {
    d.error(path, "must be a finite number");
    return std::nullopt;
  }
  if (!r.contains(x)) {
    d.error(path, r.describe() + ", got " + formatNumber(x, 6));
    return std::nullopt;
  }
  return x;
}

std::optional<long long> readInteger(const Json& j, const std::string& path, Diagnostics& d,
                                     long long lo, long long hi) {
  long long v = 0;
  if (j.is_number_integer()) {
    v = j.get<long long>();
  } else if (j.is_number_float() && std::isfinite(j.get<double>()) &&
             j.get<double>() == std::floor(j.get<double>()) && std::abs(j.get<double>()) < 9e18) {
    v = static_cast<long long>(j.get<double>());
  } else {
    d.error(path, "expected an integer, got " + typeName(j));
    return std::nullopt;
  }
  if (j.is_number_unsigned() && j.get<unsigned long long>() > 9000000000000000000ull) v = hi + 1;
  if (v < lo || v > hi) {
    d.error(path, "must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                      "], got " + typeName(j));
    return std::nullopt;
  }
  return v;
}

std::optional<Vec3> readVec3(const Json& j, const std::string& path, Diagnostics& d, Range r) {
  if (!j.is_array() || j.size() != 3) {
    d.error(path, "expected a list of 3 numbers, got " + typeName(j));
    return std::nullopt;
  }
  Vec3 out;
  bool good = true;
  for (std::size_t i = 0; i < 3; ++i) {
    auto v = readNumber(j[i], childPath(path, i), d, r);
    if (v) out[static_cast<Eigen::Index>(i)] = *v; else good = false;
  }
  if (!good) return std::nullopt;
  return out;
}

Obj::Obj(const Json& j, std::string path, Diagnostics& d) : path_(std::move(path)), d_(&d) {
  if (j.is_object())
    j_ = &j;
  else
    d.error(path_, "expected an object, got " + typeName(j));
}

const Json* Obj::get(const std::string& key, bool required) {
  known_.push_back(key);
  if (!j_) return nullptr;
  auto it = j_->find(key);
  if (it == j_->end()) {
    if (required) d_->error(childPath(path_, key), "missing required key");
    return nullptr;
  }
  return &*it;
}

bool Obj::has(const std::string& key) { return get(key, false) != nullptr; }
const Json* Obj::raw(const std::string& key) { return get(key, false); }

std::optional<double> Obj::number(const std::string& key, Range r, bool required) {
  const Json* j = get(key, required);
  if (!j) return std::nullopt;
  return readNumber(*j, childPath(path_, key), *d_, r);
}

double Obj::number(const std::string& key, double def, Range r) {
  return number(key, r, false).value_or(def);
}

std::optional<long long> Obj::integer(const std::string& key, long long lo, long long hi,
                                      bool required) {
  const Json* j = get(key, required);
  if (!j) return std::nullopt;
  return readInteger(*j, childPath(path_, key), *d_, lo, hi);
}

int Obj::integer(const std::string& key, int def, int lo, int hi) {
  return static_cast<int>(integer(key, static_cast<long long>(lo), static_cast<long long>(hi), false)
                              .value_or(def));
}

bool Obj::boolean(const std::string& key, bool def) {
  const Json* j = get(key, false);
  if (!j) return def;
  if (!j->is_boolean()) {
    d_->error(childPath(path_, key), "expected true or false, got " + typeName(*j));
    return def;
  }
  return j->get<bool>();
}

std::optional<std::string> Obj::string(const std::string& key, bool required) {
  const Json* j = get(key, required);
  if (!j) return std::nullopt;
  if (!j->is_string()) {
    d_->error(childPath(path_, key), "expected a string, got " + typeName(*j));
    return std::nullopt;
  }
  return j->get<std::string>();
}

std::string Obj::choice(const std::string& key, const std::string& def,
                        const std::vector<std::string>& options) {
  auto s = string(key);
  if (!s) return def;
  if (std::find(options.begin(), options.end(), *s) != options.end()) return *s;
  std::string list;
  for (const auto& o : options) list += (list.empty() ? "" : ", ") + o;
  const std::string near = nearest(*s, options);
  d_->error(childPath(path_, key), "unknown value " + inQuotes(*s) +
                                       (near.empty() ? "" : "; did you mean " + inQuotes(near) + "?") +
                                       " (one of: " + list + ")");
  return def;
}

std::optional<Vec3> Obj::vec3(const std::string& key, Range r, bool required) {
  const Json* j = get(key, required);
  if (!j) return std::nullopt;
  return readVec3(*j, childPath(path_, key), *d_, r);
}

Vec3 Obj::vec3(const std::string& key, const Vec3& def, Range r) {
  return vec3(key, r, false).value_or(def);
}

void Obj::finish() {
  if (!j_) return;
  for (auto it = j_->begin(); it != j_->end(); ++it) {
    if (std::find(known_.begin(), known_.end(), it.key()) != known_.end()) continue;
    const std::string near = nearest(it.key(), known_);
    d_->error(childPath(path_, it.key()),
              "unknown key" + (near.empty() ? std::string() : "; did you mean " + inQuotes(near) + "?"));
  }
}

}  // namespace reel::io
