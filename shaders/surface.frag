// Lighting in linear space: Lambert diffuse plus Blinn–Phong highlights, directional, point and
// ambient lights, filtered shadow maps, exponential fog, optional ACES tone mapping, and the
// result written sRGB-encoded.
//   directional: ρ·color·intensity·max(0, n·l)
//   point:       ρ·color·intensity·max(0, n·l) / d²
//   ambient:     ρ·color·intensity
// The renderer compiles one variant per combination of lights and features it meets, with the
// light list unrolled (LIGHTS below) and unused features compiled out: a software rasteriser
// runs both sides of a branch, so a branch around a shadow lookup would cost the lookups anyway.
in vec3 v_world;
in vec3 v_normal;
in vec2 v_uv;
in vec3 v_color;
in float v_gloss;
out vec4 o_color;

uniform vec3 u_light_vec[8];       // direction the light travels, or its position
uniform vec3 u_light_radiance[8];  // color · intensity
uniform sampler2DShadow u_shadow_map0;
uniform sampler2DShadow u_shadow_map1;
uniform mat4 u_shadow_matrix[2];
uniform float u_shadow_texel;

uniform vec3 u_color;
uniform vec3 u_back_color;  // DOUBLE_SIDED: the back's albedo
uniform int u_plain_back;   // DOUBLE_SIDED: 1 when the back has its own colour
uniform float u_specular;
uniform float u_shininess;
uniform float u_wrap;  // WRAP: 0..1
uniform float u_opacity;
uniform sampler2D u_texture;
uniform vec3 u_eye;
uniform vec3 u_fog_color;
uniform float u_fog_density;

// 3 x 3 taps of bilinear percentage-closer filtering: soft edges.
#define SHADOW_PCF(MAP, S)                                                          \
  float shadow##S(vec3 p, vec3 n, vec3 l) {                                         \
    vec4 q = u_shadow_matrix[S] * vec4(p + n * 0.01, 1.0);                         \
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

vec3 srgbEncode(vec3 c) {
  c = clamp(c, 0.0, 1.0);
  return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
}

vec3 aces(vec3 x) {  // Narkowicz 2015 fit of the ACES filmic curve
  return clamp((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
}

// Diffuse plus specular from a light of radiance `radiance` arriving along l.
vec3 shade(vec3 n, vec3 view, vec3 l, vec3 radiance, vec3 albedo) {
  float ndl = max(dot(n, l), 0.0);
#ifdef WRAP
  // Wrap lighting (Green 2004, "Real-time approximations to subsurface scattering", GPU Gems):
  // the diffuse term reaches past the terminator, as light scattered under skin does.
  vec3 c = albedo * max((dot(n, l) + u_wrap) / (1.0 + u_wrap), 0.0);
#else
  vec3 c = albedo * ndl;
#endif
#ifdef SPECULAR
  vec3 h = normalize(l + view);
  // A wet sheen (per-vertex gloss g): the highlight grows by 0.5 g and sharpens towards 120.
  float shininess = mix(u_shininess, max(u_shininess, 120.0), v_gloss);
  c += vec3((u_specular + 0.5 * v_gloss) * pow(max(dot(n, h), 0.0), shininess) * ndl);
#endif
  return radiance * c;
}

#define DIRECTIONAL(I) shade(n, view, -normalize(u_light_vec[I]), u_light_radiance[I], albedo)
#define DIRECTIONAL_SHADOW(I, S) \
  (shadow##S(v_world, n, -normalize(u_light_vec[I])) * DIRECTIONAL(I))
#define POINT_RADIANCE(I) (u_light_radiance[I] / max(dot(u_light_vec[I] - v_world, u_light_vec[I] - v_world), 1e-8))
#define POINT(I) shade(n, view, normalize(u_light_vec[I] - v_world), POINT_RADIANCE(I), albedo)
#define POINT_SHADOW(I, S) (shadow##S(v_world, n, normalize(u_light_vec[I] - v_world)) * POINT(I))
#define AMBIENT(I) (albedo * u_light_radiance[I])

void main() {
  vec3 n = normalize(v_normal);
  vec3 view = normalize(u_eye - v_world);
  vec3 albedo = u_color * v_color;
  bool plain = false;
#ifdef DOUBLE_SIDED
  // The back: the other side's normal, and its own plain colour when the material has one.
  if (dot(n, view) < 0.0) {
    n = -n;
    plain = u_plain_back != 0;
    if (plain) albedo = u_back_color * v_color;
  }
#endif
#ifdef TEXTURED
  if (!plain) albedo *= texture(u_texture, v_uv).rgb;
#endif
#ifdef CHECKER
  // 0.5 m squares of 1 and 0.55 times the albedo, fading to their mean where a pixel covers
  // several squares (no moiré towards the horizon).
  vec2 cp = v_world.xz / 0.5;
  vec2 cell = floor(cp);
  float check = mod(cell.x + cell.y, 2.0) != 0.0 ? 0.55 : 1.0;
  float blur = clamp(max(fwidth(cp.x), fwidth(cp.y)) * 1.5 - 0.35, 0.0, 1.0);
  albedo *= mix(check, 0.775, blur);
#endif
  vec3 c = vec3(0.0);
  LIGHTS
#ifdef FOG
  c = mix(u_fog_color, c, exp(-u_fog_density * length(u_eye - v_world)));
#endif
#ifdef ACES
  c = aces(c);
#endif
  o_color = vec4(srgbEncode(c), u_opacity);
}
