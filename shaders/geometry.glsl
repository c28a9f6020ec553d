// Shared by surface.vert and shadow.vert: the world position and normal of a vertex of a plain
// mesh (mode 0), an instanced sphere (mode 1: a_inst0 = centre, u_radius) or an instanced tube
// (mode 2: the unit tube mapped from a_inst0 to a_inst1, radius u_radius, or at each end at least
// u_tube_min times its distance from u_tube_eye: a minimum width on screen); compiled with
// INSTANCED, of an instanced mesh (placed by a_axis_x, a_axis_y, a_axis_z, a_origin, bent by the
// travelling wave; see DrawInstances in core/drawlist.h). A variant of its own, not a fourth mode:
// llvmpipe runs every side of a branch, and vertex shading is its serial part.
layout(location = 0) in vec3 a_pos;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec2 a_uv;
layout(location = 3) in vec3 a_inst0;
layout(location = 4) in vec3 a_inst1;
layout(location = 5) in vec3 a_color;  // per-vertex colour; (1, 1, 1) where a mesh has none
layout(location = 6) in vec3 a_axis_x;  // INSTANCED, per instance: local axes in world space
layout(location = 7) in vec3 a_axis_y;
layout(location = 8) in vec3 a_axis_z;
layout(location = 9) in vec3 a_origin;
layout(location = 10) in vec4 a_tint_phase;  // INSTANCED, per instance: rgb tint, wave phase
layout(location = 11) in float a_gloss;  // per-vertex wet sheen 0..1; 0 where a mesh has none
layout(location = 12) in float a_clarity;  // per-vertex share of the transmission 0..1; 1 where a mesh has none
layout(location = 13) in float a_wrinkle;  // per-vertex depth of the wrinkle map 0..1; 0 where a mesh has none

uniform int u_mode;
uniform float u_radius;
uniform float u_tube_min;  // mode 2: the least radius at 1 m from u_tube_eye, m (0: none)
uniform vec3 u_tube_eye;
uniform vec4 u_wave;  // INSTANCED: amplitude, wave number, wave_start, 1 / (wave_start − wave_end)

// The wave's sideways displacement x += f(z) = a(z)·sin(phase − k·(start − z)), a = A·s²,
// s = clamp((start − z)/(start − end), 0, 1); returns f and df/dz.
vec2 waveAt(float z, float phase) {
  float d = u_wave.z - z;
  float s = clamp(d * u_wave.w, 0.0, 1.0);
  float ds = (s > 0.0 && s < 1.0) ? -u_wave.w : 0.0;  // ds/dz
  float th = phase - u_wave.y * d;
  float a = u_wave.x * s * s;
  return vec2(a * sin(th), 2.0 * u_wave.x * s * ds * sin(th) + a * cos(th) * u_wave.y);
}

void instancedVertex(out vec3 p, out vec3 n) {
  vec2 f = waveAt(a_pos.z, a_tint_phase.w);
  vec3 q = vec3(a_pos.x + f.x, a_pos.yz);
  // The bend's Jacobian J = [1 0 f'; 0 1 0; 0 0 1] takes normals by J^-T: n.z −= f'·n.x.
  vec3 m = vec3(a_normal.xy, a_normal.z - f.y * a_normal.x);
  p = a_origin + q.x * a_axis_x + q.y * a_axis_y + q.z * a_axis_z;
  // Normals by the inverse transpose of M = [X Y Z], as its cofactor matrix det(M)·M^-T (the
  // columns Y×Z, Z×X, X×Y) signed by det(M): right for any invertible M, scaled or sheared.
  vec3 cx = cross(a_axis_y, a_axis_z), cy = cross(a_axis_z, a_axis_x), cz = cross(a_axis_x, a_axis_y);
  n = sign(dot(a_axis_x, cx)) * (m.x * cx + m.y * cy + m.z * cz);
}

#ifdef INSTANCED
void worldVertex(out vec3 p, out vec3 n) { instancedVertex(p, n); }
vec3 vertexColor() { return a_color * a_tint_phase.rgb; }  // times the copy's tint
#else
void worldVertex(out vec3 p, out vec3 n) {
  if (u_mode == 1) {
    p = a_inst0 + u_radius * a_pos;
    n = a_normal;
  } else if (u_mode == 2) {
    vec3 d = a_inst1 - a_inst0;
    float len = length(d);
    vec3 w = len > 0.0 ? d / len : vec3(0.0, 1.0, 0.0);
    vec3 helper = abs(w.y) < 0.9 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0);
    vec3 u = normalize(cross(helper, w));
    vec3 v = cross(w, u);
    vec3 axis = a_inst0 + a_pos.z * d;
    float r = max(u_radius, u_tube_min * distance(axis, u_tube_eye));
    p = axis + r * (a_pos.x * u + a_pos.y * v);
    n = a_normal.x * u + a_normal.y * v;
  } else {
    p = a_pos;
    n = a_normal;
  }
}
vec3 vertexColor() { return a_color; }
#endif
