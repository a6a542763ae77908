#version 450 core
// svit-walk's statistics overlay (samples/walk/walk_overlay.cpp): flat 2D
// quads given in framebuffer pixels, origin at the top-left corner, y down
// (stb_easy_font's convention).

layout(location = 0) in vec2 a_position_px;

layout(location = 0) uniform vec2 u_target_px;  // framebuffer width, height

void main() {
  vec2 ndc = a_position_px / u_target_px * 2.0 - 1.0;
  gl_Position = vec4(ndc.x, -ndc.y, 0.0, 1.0);
}
