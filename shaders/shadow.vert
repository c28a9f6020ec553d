uniform mat4 u_view_proj;

void main() {
  vec3 p, n;
  worldVertex(p, n);
  gl_Position = u_view_proj * vec4(p, 1.0);
}
