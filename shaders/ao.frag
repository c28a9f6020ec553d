// Screen-space ambient occlusion from the camera's depth (a normal-oriented hemisphere, as in
// Mittring 2007 / Bavoil & Sainz 2008): 16 points within u_radius above each visible point,
// each counted as occluded where the depth buffer shows a surface in front of it (within the
// radius, so a far background does not darken a silhouette). The kernel turns from pixel to
// pixel in a 4 x 4 pattern that ao_blur.frag's 4 x 4 average removes.
in vec2 v_ndc;
out float o_ao;
uniform sampler2D u_depth;
uniform mat4 u_proj;
uniform mat4 u_inv_proj;
uniform vec2 u_texel;      // 1 / picture size
uniform float u_radius;    // m
uniform float u_strength;  // exponent on the visibility

vec3 viewPos(vec2 uv) {
  float d = texture(u_depth, uv).r;
  vec4 p = u_inv_proj * vec4(vec3(uv, d) * 2.0 - 1.0, 1.0);
  return p.xyz / p.w;
}

void main() {
  vec2 uv = gl_FragCoord.xy * u_texel;
  if (texture(u_depth, uv).r >= 1.0) {  // the background
    o_ao = 1.0;
    return;
  }
  vec3 p = viewPos(uv);
  // The normal from the nearer neighbour on each axis (no smearing across silhouettes).
  vec3 px = viewPos(uv + vec2(u_texel.x, 0.0)) - p, mx = p - viewPos(uv - vec2(u_texel.x, 0.0));
  vec3 py = viewPos(uv + vec2(0.0, u_texel.y)) - p, my = p - viewPos(uv - vec2(0.0, u_texel.y));
  vec3 dx = abs(px.z) < abs(mx.z) ? px : mx, dy = abs(py.z) < abs(my.z) ? py : my;
  vec3 n = normalize(cross(dx, dy));
  if (n.z < 0.0) n = -n;  // towards the camera (view space looks along −z)
  // A turn of the kernel by the pixel's place in a 4 x 4 tile.
  ivec2 q = ivec2(gl_FragCoord.xy) & 3;
  float turn = float(q.x * 4 + q.y) * (2.0 * PI / 16.0) + float(q.y) * 0.37;
  vec3 t = normalize(vec3(cos(turn), sin(turn), 0.0) - n * dot(vec3(cos(turn), sin(turn), 0.0), n));
  if (any(isnan(t))) t = normalize(cross(n, vec3(1.0, 0.0, 0.0)));
  vec3 b = cross(n, t);
  float occluded = 0.0;
  for (int i = 0; i < 16; ++i) {
    // Points of a golden-angle spiral over the hemisphere, denser near the centre.
    float fi = float(i) + 0.5;
    float r = fi / 16.0;
    float phi = fi * 2.39996;
    float h = sqrt(1.0 - r * r);  // height above the surface
    vec3 s = p + u_radius * r * (t * (cos(phi) * h) + b * (sin(phi) * h) + n * (0.15 + 0.85 * r));
    vec4 c = u_proj * vec4(s, 1.0);
    vec2 suv = c.xy / c.w * 0.5 + 0.5;
    float scene_z = viewPos(suv).z;
    float range = smoothstep(0.0, 1.0, u_radius / max(abs(p.z - scene_z), 1e-4));
    occluded += (scene_z >= s.z + 0.02 * u_radius ? 1.0 : 0.0) * range;
  }
  o_ao = pow(clamp(1.0 - occluded / 16.0, 0.0, 1.0), u_strength);
}
