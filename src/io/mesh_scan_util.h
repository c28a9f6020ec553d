// The text helpers of the mesh scan (io/mesh_scan.*), shared by its format scanners: counts in
// words, lines read in blocks, words and numbers of a line. Internal to io.
#pragma once

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/error.h"

namespace reel::io::scan {

inline std::string thousands(unsigned long long n) {
  std::string s = std::to_string(n);
  for (int i = static_cast<int>(s.size()) - 3; i > 0; i -= 3) s.insert(static_cast<std::size_t>(i), ",");
  return s;
}

inline Error bad(const std::string& path, const std::string& why) { return Error(ErrorKind::BadInput, path + ": " + why); }

// The first `n` bytes of the file (fewer when it is shorter).
inline std::string head(const std::string& path, std::size_t n) {
  std::ifstream in(path, std::ios::binary);
  std::string s(n, '\0');
  in.read(s.data(), static_cast<std::streamsize>(n));
  s.resize(static_cast<std::size_t>(std::max<std::streamsize>(in.gcount(), 0)));
  return s;
}

// Calls line(text, number) for each line (without its end), reading the file in blocks; stops
// when line returns an error.
template <class F>
inline Status forEachLine(const std::string& path, F&& line) {
  std::ifstream in(path, std::ios::binary);
  std::string carry, block(1u << 20, '\0');
  std::size_t number = 0;
  while (in) {
    in.read(block.data(), static_cast<std::streamsize>(block.size()));
    const auto got = static_cast<std::size_t>(in.gcount());
    std::size_t start = 0;
    for (std::size_t i = 0; i < got; ++i) {
      if (block[i] != '\n') continue;
      carry.append(block, start, i - start);
      if (Status st = line(std::string_view(carry), ++number); !st) return st;
      carry.clear();
      start = i + 1;
    }
    carry.append(block, start, got - start);
    if (carry.size() > (16u << 20)) return bad(path, "line " + std::to_string(number + 1) + " is longer than 16 MiB");
  }
  if (!carry.empty()) return line(std::string_view(carry), ++number);
  return {};
}

inline std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t' || s.front() == '\r')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

inline std::vector<std::string_view> words(std::string_view s) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && (s[i] == ' ' || s[i] == '\t' || s[i] == '\r')) ++i;
    const std::size_t b = i;
    while (i < s.size() && s[i] != ' ' && s[i] != '\t' && s[i] != '\r') ++i;
    if (i > b) out.push_back(s.substr(b, i - b));
  }
  return out;
}

// A decimal count, or nothing when the word is not one or passes 10^15.
inline std::optional<unsigned long long> count(std::string_view w) {
  if (w.empty() || w.size() > 15) return std::nullopt;
  unsigned long long n = 0;
  for (char c : w) {
    if (c < '0' || c > '9') return std::nullopt;
    n = n * 10 + static_cast<unsigned long long>(c - '0');
  }
  return n;
}

inline bool isNumber(std::string_view w) {
  if (w.empty() || w.size() > 64) return false;
  char buf[65];
  std::memcpy(buf, w.data(), w.size());
  buf[w.size()] = '\0';
  char* end = nullptr;
  (void)std::strtod(buf, &end);
  return end == buf + w.size();
}

// PLY (mesh_scan_ply.cpp).
Status scanPly(const std::string& path, std::uintmax_t size);

}  // namespace reel::io::scan
