// Depth-only in the shadow pass (the framebuffer has no colour buffer); a constant colour where
// one exists (the bare-draw benchmark).
out vec4 o_color;
void main() { o_color = vec4(0.8, 0.8, 0.8, 1.0); }
