out float v_t;
out vec2 v_ndc;
void main() {
  // One triangle covering the screen; v_t = 0 at the bottom edge, 1 at the top.
  vec2 p = vec2(float((gl_VertexID & 1) << 2) - 1.0, float((gl_VertexID & 2) << 1) - 1.0);
  v_t = p.y * 0.5 + 0.5;
  v_ndc = p;
  gl_Position = vec4(p, 1.0, 1.0);
}
