// Lighting in linear space: Lambert diffuse plus Blinn–Phong highlights, directional, point and
// ambient lights, filtered shadow maps, exponential fog, optional ACES tone mapping, and the
// result written sRGB-encoded.
//   directional: ρ·color·intensity·max(0, n·l)
//   point:       ρ·color·intensity·max(0, n·l) / d²
//   ambient:     ρ·color·intensity
in vec3 v_world;
in vec3 v_normal;
in vec2 v_uv;
out vec4 o_color;

#define MAX_LIGHTS 8
#define MAX_SHADOWS 2
uniform int u_light_count;
uniform int u_light_type[MAX_LIGHTS];       // 0 directional, 1 point, 2 ambient
uniform vec3 u_light_vec[MAX_LIGHTS];       // direction the light travels, or its position
uniform vec3 u_light_radiance[MAX_LIGHTS];  // color · intensity
uniform int u_light_shadow[MAX_LIGHTS];     // index of its shadow map, or -1
uniform sampler2DShadow u_shadow_map[MAX_SHADOWS];
uniform mat4 u_shadow_matrix[MAX_SHADOWS];
uniform float u_shadow_texel[MAX_SHADOWS];

uniform vec3 u_color;
uniform float u_specular;
uniform float u_shininess;
uniform float u_opacity;
uniform int u_double_sided;
uniform int u_checker;
uniform int u_textured;
uniform sampler2D u_texture;
uniform vec3 u_eye;
uniform vec3 u_fog_color;
uniform float u_fog_density;
uniform int u_tonemap;  // 0 none, 1 ACES

float shadowFactor(int s, vec3 p, vec3 n, vec3 l) {
  vec4 q = u_shadow_matrix[s] * vec4(p + n * 0.01, 1.0);
  q.xyz /= q.w;
  if (q.x < 0.0 || q.x > 1.0 || q.y < 0.0 || q.y > 1.0 || q.z > 1.0) return 1.0;
  float bias = 0.0015 + 0.004 * (1.0 - max(dot(n, l), 0.0));
  float sum = 0.0;
  // 5 x 5 percentage-closer filtering: soft edges.
  for (int y = -2; y <= 2; ++y)
    for (int x = -2; x <= 2; ++x) {
      vec2 o = vec2(float(x), float(y)) * u_shadow_texel[s] * 1.5;
      // Indexing sampler arrays needs a constant index in GLSL 3.30.
      if (s == 0) sum += texture(u_shadow_map[0], vec3(q.xy + o, q.z - bias));
      else sum += texture(u_shadow_map[1], vec3(q.xy + o, q.z - bias));
    }
  return sum / 25.0;
}

vec3 srgbEncode(vec3 c) {
  c = clamp(c, 0.0, 1.0);
  return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
}

vec3 aces(vec3 x) {  // Narkowicz 2015 fit of the ACES filmic curve
  return clamp((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
}

void main() {
  vec3 n = normalize(v_normal);
  vec3 view = normalize(u_eye - v_world);
  if (u_double_sided == 1 && dot(n, view) < 0.0) n = -n;
  vec3 albedo = u_color;
  if (u_textured == 1) albedo *= texture(u_texture, v_uv).rgb;
  if (u_checker == 1) {
    vec2 cell = floor(v_world.xz / 0.5);
    if (mod(cell.x + cell.y, 2.0) != 0.0) albedo *= 0.55;
  }
  vec3 c = vec3(0.0);
  for (int i = 0; i < u_light_count; ++i) {
    vec3 radiance = u_light_radiance[i];
    if (u_light_type[i] == 2) {
      c += albedo * radiance;
      continue;
    }
    vec3 l;
    if (u_light_type[i] == 0) {
      l = -normalize(u_light_vec[i]);
    } else {
      vec3 d = u_light_vec[i] - v_world;
      float d2 = max(dot(d, d), 1e-8);
      l = d / sqrt(d2);
      radiance /= d2;
    }
    float ndl = max(dot(n, l), 0.0);
    if (ndl <= 0.0) continue;
    float vis = u_light_shadow[i] >= 0 ? shadowFactor(u_light_shadow[i], v_world, n, l) : 1.0;
    vec3 h = normalize(l + view);
    float spec = u_specular * pow(max(dot(n, h), 0.0), u_shininess);
    c += vis * radiance * (albedo * ndl + vec3(spec) * ndl);
  }
  if (u_fog_density > 0.0) c = mix(u_fog_color, c, exp(-u_fog_density * length(u_eye - v_world)));
  if (u_tonemap == 1) c = aces(c);
  o_color = vec4(srgbEncode(c), u_opacity);
}
