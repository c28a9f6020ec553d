#include "io/stats.h"

#include <algorithm>

#include "core/format.h"

namespace reel::io {
namespace {

// A body name as a CSV field: quoted when it holds a comma, a quote or a line break.
std::string csvField(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

}  // namespace

Status StatsWriter::open(const std::string& path) { return file_.open(path); }

Status StatsWriter::write(int frame, double time, const std::vector<std::pair<std::string, std::vector<Statistic>>>& bodies) {
  std::string out;
  if (!started_) {
    for (const auto& [name, stats] : bodies)
      for (const Statistic& s : stats)
        if (std::find(columns_.begin(), columns_.end(), s.name) == columns_.end()) columns_.push_back(s.name);
    out += "frame,time,body";
    for (const std::string& c : columns_) out += "," + c;
    out += "\n";
    started_ = true;
  }
  for (const auto& [name, stats] : bodies) {
    if (stats.empty()) continue;
    out += std::to_string(frame) + ",";
    appendNumber(out, time);
    out += "," + csvField(name);
    for (const std::string& c : columns_) {
      out += ",";
      const auto it = std::find_if(stats.begin(), stats.end(), [&](const Statistic& s) { return s.name == c; });
      if (it != stats.end()) appendNumber(out, it->value);
    }
    out += "\n";
  }
  return file_.write(out);
}

Status StatsWriter::finish() { return file_.commit(); }

}  // namespace reel::io
