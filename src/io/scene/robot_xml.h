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

// The numbers of attribute value v (of `key` in e), refused unless finite and their count in [lo, hi].
inline std::vector<double> parseNumbers(const XmlElement& e, const std::string& key, const std::string& v, std::size_t lo,
                                        std::size_t hi) {
  std::istringstream in(v);
  in.imbue(std::locale::classic());
  std::vector<double> out;
  double x = 0;
  while (in >> x) out.push_back(x);
  in.clear();
  std::string rest;
  if (in >> rest || out.size() < lo || out.size() > hi)
    refuse(e, "<" + e.name + "> " + key + "=\"" + v + "\": expected " +
                  (lo == hi ? std::to_string(lo) + (lo == 1 ? " number" : " numbers") : std::to_string(lo) + " to " + std::to_string(hi) + " numbers"));
  for (double d : out) {
    if (!std::isfinite(d)) refuse(e, "<" + e.name + "> " + key + ": numbers must be finite");
    if (std::abs(d) > 1e9) {
      std::ostringstream got;
      got.imbue(std::locale::classic());
      got << d;
      refuse(e, "<" + e.name + "> " + key + ": " + got.str() + " is beyond the limit of ±1e9");
    }
  }
  return out;
}

// A link's mass (kg) and inertia (kg·m², any axes) as the articulated body takes them: mass in
// (0, 1e6], inertia finite with its diagonal positive and below 1e12; refused at element e (the
// geom or inertial they came from, so the message has its line).
inline void requireUsableMass(const XmlElement& e, double mass, const Mat3& inertia) {
  if (mass > 0 && mass <= 1e6 && inertia.allFinite() && inertia.diagonal().minCoeff() > 0 && inertia.diagonal().maxCoeff() < 1e12)
    return;
  std::ostringstream m;
  m.imbue(std::locale::classic());
  m << "<" << e.name << "> gives no usable mass and inertia (mass " << mass << " kg, inertia diagonal " << inertia(0, 0) << ", "
    << inertia(1, 1) << ", " << inertia(2, 2) << " kg·m²; the mass must be in (0, 1e6] kg and the inertia positive and below 1e12)";
  refuse(e, m.str());
}

// n numbers of attribute `key`; `def` when it is absent (empty `def`: required).
inline std::vector<double> numbers(const XmlElement& e, const std::string& key, std::size_t n, const std::vector<double>& def) {
  const std::string* v = e.attribute(key);
  if (!v) {
    if (def.empty()) refuse(e, "<" + e.name + "> needs " + key);
    return def;
  }
  return parseNumbers(e, key, *v, n, n);
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

// Every number of attribute `key` (required): 1 to `most` of them.
inline std::vector<double> numberList(const XmlElement& e, const std::string& key, std::size_t most) {
  const std::string* v = e.attribute(key);
  if (!v) refuse(e, "<" + e.name + "> needs " + key);
  return parseNumbers(e, key, *v, 1, most);
}

}  // namespace reel::io
