// What any object or body of a scene may carry: its appearance (read by the renderer) and its
// surface (contact response).
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/image.h"
#include "core/types.h"

namespace reel {

// Appearance, read by the renderer; any object or body may carry it.
struct Material {
  Vec3 color{0.8, 0.8, 0.8};  // linear albedo
  std::string texture;        // resolved path of a PNG, empty for none
  std::shared_ptr<const Image> texture_image;  // its pixels, decoded when the scene loads
  // The physically based model of DrawMaterial (core/drawlist.h, docs/rendering.md).
  double specular = 0.0;      // 0..1: a dielectric reflects 0.08·specular at normal incidence
  double shininess = 32.0;    // Blinn–Phong exponent of older scenes: roughness √√(2/(n+2))
  std::optional<double> roughness;  // 0..1; given, it replaces shininess
  double metallic = 0.0;      // 0..1
  double sheen = 0.0;         // 0..1
  double transmission = 0.0;  // 0..1: see-through (water, glass), refracted and absorbed
  double absorption_depth = 0.1;  // m: the depth of it through which light keeps `color` of itself
  double opacity = 1.0;       // 0..1
  // Relief (bump mapping): the height of a bump map's luminance 1 over 0, m (0: flat; negative:
  // the dark parts stand out). The map is `bump_texture` when given, else the texture or pattern.
  double bump = 0.0;
  std::string bump_texture;  // resolved path of a PNG, empty for none
  std::shared_ptr<const Image> bump_image;  // its pixels
  // A sheet's back (the side its normal points away from), plain: this albedo and no texture.
  std::optional<Vec3> back_color;
};

// Contact response of an object's surface.
struct Surface {
  double friction = 0.3;     // Coulomb coefficient μ
  double restitution = 0.0;  // normal velocity kept after a bounce, 0..1
  double adhesion = 0.0;     // liquids: pull towards the surface within reach, m/s² (acceleration)
};

// Surfaces for particular liquid species (by species name), each overriding the base surface.
using SpeciesSurfaces = std::vector<std::pair<std::string, Surface>>;

// The surface a species meets: its own entry, or `base`.
inline Surface surfaceFor(const Surface& base, const SpeciesSurfaces& per, const std::string& species) {
  for (const auto& [name, sf] : per)
    if (name == species) return sf;
  return base;
}

}  // namespace reel
