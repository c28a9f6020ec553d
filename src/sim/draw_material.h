// The renderer's material of a scene material (shared by every *_draw.cpp).
#pragma once

#include "core/drawlist.h"
#include "core/scene/material.h"

namespace reel {

inline DrawMaterial drawMaterial(const Material& m) {
  DrawMaterial d;
  d.color = m.color;
  d.texture = m.texture_image;
  d.specular = m.specular;
  d.shininess = m.shininess;
  d.opacity = m.opacity;
  return d;
}

}  // namespace reel
