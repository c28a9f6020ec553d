// What the robot readers (URDF, MJCF) share: a refusal carrying the element's line, numbers from
// attributes, children by name, rigid frames. Internal to io/scene.
#pragma once

#include <cmath>
#include <initializer_list>
#include <locale>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/types.h"
#include "io/xml.h"

namespace reel::io {

struct Frame {
  Mat3 R = Mat3::Identity();
  Vec3 p{0, 0, 0};
  Frame operator*(const Frame& o) const { return {R * o.R, p + R * o.p}; }
};

class RobotError {
 public:
  RobotError(int line, std::string m) : line_(line), message_(std::move(m)) {}
  Error error() const { return Error(ErrorKind::BadInput, "line " + std::to_string(line_) + ": " + message_); }

 private:
  int line_;
  std::string message_;
};

[[noreturn]] inline void refuse(const XmlElement& e, const std::string& m) { throw RobotError(e.line, m); }

inline std::vector<double> numbers(const XmlElement& e, const std::string& key, std::size_t n, const std::vector<double>& def) {
  const std::string* v = e.attribute(key);
  if (!v) {
    if (def.empty()) refuse(e, "<" + e.name + "> needs " + key);
    return def;
  }
  std::istringstream in(*v);
  in.imbue(std::locale::classic());
  std::vector<double> out;
  double x = 0;
  while (in >> x) out.push_back(x);
  in.clear();
  std::string rest;
  if (in >> rest || out.size() != n)
    refuse(e, "<" + e.name + "> " + key + "=\"" + *v + "\": expected " + std::to_string(n) + (n == 1 ? " number" : " numbers"));
  for (double d : out)
    if (!std::isfinite(d) || std::abs(d) > 1e9) refuse(e, "<" + e.name + "> " + key + ": numbers must be finite");
  return out;
}

inline double number(const XmlElement& e, const std::string& key, std::optional<double> def = std::nullopt) {
  return numbers(e, key, 1, def ? std::vector<double>{*def} : std::vector<double>{})[0];
}

inline const XmlElement* child(const XmlElement& e, const std::string& name) {
  for (const XmlElement& c : e.children)
    if (c.name == name) return &c;
  return nullptr;
}

// Refuses a child element named in neither list (`passed`: read past without effect).
inline void onlyChildren(const XmlElement& e, std::initializer_list<const char*> known, std::initializer_list<const char*> passed) {
  for (const XmlElement& c : e.children) {
    bool ok = false;
    for (const char* k : known) ok = ok || c.name == k;
    for (const char* k : passed) ok = ok || c.name == k;
    if (!ok) refuse(c, "<" + c.name + "> in <" + e.name + "> is outside the supported URDF subset");
  }
}

// Every number of attribute `key` (required), at most `most`.
inline std::vector<double> numberList(const XmlElement& e, const std::string& key, std::size_t most) {
  const std::string* v = e.attribute(key);
  if (!v) refuse(e, "<" + e.name + "> needs " + key);
  std::istringstream in(*v);
  in.imbue(std::locale::classic());
  std::vector<double> out;
  double x = 0;
  while (in >> x) out.push_back(x);
  in.clear();
  std::string rest;
  if (in >> rest || out.empty() || out.size() > most)
    refuse(e, "<" + e.name + "> " + key + "=\"" + *v + "\": expected 1 to " + std::to_string(most) + " numbers");
  for (double d : out)
    if (!std::isfinite(d) || std::abs(d) > 1e9) refuse(e, "<" + e.name + "> " + key + ": numbers must be finite");
  return out;
}

}  // namespace reel::io
