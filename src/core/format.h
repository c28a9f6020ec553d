// Numbers as text, one way everywhere: messages round to a few significant digits, dumps write
// the shortest form that reads back to the same double.
#pragma once

#include <charconv>
#include <cstdio>
#include <string>

namespace reel {

// `digits` significant digits (printf's %g); 0: the shortest round-trip form (std::to_chars).
inline void appendNumber(std::string& out, double x, int digits = 0) {
  char buf[40];
  if (digits <= 0) {
    const auto r = std::to_chars(buf, buf + sizeof buf, x);
    out.append(buf, r.ptr);
    return;
  }
  const int n = std::snprintf(buf, sizeof buf, "%.*g", digits, x);
  out.append(buf, static_cast<std::size_t>(n > 0 ? n : 0));
}

inline std::string formatNumber(double x, int digits = 0) {
  std::string s;
  appendNumber(s, x, digits);
  return s;
}

}  // namespace reel
