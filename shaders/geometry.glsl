// Shared by surface.vert and shadow.vert: the world position and normal of a vertex of a plain
// mesh (mode 0), an instanced sphere (mode 1: a_inst0 = centre, u_radius) or an instanced tube
// (mode 2: the unit tube mapped from a_inst0 to a_inst1, radius u_radius).
layout(location = 0) in vec3 a_pos;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec2 a_uv;
layout(location = 3) in vec3 a_inst0;
layout(location = 4) in vec3 a_inst1;
layout(location = 5) in vec3 a_color;  // per-vertex colour; (1, 1, 1) where a mesh has none

uniform int u_mode;
uniform float u_radius;

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
    p = a_inst0 + u_radius * (a_pos.x * u + a_pos.y * v) + a_pos.z * d;
    n = a_normal.x * u + a_normal.y * v;
  } else {
    p = a_pos;
    n = a_normal;
  }
}
