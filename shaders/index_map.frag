#version 450 core
// Index shadow maps (thesis 5.2): writes, per texel, the receiver the visible
// side of the nearest triangle stands for (kNoReceiver = absorbs, still
// occludes) and the triangle's index, for the reduction and the fallback.

layout(std430, binding = 0) readonly buffer Receivers { uvec2 receivers[]; };  // (front, back) per triangle

flat in uint v_triangle;

layout(location = 0) out uvec2 o_id;  // (receiver, triangle)

void main() {
  uvec2 r = receivers[v_triangle];
  o_id = uvec2(gl_FrontFacing ? r.x : r.y, v_triangle);
}
