// Shared by every fragment shader: output encoding, tone mapping and environment lookups.
const float PI = 3.14159265358979;

vec3 srgbEncode(vec3 c) {
  c = clamp(c, 0.0, 1.0);
  return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
}

// Stephen Hill's fit of the ACES reference rendering and sRGB output transforms (RRT + ODT),
// with its input and output matrices; the renderer scales the input (u_exposure) so that middle
// grey 0.18 stays 0.18 (diffuse white 1.0 becomes 0.73).
vec3 aces(vec3 c) {
  const mat3 to_rrt = mat3(0.59719, 0.07600, 0.02840, 0.35458, 0.90834, 0.13383, 0.04823, 0.01566, 0.83777);
  const mat3 from_odt = mat3(1.60475, -0.10208, -0.00327, -0.53108, 1.10813, -0.07276, -0.07367, -0.00605, 1.07602);
  vec3 v = to_rrt * c;
  v = (v * (v + 0.0245786) - 0.000090537) / (v * (0.983729 * v + 0.4329510) + 0.238081);
  return clamp(from_odt * v, 0.0, 1.0);
}

vec3 srgbDecode(vec3 c) {
  return mix(c / 12.92, pow((c + 0.055) / 1.055, vec3(2.4)), step(vec3(0.04045), c));
}

// A linear colour as it is shown, before the sRGB encoding: scaled by the exposure, tone mapped
// (ACES).
vec3 display(vec3 c, float exposure) {
  c *= exposure;
#ifdef ACES
  c = aces(c);
#endif
  return c;
}

// A linear colour as it is written: display() and sRGB-encoded.
vec3 finish(vec3 c, float exposure) { return srgbEncode(display(c, exposure)); }

#ifdef ENVIRONMENT
uniform sampler2D u_env;  // prefiltered radiance (core/environment.h's equirectangular layout)
vec3 envAt(vec3 d, float lod) {
  vec2 st = vec2((atan(d.x, -d.z) + PI) / (2.0 * PI), acos(clamp(d.y, -1.0, 1.0)) / PI);
  return textureLod(u_env, st, lod).rgb;
}
#endif
