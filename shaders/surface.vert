uniform mat4 u_view_proj;
out vec3 v_world;
out vec3 v_normal;
out vec2 v_uv;
out vec3 v_color;
out float v_gloss;
out float v_clarity;
out float v_wrinkle;

void main() {
  vec3 p, n;
  worldVertex(p, n);
  v_world = p;
  v_normal = n;
  v_uv = a_uv;
  v_color = vertexColor();
  v_gloss = a_gloss;
  v_clarity = a_clarity;
  v_wrinkle = a_wrinkle;
  gl_Position = u_view_proj * vec4(p, 1.0);
}
