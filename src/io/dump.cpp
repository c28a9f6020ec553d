#include "io/dump.h"

#include <cmath>

#include <nlohmann/json.hpp>

#include "core/format.h"

namespace reel::io {
namespace {

void putVec3s(std::string& out, std::span<const Vec3> vs) {
  out += '[';
  for (std::size_t i = 0; i < vs.size(); ++i) {
    if (i) out += ',';
    out += '[';
    appendNumber(out, vs[i].x());
    out += ',';
    appendNumber(out, vs[i].y());
    out += ',';
    appendNumber(out, vs[i].z());
    out += ']';
  }
  out += ']';
}

// Invalid UTF-8 (a file name, say) is written with U+FFFD instead of failing.
std::string jsonString(const std::string& s) {
  return nlohmann::json(s).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

// `"masses"` and the kind's own fields, each as ,"name":[...] (lists of per_item numbers).
void putExtras(std::string& out, const BodyView& s) {
  // The numbers of v, comma-separated.
  auto numbers = [&](std::span<const double> v) {
    for (std::size_t i = 0; i < v.size(); ++i) {
      if (i) out += ',';
      appendNumber(out, v[i]);
    }
  };
  if (!s.masses.empty()) {
    out += ",\n  \"masses\":[";
    numbers(s.masses);
    out += ']';
  }
  for (const ViewField& f : s.fields) {
    out += ",\n  " + jsonString(f.name) + ":[";
    const std::size_t per = static_cast<std::size_t>(f.per_item), n = per ? f.values.size() / per : 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (i) out += ',';
      const std::span<const double> item(f.values.data() + i * per, per);
      if (per == 1) {
        numbers(item);
        continue;
      }
      out += '[';
      numbers(item);
      out += ']';
    }
    out += ']';
  }
}

// An articulated body's `links` (name, position of the centre of mass, orientation [w, x, y, z],
// velocity, angular velocity) and `joints` (name of the child link, angles in rad).
void putLinks(std::string& out, const BodyView& s) {
  const ViewField* q = nullptr;
  const ViewField* w = nullptr;
  for (const ViewField& f : s.fields) {
    if (f.name == "orientation") q = &f;
    if (f.name == "angular_velocity") w = &f;
  }
  auto numbers = [&](const double* v, std::size_t n) {
    out += '[';
    for (std::size_t i = 0; i < n; ++i) {
      if (i) out += ',';
      appendNumber(out, v[i]);
    }
    out += ']';
  };
  out += ",\n  \"links\":[";
  for (std::size_t i = 0; i < s.link_names.size(); ++i) {
    out += std::string(i ? "," : "") + "\n   {\"name\":" + jsonString(s.link_names[i]) + ",\"position\":";
    numbers(s.positions[i].data(), 3);
    out += ",\"orientation\":";
    if (q) numbers(q->values.data() + 4 * i, 4);
    out += ",\"velocity\":";
    numbers(s.velocities[i].data(), 3);
    out += ",\"angular_velocity\":";
    if (w) numbers(w->values.data() + 3 * i, 3);
    out += '}';
  }
  out += "],\n  \"joints\":[";
  for (std::size_t i = 0; i < s.joints.size(); ++i) {
    out += std::string(i ? "," : "") + "\n   {\"name\":" + jsonString(s.joints[i].name) + ",\"angles\":";
    numbers(s.joints[i].angles.data(), s.joints[i].angles.size());
    out += '}';
  }
  out += ']';
}

}  // namespace

Status DumpWriter::open(const std::string& path, const std::string& scene, int fps, int substeps) {
  if (Status st = file_.open(path); !st) return st;
  first_ = true;
  buf_ = "{\"format\":\"reel-dump/1\",\"scene\":" + jsonString(scene) + ",\"fps\":" +
         std::to_string(fps) + ",\"substeps\":" + std::to_string(substeps) + ",\"frames\":[\n";
  return {};
}

Status DumpWriter::write(const FrameView& f) {
  if (!first_) buf_ += ",\n";
  first_ = false;
  buf_ += "{\"frame\":" + std::to_string(f.frame) + ",\"time\":";
  appendNumber(buf_, f.time);
  buf_ += ",\"bodies\":[";
  for (std::size_t b = 0; b < f.bodies.size(); ++b) {
    const BodyView& s = f.bodies[b];
    if (b) buf_ += ',';
    buf_ += "\n {\"name\":" + jsonString(s.name) + ",\"type\":" + jsonString(s.type) +
            ",\"generator\":" + jsonString(s.generator) + ",\n  \"positions\":";
    putVec3s(buf_, s.positions);
    buf_ += ",\n  \"velocities\":";
    putVec3s(buf_, s.velocities);
    putExtras(buf_, s);
    if (!s.species_names.empty()) {
      buf_ += ",\n  \"species_names\":[";
      for (std::size_t k = 0; k < s.species_names.size(); ++k) buf_ += (k ? "," : "") + jsonString(s.species_names[k]);
      buf_ += "],\n  \"species\":[";
      for (std::size_t k = 0; k < s.species.size(); ++k) {
        if (k) buf_ += ',';
        buf_ += std::to_string(s.species[k]);
      }
      buf_ += "]}";
      continue;
    }
    if (!s.link_names.empty()) {
      putLinks(buf_, s);
      buf_ += '}';
      continue;
    }
    if (s.type != "mass_spring") {  // agents: positions and velocities only
      buf_ += '}';
      continue;
    }
    buf_ += ",\n  \"springs\":[";
    for (std::size_t k = 0; k < s.spring_a.size(); ++k) {
      if (k) buf_ += ',';
      buf_ += '[' + std::to_string(s.spring_a[k]) + ',' + std::to_string(s.spring_b[k]) + ']';
    }
    buf_ += "]}";
  }
  buf_ += "]}";
  Status st = file_.write(buf_);
  buf_.clear();
  return st;
}

Status DumpWriter::finish() {
  buf_ += "\n]}\n";
  Status st = file_.write(buf_);
  buf_.clear();
  return st ? file_.commit() : st;
}

}  // namespace reel::io
