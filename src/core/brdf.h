// The microfacet BRDF the renderer shades with, on the CPU: for the tables it samples (the
// split-sum DFG table) and for the tests that check the shader's terms against them.
//
// Conventions, as in shaders/surface.frag: α = roughness² (Burley 2012); a light of radiance E
// arriving along l adds  E·(n·l)·(ρ_d + π·f_s)  to a pixel, so that a Lambert surface of albedo
// ρ_d under E at normal incidence is ρ_d·E (reel's light units, docs/rendering.md).
#pragma once

#include <vector>

#include "core/types.h"

namespace reel::brdf {

// GGX / Trowbridge–Reitz normal distribution (Walter, Marschner, Li, Torrance 2007, eq. 33).
double ggxD(double n_dot_h, double alpha);
// Height-correlated Smith masking-shadowing folded with the 1/(4 n·l n·v) of the microfacet
// BRDF: V = G₂/(4 n·l n·v) (Heitz 2014, "Understanding the Masking-Shadowing Function", eq. 99).
double smithV(double n_dot_l, double n_dot_v, double alpha);
// Schlick's Fresnel approximation (Schlick 1994) from f0 at normal incidence to f90 at grazing.
double schlick(double f0, double f90, double cos_theta);

// Today's Blinn–Phong exponent n as a roughness: Beckmann's α = √(2/(n+2)) (Walter et al. 2007,
// §5.2), taken as GGX's α, and roughness = √α. shininess 32 → 0.49, 120 → 0.36, 8 → 0.69.
double roughnessOfShininess(double shininess);

// The split-sum table (Karis 2013, "Real Shading in Unreal Engine 4"): for each cosine n·v and
// roughness r on a size×size grid (texel centres, n·v = (i+½)/size, r = (j+½)/size), the pair
// (A, B) with ∫ f_s·(n·l) dl = F0·A + F90·B for the GGX BRDF above with Schlick's Fresnel,
// integrated by GGX importance sampling over `samples` Hammersley points. Row j, column i, A and
// B interleaved: ab[2·(j·size + i)].
struct DfgTable {
  int size = 0;
  std::vector<float> ab;
  // Bilinear lookup, clamped to the texel centres, as the shader's texture does.
  Vec2 at(double n_dot_v, double roughness) const;
};
DfgTable integrateDfg(int size, int samples);

// Skin's diffusion profile (d'Eon & Luebke 2007, "Advanced Techniques for Realistic Real-Time
// Skin Rendering", GPU Gems 3 ch. 14, table 14-1): R(r) = Σ w_i·G(v_i, r), six Gaussians
// G(v, r) = e^(−r²/2v)/(2πv) of variances 0.0064 to 7.41 mm², their red, green and blue weights
// (red reaches farthest). r in mm; R in mm⁻² per colour.
Vec3 skinProfile(double r_mm);

// Pre-integrated skin (Penner & Borshukov 2011, "Pre-Integrated Skin Shading", GPU Pro 2): the
// diffuse response of skin lit at angle θ from the normal, on a ring of radius r (the surface's
// curvature 1/r): D(θ, r) = ∫ cos⁺(θ + x)·R(2r·sin(|x|/2)) dx / ∫ R(2r·sin(|x|/2)) dx over
// x ∈ [−π, π] (the light reaching the ring's points, carried under the skin by the profile to the
// point at x = 0). Flat skin (1/r = 0) is Lambert, cos⁺θ; the curvier, the further past the
// terminator each colour reaches (red farthest). Each Gaussian is integrated over its own width,
// so the narrow ones are not lost between samples.
// The table: cos θ = 2(i+½)/size − 1 across, the curvature 1/r = kSkinMaxCurvature·((j+½)/size)²
// down (more rows where skin is nearly flat), rgb interleaved: rgb[3·(j·size + i)].
inline constexpr double kSkinMaxCurvature = 1.0;  // mm⁻¹: a ring 1 mm round (an ear's rim is ~2 mm)
struct SkinTable {
  int size = 0;
  std::vector<float> rgb;
  // Bilinear lookup, clamped to the texel centres, as the shader's texture does.
  Vec3 at(double n_dot_l, double curvature_per_mm) const;
};
SkinTable integrateSkin(int size);
// D(θ, 1/r) itself (cos θ = n_dot_l), integrated for one (θ, r).
Vec3 preintegratedSkin(double n_dot_l, double curvature_per_mm);

// The k-th of n Hammersley points in [0,1)² (van der Corput radical inverse in base 2).
Vec2 hammersley(unsigned k, unsigned n);
// The half vector of a GGX-distributed microfacet for the uniform point u, around +z
// (Walter et al. 2007, eq. 35–36).
Vec3 sampleGgx(const Vec2& u, double alpha);

}  // namespace reel::brdf
