// The 4 x 4 average of ambient occlusion (ao.frag turns its kernel in 4 x 4 tiles), over the
// pixels at about the same depth only, so occlusion does not bleed across silhouettes.
in vec2 v_ndc;
out float o_ao;
uniform sampler2D u_ao;
uniform sampler2D u_depth;
uniform vec2 u_texel;

void main() {
  vec2 uv = gl_FragCoord.xy * u_texel;
  float d0 = texture(u_depth, uv).r;
  float sum = 0.0, w = 0.0;
  for (int y = -2; y < 2; ++y)
    for (int x = -2; x < 2; ++x) {
      vec2 o = uv + vec2(x, y) * u_texel;
      float k = abs(texture(u_depth, o).r - d0) < 0.05 * (1.0 - d0) + 1e-6 ? 1.0 : 0.0;  // about 5% in distance
      sum += texture(u_ao, o).r * k;
      w += k;
    }
  o_ao = w > 0.0 ? sum / w : 1.0;
}
