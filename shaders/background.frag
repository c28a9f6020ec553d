// Where nothing covers the picture: the environment seen along each pixel's ray (ENVIRONMENT),
// else a vertical gradient from u_bottom to u_top with a glow about u_glow_at.xy (in NDC; its σ
// u_glow_at.z in NDC heights) added, a backdrop's pool of light; exposed and tone mapped as the
// surfaces are.
in float v_t;
in vec2 v_ndc;
out vec4 o_color;
uniform vec3 u_top;
uniform vec3 u_bottom;
uniform vec3 u_glow;
uniform vec3 u_glow_at;
uniform float u_aspect;  // the frame's width over its height
uniform float u_exposure;
uniform mat4 u_inv_view_proj;
uniform vec3 u_eye;

void main() {
#ifdef ENVIRONMENT
  vec4 w = u_inv_view_proj * vec4(v_ndc, 1.0, 1.0);
  vec3 c = envAt(normalize(w.xyz / w.w - u_eye), 0.0);
#else
  vec3 c = mix(u_bottom, u_top, clamp(v_t, 0.0, 1.0));
  vec2 r = (v_ndc - u_glow_at.xy) * vec2(u_aspect, 1.0) / u_glow_at.z;
  c += u_glow * exp(-0.5 * dot(r, r));
#endif
  o_color = vec4(finish(c, u_exposure), 1.0);
}
