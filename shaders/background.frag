in float v_t;
out vec4 o_color;
uniform vec3 u_top;
uniform vec3 u_bottom;
uniform int u_tonemap;

vec3 srgbEncode(vec3 c) {
  c = clamp(c, 0.0, 1.0);
  return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
}

void main() {
  vec3 c = mix(u_bottom, u_top, clamp(v_t, 0.0, 1.0));
  o_color = vec4(srgbEncode(c), 1.0);
}
