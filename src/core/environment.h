// Image-based light: the radiance arriving from every direction (a procedural sky or an HDR
// picture of one), prefiltered once per scene for the shader: spherical harmonics for the diffuse
// term and GGX-blurred copies for the specular term (Karis 2013's split sum).
#pragma once

#include <array>
#include <memory>
#include <vector>

#include "core/types.h"

namespace reel {

// Radiance by direction in an equirectangular layout, linear RGB. A point (u, v) of the picture
// (u in [0, width), v in [0, height), texel centres at +½) looks along
//   (sin φ sin θ, cos θ, −cos φ sin θ),  φ = 2π·u/width − π,  θ = π·v/height,
// so the top row looks up (+y), the middle of the picture along −z (where a default camera
// looks), its left and right edges along +z.
struct RadianceMap {
  int width = 0, height = 0;
  std::vector<float> rgb;  // 3 floats per texel, row by row
  Vec3 texel(int x, int y) const;
  // Bilinear, wrapping around horizontally and clamped at the poles.
  Vec3 at(const Vec3& dir) const;
  // The direction through the centre of texel (x, y), and the texel coordinates of a direction.
  Vec3 directionOf(double x, double y) const;
  void coordsOf(const Vec3& dir, double& x, double& y) const;
};

// A sky without a sun (the scene's lights are the sun): `zenith` overhead fading to `horizon` at
// the horizon with (1 − elevation)³, and below the horizon `ground` (light bounced off the
// ground), reached 12° down: just under the horizon, where a floor's far edge ends, the sky
// still shows its horizon colour, so no dark band sits between the floor and the sky.
RadianceMap proceduralSky(const Vec3& zenith, const Vec3& horizon, const Vec3& ground, int width = 256);

// What the renderer samples.
struct Environment {
  // GGX-prefiltered radiance, level k for roughness k/(levels − 1), each half the size of the
  // one before; level 0 is the map itself (a mirror).
  std::vector<RadianceMap> levels;
  // Irradiance divided by π in order-2 spherical harmonics (Ramamoorthi & Hanrahan 2001, "An
  // Efficient Representation for Irradiance Environment Maps"): diffuse(n) = Σ sh[i]·Y_i(n) is
  // what a white Lambert surface facing n reflects, in reel's units (a uniform radiance L gives L).
  std::array<Vec3, 9> sh{};
  bool background = true;  // drawn where nothing covers the picture
  Vec3 diffuse(const Vec3& n) const;
  // The prefiltered radiance along r for roughness 0..1, trilinear between levels as the shader.
  Vec3 specular(const Vec3& r, double roughness) const;
};

// The nine real spherical harmonics of bands 0–2 at the unit vector n.
std::array<double, 9> shBasis(const Vec3& n);

// Prefilters `map` (scaled by `intensity`, turned by `rotation_deg` about +y) into `levels`
// specular levels (at most 6: level 0 is 256x128, each next one half as wide) and the irradiance
// harmonics.
std::shared_ptr<Environment> prefilterEnvironment(const RadianceMap& map, double intensity, double rotation_deg,
                                                        int levels = 6, int samples = 96);

}  // namespace reel
