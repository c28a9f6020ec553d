// Physically based shading in linear space (docs/rendering.md, "Shading"): Lambert diffuse, a
// GGX specular lobe with height-correlated Smith masking and Schlick's Fresnel, an optional
// sheen lobe; directional, point and ambient lights, image-based light from an environment,
// filtered shadow maps, exponential fog, exposure, optional ACES tone mapping, and the result
// written sRGB-encoded. A light of radiance E arriving along l adds E·(n·l)·(k_d + π·f_s):
//   directional: E = color·intensity;  point: E = color·intensity / d²
//   ambient:     (k_d + E_s)·color·intensity, the response to a uniform surrounding radiance
// where k_d = ρ·(1 − metallic)·(1 − E_s) and E_s = F0·A + F90·B is the specular albedo from the
// split-sum table (what the specular lobe reflects the diffuse term does not: energy is
// conserved, and a white surface under a uniform light is uniformly white). specular = 0 and
// metallic = 0 leave F0 = F90 = 0: exactly Lambert, k_d = ρ.
// The renderer compiles one variant per combination of lights and features it meets, with the
// light list unrolled (LIGHTS below) and unused features compiled out: a software rasteriser
// runs both sides of a branch, so a branch around a shadow lookup would cost the lookups anyway.
in vec3 v_world;
in vec3 v_normal;
in vec2 v_uv;
in vec3 v_color;
in float v_gloss;
in float v_clarity;  // the share of u_transmission that passes here
in float v_wrinkle;  // WRINKLED: how deep the wrinkle map sinks here, 0..1
out vec4 o_color;

uniform vec3 u_light_vec[8];       // direction the light travels, or its position
uniform vec3 u_light_radiance[8];  // color · intensity
uniform sampler2DShadow u_shadow_map0;
uniform sampler2DShadow u_shadow_map1;
uniform mat4 u_shadow_matrix[2];
uniform float u_shadow_texel;
uniform sampler2D u_shadow_raw0;  // the same maps read as depths (no comparison)
uniform sampler2D u_shadow_raw1;
uniform vec4 u_shadow_soft[2];    // per map: its penumbra's parameters (render/surfaces.h ShadowFrame)
uniform float u_shadow_offset[2]; // per map: a texel's width on the scene, m

uniform vec3 u_color;
uniform vec3 u_back_color;  // DOUBLE_SIDED: the back's albedo
uniform int u_plain_back;   // DOUBLE_SIDED: 1 when the back has its own colour
uniform float u_f0;         // a dielectric's reflectance at normal incidence, 0.08·specular
uniform float u_roughness;  // 0..1, α = roughness²
uniform float u_checker_size;  // CHECKER: m
uniform float u_metallic;   // 0..1
uniform float u_sheen;      // SHEEN: 0..1
uniform float u_scatter;    // SCATTER: the profile's scale (1: skin at the scene's metres)
uniform sampler2D u_skin;   // SCATTER: pre-integrated skin, D by (n·l, √(curvature / its table's most))
uniform float u_skin_max_curvature;  // SCATTER: the table's most curvature, m⁻¹
uniform float u_translucency;        // TRANSLUCENT: 0..1
uniform float u_opacity;
uniform sampler2D u_texture;
uniform sampler2D u_bump;         // BUMPED: a height map over the UVs (its luminance, 0..1)
uniform float u_bump_depth;       // BUMPED: the height of luminance 1 over 0, m (0 with only wrinkles)
uniform sampler2D u_wrinkles;     // WRINKLED: a second height map, its depth scaled per vertex
uniform float u_wrinkle_depth;    // WRINKLED: m
uniform float u_wrinkle_shade;    // WRINKLED: 0..1, a crease's floor this much darker in full
uniform sampler2D u_dfg;    // SPECULAR: the split-sum table (A, B) by (n·v, roughness)
uniform float u_env_lod;    // ENVIRONMENT: u_env's last mip level (roughness 1)
uniform vec3 u_sh[9];       // ENVIRONMENT: irradiance / π in spherical harmonics
uniform vec3 u_eye;
uniform vec3 u_fog_color;
uniform float u_fog_density;
uniform float u_exposure;   // 2^EV (with ACES, times its middle-grey gain)
uniform sampler2D u_ao;     // AO: ambient occlusion of the picture's pixels (ao.frag)
uniform float u_transmission;     // TRANSMISSIVE: 0..1
uniform float u_absorption_depth; // TRANSMISSIVE: m
uniform sampler2D u_scene_color;  // TRANSMISSIVE: the picture behind (as shown, sRGB)
uniform sampler2D u_scene_depth;  // TRANSMISSIVE: its depth
uniform sampler2D u_back_depth;   // TRANSMISSIVE: the farthest depth of the see-through bodies
uniform mat4 u_view;
uniform vec2 u_near_far;
uniform vec2 u_screen_texel;

// The point a shadow map is read at: moved off its surface along the normal by one to three of
// the map's texels (more as the light grazes), so that a surface does not shadow itself between
// the map's samples (acne). In texels, not metres: a fixed centimetre lost every shadow smaller
// than it (a nose's on a face), and was under a texel of a map over a large scene.
vec3 shadowPoint(vec3 p, vec3 n, vec3 l, int s) {
  return p + n * (u_shadow_offset[s] * (1.0 + 2.0 * (1.0 - max(dot(n, l), 0.0))));
}

// 3 x 3 taps of bilinear percentage-closer filtering: soft edges.
#define SHADOW_PCF(MAP, S)                                                          \
  float shadow##S(vec3 p, vec3 n, vec3 l) {                                         \
    vec4 q = u_shadow_matrix[S] * vec4(shadowPoint(p, n, l, S), 1.0);              \
    q.xyz /= q.w;                                                                    \
    float bias = 0.0015 + 0.004 * (1.0 - max(dot(n, l), 0.0));                     \
    float sum = 0.0;                                                                 \
    for (int y = -1; y <= 1; ++y)                                                    \
      for (int x = -1; x <= 1; ++x)                                                  \
        sum += texture(MAP, vec3(q.xy + vec2(x, y) * (1.5 * u_shadow_texel), q.z - bias)); \
    /* outside the map (beyond the fitted scene bounds): lit */                     \
    bool inside = all(greaterThanEqual(q.xyz, vec3(0.0))) && all(lessThanEqual(q.xyz, vec3(1.0))); \
    return inside ? sum / 9.0 : 1.0;                                                 \
  }
SHADOW_PCF(u_shadow_map0, 0)
SHADOW_PCF(u_shadow_map1, 1)

// Percentage-closer soft shadows (Fernando 2005, "Percentage-Closer Soft Shadows"): the mean
// depth of the blockers found by 8 taps within a search disc gives the penumbra's width by similar
// triangles, w = (d_receiver − d_blocker)·light size / d_blocker, then 12 filtered taps over a
// disc that wide (its radius w/2). The discs are golden-angle spirals turned per pixel by
// interleaved gradient noise (Jimenez 2014); the radii stay between 1.5 and 40 texels.
float penumbra(vec4 prm, float zr, float zb) {  // in map texture units
  if (prm.x < 1.5) return max(zr - zb, 0.0) * prm.y;
  float lr = prm.y * prm.z / (prm.z - zr * (prm.z - prm.y));  // linear distances from the light
  float lb = prm.y * prm.z / (prm.z - zb * (prm.z - prm.y));
  return max(lr - lb, 0.0) / max(lb, 1e-4) * prm.w / max(lr, 1e-4);
}
// The spirals' points unturned (constants: built-in functions of constants fold at compile time),
// each turned by the pixel's angle through its cosine and sine (cs): one cosine and sine a pixel
// instead of two for each of the 20 taps.
#define SPIRAL(I, N) (sqrt((float(I) + 0.5) / float(N)) * vec2(cos(float(I) * 2.39996), sin(float(I) * 2.39996)))
const vec2 kSpiral8[8] = vec2[](SPIRAL(0, 8), SPIRAL(1, 8), SPIRAL(2, 8), SPIRAL(3, 8), SPIRAL(4, 8), SPIRAL(5, 8),
                                SPIRAL(6, 8), SPIRAL(7, 8));
const vec2 kSpiral12[12] = vec2[](SPIRAL(0, 12), SPIRAL(1, 12), SPIRAL(2, 12), SPIRAL(3, 12), SPIRAL(4, 12),
                                  SPIRAL(5, 12), SPIRAL(6, 12), SPIRAL(7, 12), SPIRAL(8, 12), SPIRAL(9, 12),
                                  SPIRAL(10, 12), SPIRAL(11, 12));
vec2 turned(vec2 p, vec2 cs) { return vec2(cs.x * p.x - cs.y * p.y, cs.y * p.x + cs.x * p.y); }
// The mean of a pixel's value and its two neighbours' in its 2 x 2 quad (read through the
// derivatives, which the quad computes anyway): the soft shadow's 12 taps, turned differently in
// each pixel, become 36, and its noise, which read as hairs in a penumbra on skin, falls by 1.7.
// llvmpipe's derivatives are per row and column of the quad; a driver's coarse ones (GLSL 3.30
// allows them) give the bottom row the top's, so the result is clamped to a fraction.
float quadMean(float v) {
  float dx = dFdx(v), dy = dFdy(v);
  float sx = mod(floor(gl_FragCoord.x), 2.0) < 0.5 ? 1.0 : -1.0;
  float sy = mod(floor(gl_FragCoord.y), 2.0) < 0.5 ? 1.0 : -1.0;
  return clamp(v + (sx * dx + sy * dy) / 3.0, 0.0, 1.0);
}
#define SHADOW_PCSS(MAP, RAW, S)                                                    \
  float shadowSoft##S(vec3 p, vec3 n, vec3 l) {                                     \
    vec4 q = u_shadow_matrix[S] * vec4(shadowPoint(p, n, l, S), 1.0);              \
    q.xyz /= q.w;                                                                    \
    float zr = q.z - (0.0015 + 0.004 * (1.0 - max(dot(n, l), 0.0)));               \
    float turn = 6.2831853 * fract(52.9829189 * fract(dot(gl_FragCoord.xy, vec2(0.06711056, 0.00583715)))); \
    vec2 cs = vec2(cos(turn), sin(turn));                                           \
    float lo = 1.5 * u_shadow_texel, hi = 40.0 * u_shadow_texel;                   \
    float search = clamp(penumbra(u_shadow_soft[S], zr, 0.0), lo, hi);              \
    float sum = 0.0, count = 0.0;                                                    \
    for (int i = 0; i < 8; ++i) {                                                    \
      float d = texture(RAW, q.xy + turned(kSpiral8[i], cs) * search).r;                 \
      if (d < zr) { sum += d; count += 1.0; }                                        \
    }                                                                                \
    float w = clamp(0.5 * penumbra(u_shadow_soft[S], zr, sum / max(count, 1.0)), lo, hi); \
    float lit = 0.0;                                                                 \
    for (int i = 0; i < 12; ++i) lit += texture(MAP, vec3(q.xy + turned(kSpiral12[i], cs) * w, zr)); \
    bool inside = all(greaterThanEqual(q.xyz, vec3(0.0))) && all(lessThanEqual(q.xyz, vec3(1.0))); \
    return quadMean(inside && count > 0.0 ? lit / 12.0 : 1.0);                       \
  }
SHADOW_PCSS(u_shadow_map0, u_shadow_raw0, 0)
SHADOW_PCSS(u_shadow_map1, u_shadow_raw1, 1)

#ifdef TRANSMISSIVE
float linearDepth(float d) {  // window depth → distance along the view axis
  float z = d * 2.0 - 1.0, n = u_near_far.x, f = u_near_far.y;
  return 2.0 * n * f / (f + n - z * (f - n));
}
#endif

#if defined(BUMPED) || defined(WRINKLED)
// Bump mapping without tangents (Mikkelsen 2010, "Bump Mapping Unparametrized Surfaces on the
// GPU"): the height's screen-space derivatives dB/dx, dB/dy and the position's σ_s = ∂p/∂x,
// σ_t = ∂p/∂y give the surface gradient ∇_S B = (dB/dx·(σ_t × n) + dB/dy·(n × σ_s)) / (σ_s·(σ_t × n)),
// and the bumped normal n − ∇_S B. dB/dx and dB/dy come from the height's gradient over the UVs,
// by central differences a texel (or the pixel's footprint, where wider) apart, taken through the
// UVs' own derivatives (per pixel; differencing the height itself would be blocky over 2 × 2 quads).
// The height (m) at uv: the bump map's, plus the wrinkle map's (animated wrinkle maps, Oat 2007)
// as deep as the vertices' weights say. The maps hold luminance, uploaded as one channel.
float bumpHeight(vec2 uv) {
  float h = 0.0;
#ifdef BUMPED
  h += texture(u_bump, uv).r * u_bump_depth;
#endif
#ifdef WRINKLED
  h += texture(u_wrinkles, uv).r * (u_wrinkle_depth * clamp(v_wrinkle, 0.0, 1.0));
#endif
  return h;
}
vec3 bumped(vec3 n, vec3 p, vec2 uv) {
  vec3 ss = dFdx(p), st = dFdy(p);
  vec2 dx = dFdx(uv), dy = dFdy(uv);
#ifdef BUMPED
  vec2 texel = 1.0 / vec2(textureSize(u_bump, 0));
#else
  vec2 texel = 1.0 / vec2(textureSize(u_wrinkles, 0));
#endif
  vec2 e = max(texel, max(abs(dx), abs(dy)));
  vec2 grad = vec2(bumpHeight(uv + vec2(e.x, 0.0)) - bumpHeight(uv - vec2(e.x, 0.0)),
                   bumpHeight(uv + vec2(0.0, e.y)) - bumpHeight(uv - vec2(0.0, e.y))) / (2.0 * e);
  vec3 r1 = cross(st, n), r2 = cross(n, ss);
  float det = dot(ss, r1);
  vec3 surf = sign(det) * (dot(grad, dx) * r1 + dot(grad, dy) * r2);
  vec3 b = abs(det) * n - surf;
  return dot(b, b) > 0.0 && abs(det) > 0.0 ? normalize(b) : n;
}
#endif

// The material at this pixel, set once in main() and read by every light.
vec3 g_kd;                 // diffuse albedo, less what the specular lobe reflects
vec3 g_f0;                 // specular reflectance at normal incidence
float g_f90;               // ... at grazing incidence (0 when f0 is: no reflection at all)
vec3 g_es = vec3(0.0);     // specular albedo E_s for the view direction (with g_comp)
vec3 g_comp = vec3(1.0);   // multiple-scattering compensation of the specular lobe
float g_alpha, g_nv;
float g_ao = 1.0;          // AO: how much of the surroundings this point sees
vec3 g_sheen = vec3(0.0);  // SHEEN: its colour
vec3 g_geo;                // the surface's own normal (without its relief)
float g_curv = 0.0;        // SCATTER: the skin table's row for this pixel's curvature

// GGX distribution (Walter et al. 2007) and height-correlated Smith visibility G₂/(4 n·l n·v)
// (Heitz 2014): the same functions as core/brdf.cpp.
float ggxD(float nh, float a) {
  float a2 = a * a, d = nh * nh * (a2 - 1.0) + 1.0;
  return a2 / (PI * d * d);
}
float smithV(float nl, float nv, float a) {
  float a2 = a * a;
  float gv = nl * sqrt(nv * nv * (1.0 - a2) + a2), gl = nv * sqrt(nl * nl * (1.0 - a2) + a2);
  return 0.5 / max(gv + gl, 1e-6);
}

// Diffuse plus specular from a light of radiance `radiance` arriving along l.
vec3 shade(vec3 n, vec3 view, vec3 l, vec3 radiance) {
  float ndl_raw = dot(n, l), ndl = max(ndl_raw, 0.0);
#ifdef SCATTER
  // Pre-integrated skin (Penner & Borshukov 2011): each colour's diffuse term from the table at
  // this pixel's curvature. Light scattered under skin also blurs its fine relief, red most (it
  // travels farthest): red sees n·l blended 80% toward the smooth normal's, green and blue 35%
  // (after Penner's per-colour blurred normals; two reads of the table, not three).
  // (Red never sees less light than green and blue: scattered farthest, it brightens a crease's
  // shaded side, but taken darker on a lit side that tilts toward the light, it tinted the lit
  // walls of deep wrinkles cyan, a colour fringe along the brows' furrows.)
  float nl_geo = dot(g_geo, l), nl_gb = mix(ndl_raw, nl_geo, 0.35), nl_r = max(mix(ndl_raw, nl_geo, 0.8), nl_gb);
  vec3 c = g_kd * vec3(texture(u_skin, vec2(0.5 * nl_r + 0.5, g_curv)).r, texture(u_skin, vec2(0.5 * nl_gb + 0.5, g_curv)).gb);
#else
  vec3 c = g_kd * ndl;
#endif
#ifdef TRANSLUCENT
  // A thin sheet lit from behind: a share of the light passes through, reddened by the tissue.
  c += g_kd * (u_translucency * max(-dot(g_geo, l), 0.0)) * vec3(1.0, 0.4, 0.25);
#endif
#if defined(SPECULAR) || defined(SHEEN)
  vec3 h = normalize(l + view);
  float nh = max(dot(n, h), 0.0);
#endif
#ifdef SPECULAR
  vec3 F = g_f0 + (g_f90 - g_f0) * pow(1.0 - max(dot(l, h), 0.0), 5.0);  // Schlick 1994
  c += PI * ggxD(nh, g_alpha) * smithV(ndl, g_nv, g_alpha) * F * g_comp * ndl;
#endif
#ifdef SHEEN
  // Sheen: the "Charlie" distribution of Estevez & Kulla 2017 ("Production Friendly Microfacet
  // Sheen BRDF", α = 0.35) with Neubelt & Pettineo's 2013 visibility 1/(4(n·l + n·v − n·l n·v)).
  float inv_a = 1.0 / 0.35, sin2 = max(1.0 - nh * nh, 0.0);
  float d_sheen = (2.0 + inv_a) * pow(sin2, 0.5 * inv_a) / (2.0 * PI);
  c += PI * d_sheen / (4.0 * (ndl + g_nv - ndl * g_nv) + 1e-4) * g_sheen * ndl;
#endif
  return radiance * c;
}

#ifdef ENVIRONMENT
vec3 irradiance(vec3 n) {  // Ramamoorthi & Hanrahan 2001: irradiance / π from 9 coefficients
  return max(u_sh[0] * 0.282095 + u_sh[1] * (0.488603 * n.y) + u_sh[2] * (0.488603 * n.z) + u_sh[3] * (0.488603 * n.x) +
             u_sh[4] * (1.092548 * n.x * n.y) + u_sh[5] * (1.092548 * n.y * n.z) +
             u_sh[6] * (0.315392 * (3.0 * n.z * n.z - 1.0)) + u_sh[7] * (1.092548 * n.x * n.z) +
             u_sh[8] * (0.546274 * (n.x * n.x - n.y * n.y)), 0.0);
}
#endif

#define DIRECTIONAL(I) shade(n, view, -normalize(u_light_vec[I]), u_light_radiance[I])
#ifdef SCATTER
// Skin: light past the terminator is what scattered under it, which the head's shadow of itself
// there does not stop; the shadow map counts only where the surface faces the light (a nose's
// shadow on the cheek stays), else its edge draws a seam along the terminator.
// A shadow's edge on skin is warm: red light, scattered farthest under it, reaches furthest into
// the shadow, blue least (the penumbra reddens, as in d'Eon & Luebke's renders, 2007): each
// colour takes the shadow's fraction to a power below 1 in the order of the profile's widths.
#define LIT(s, L) mix(vec3(1.0), pow(vec3(s), vec3(0.6, 0.85, 1.0)), smoothstep(-0.05, 0.3, dot(n, (L))))
#else
#define LIT(s, L) (s)
#endif
#define DIRECTIONAL_SHADOW(I, S) \
  (LIT(shadow##S(v_world, geo, -normalize(u_light_vec[I])), -normalize(u_light_vec[I])) * DIRECTIONAL(I))
#define POINT_RADIANCE(I) (u_light_radiance[I] / max(dot(u_light_vec[I] - v_world, u_light_vec[I] - v_world), 1e-8))
#define POINT(I) shade(n, view, normalize(u_light_vec[I] - v_world), POINT_RADIANCE(I))
#define POINT_SHADOW(I, S) (LIT(shadow##S(v_world, geo, normalize(u_light_vec[I] - v_world)), normalize(u_light_vec[I] - v_world)) * POINT(I))
#define DIRECTIONAL_SHADOW_SOFT(I, S) (LIT(shadowSoft##S(v_world, geo, -normalize(u_light_vec[I])), -normalize(u_light_vec[I])) * DIRECTIONAL(I))
#define POINT_SHADOW_SOFT(I, S) (LIT(shadowSoft##S(v_world, geo, normalize(u_light_vec[I] - v_world)), normalize(u_light_vec[I] - v_world)) * POINT(I))
#define AMBIENT(I) ((g_kd + g_es) * u_light_radiance[I] * g_ao)

void main() {
  vec3 n = normalize(v_normal);
#ifdef SCATTER
  // The curvature 1/r at this pixel, |∂n| / |∂p| across the pixel (for a sphere of radius r, 1/r),
  // scaled by the material's profile scale, as the table's row. Of the normal before a double-
  // sided sheet's back flips it: a quad with both sides in it would read a jump of 2 / |∂p|.
  vec3 dnx = dFdx(n), dny = dFdy(n), dpx = dFdx(v_world), dpy = dFdy(v_world);
  float curv = sqrt((dot(dnx, dnx) + dot(dny, dny)) / max(dot(dpx, dpx) + dot(dpy, dpy), 1e-14));
  g_curv = sqrt(clamp(u_scatter * curv / u_skin_max_curvature, 0.0, 1.0));
#endif
  vec3 view = normalize(u_eye - v_world);
  vec3 albedo = u_color * v_color;
  bool plain = false;
#if defined(BUMPED) || defined(WRINKLED)
  // The relief tilts the front's normal (here, outside any branch: it takes screen derivatives);
  // a back sees the same surface from behind, its normal the tilted one reversed.
  vec3 tilted = bumped(n, v_world, v_uv);
#endif
#ifdef DOUBLE_SIDED
  // The back: the other side's normal, and its own plain colour when the material has one.
  bool from_back = dot(n, view) < 0.0;
  if (from_back) {
    n = -n;
    plain = u_plain_back != 0;
    if (plain) albedo = u_back_color * v_color;
  }
#else
  bool from_back = false;
#endif
#ifdef TEXTURED
  if (!plain) albedo *= texture(u_texture, v_uv).rgb;
#endif
  // The surface's own normal, which the shadow maps are read along: the relief's tilt would move
  // each pixel's lookup by its pore, and speckle a penumbra.
  vec3 geo = n;
  g_geo = geo;
#if defined(BUMPED) || defined(WRINKLED)
  // (A plain back has neither the front's texture nor its relief.)
  if (!plain) n = from_back ? -tilted : tilted;
#endif
#ifdef WRINKLED
  // A crease's floor darker: less of the light reaches into a fold.
  if (!plain) albedo *= 1.0 - u_wrinkle_shade * clamp(v_wrinkle, 0.0, 1.0) * (1.0 - texture(u_wrinkles, v_uv).r);
#endif
#ifdef CHECKER
  // Squares (u_checker_size m) of 1 and 0.55 times the albedo, fading to their mean where a pixel covers
  // several squares (no moiré towards the horizon).
  vec2 cp = v_world.xz / u_checker_size;
  vec2 cell = floor(cp);
  float check = mod(cell.x + cell.y, 2.0) != 0.0 ? 0.55 : 1.0;
  float blur = clamp(max(fwidth(cp.x), fwidth(cp.y)) * 1.5 - 0.35, 0.0, 1.0);
  albedo *= mix(check, 0.775, blur);
#endif
  // The material (docs/rendering.md): a metal reflects in its albedo's colour and has no
  // diffuse term; a wet sheen (per-vertex gloss g) adds reflectance and smooths the surface.
  // A negative gloss dulls it instead (hair over a scalp): rougher, its reflection in its own
  // colour and faint at grazing, as a fibre's sheen is light that went through it and came back
  // tinted (Marschner et al. 2003, the TRT lobe), not a white Fresnel rim round the head.
  float gloss = max(v_gloss, 0.0), dull = clamp(-v_gloss, 0.0, 1.0);
  float rough = clamp(mix(u_roughness, min(u_roughness, 0.2), gloss) + 0.3 * dull, 0.03, 1.0);
  g_alpha = rough * rough;
  g_nv = max(dot(n, view), 1e-4);
  g_kd = albedo * (1.0 - u_metallic);
  g_f0 = mix(vec3(u_f0 + 0.04 * gloss), albedo, u_metallic);
  g_f90 = clamp(50.0 * dot(g_f0, vec3(0.3333)), 0.0, 1.0);
  g_f0 *= mix(vec3(1.0), albedo / max(max(albedo.r, max(albedo.g, albedo.b)), 1e-3), dull);
  g_f90 *= 1.0 - dull;
#ifdef SPECULAR
  // Split sum (Karis 2013): E_s = F0·A + F90·B. The single-scattering lobe loses 1 − A − B of
  // the light at high roughness; it is given back in F0's colour (Fdez-Agüera 2019, as Filament).
  vec2 ab = texture(u_dfg, vec2(g_nv, rough)).rg;
  g_comp = 1.0 + g_f0 * (1.0 / max(ab.x + ab.y, 1e-3) - 1.0);
  g_es = (g_f0 * ab.x + g_f90 * ab.y) * g_comp;
  g_kd *= max(vec3(1.0) - g_es, 0.0);
#endif
#ifdef TRANSMISSIVE
  float transmission = u_transmission * clamp(v_clarity, 0.0, 1.0);
  g_kd *= 1.0 - transmission;  // what shows through is not scattered back
#endif
#ifdef SHEEN
  float lum = dot(albedo, vec3(0.2126, 0.7152, 0.0722));
  g_sheen = u_sheen * mix(vec3(1.0), albedo / max(lum, 1e-3), 0.5);
#endif
#ifdef AO
  g_ao = texture(u_ao, gl_FragCoord.xy * u_screen_texel).r;
#endif
  vec3 c = vec3(0.0);
  LIGHTS
#ifdef ENVIRONMENT
  c += g_kd * irradiance(n) * g_ao;
#ifdef SPECULAR
  c += envAt(reflect(-view, n), rough * u_env_lod) * g_es * g_ao;
#endif
#endif
#ifdef FOG
  c = mix(u_fog_color, c, exp(-u_fog_density * length(u_eye - v_world)));
#endif
#ifdef TRANSMISSIVE
  // What lies behind, as shown (screen-space transmission): refracted by an offset along the
  // view-space normal that grows with the depth of the body (up to 3% of the picture), and
  // absorbed along that depth, Beer–Lambert: albedo^(depth / absorption_depth) is what is left.
  // The depth runs from this surface to the body's far side or to the opaque surface behind,
  // whichever is nearer. Composed as shown (after tone mapping), weighted by 1 − E_s: what the
  // surface reflects does not pass.
  vec2 suv = gl_FragCoord.xy * u_screen_texel;
  float zf = linearDepth(gl_FragCoord.z), zo = linearDepth(texture(u_scene_depth, suv).r);
  float back = texture(u_back_depth, suv).r;
  float thick = max(min(back > 0.0 ? linearDepth(back) : zo, zo) - zf, 0.0);
  vec3 nv = mat3(u_view) * n;
  vec2 ruv = suv - nv.xy * (0.03 * min(thick / 0.05, 1.0));
  if (linearDepth(texture(u_scene_depth, ruv).r) < zf) ruv = suv;  // in front of us there: no bend
  vec3 behind = srgbDecode(texture(u_scene_color, ruv).rgb);
  vec3 absorbed = pow(max(albedo, vec3(1e-3)), vec3(thick / u_absorption_depth));
  vec3 through = transmission * (vec3(1.0) - g_es) * absorbed * behind;
  o_color = vec4(srgbEncode(display(c, u_exposure) + through), 1.0);
#else
  o_color = vec4(finish(c, u_exposure), u_opacity);
#endif
}
