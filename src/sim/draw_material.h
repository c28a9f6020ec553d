// The renderer's material of a scene material, and points as draw-list floats (shared by every
// *_draw.cpp).
#pragma once

#include <span>
#include <vector>

#include "core/drawlist.h"
#include "core/scene/material.h"

namespace reel {

inline DrawMaterial drawMaterial(const Material& m) {
  DrawMaterial d;
  d.color = m.color;
  d.texture = m.texture_image;
  d.bump = m.bump_image ? m.bump_image : m.texture_image;
  d.bump_depth = d.bump ? m.bump : 0.0;
  d.specular = m.specular;
  d.shininess = m.shininess;
  d.roughness = m.roughness;
  d.metallic = m.metallic;
  d.sheen = m.sheen;
  d.transmission = m.transmission;
  d.absorption_depth = m.absorption_depth;
  d.opacity = m.opacity;
  d.back_color = m.back_color;
  return d;
}

// A plain material of one colour and a dielectric's specular reflectance (0..1, as DrawMaterial's).
inline DrawMaterial plainMaterial(const Vec3& color, double specular = 0.1) {
  DrawMaterial m;
  m.color = color;
  m.specular = specular;
  m.shininess = 24;
  return m;
}

// Appends points as the float xyz triples a DrawSpheres (or DrawTubes) list holds.
inline void appendPoints(std::vector<float>& out, std::span<const Vec3> points) {
  out.reserve(out.size() + 3 * points.size());
  for (const Vec3& p : points)
    for (int k = 0; k < 3; ++k) out.push_back(static_cast<float>(p[k]));
}

}  // namespace reel
