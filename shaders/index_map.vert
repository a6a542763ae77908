#version 450 core
// Index shadow maps (thesis 5.2): projects world triangles into one face of a
// point sample's map. Perspective faces look from the sample along the face's
// forward axis (90 degrees, reversed depth near/z so float depth keeps its
// precision far away); the parallel layout is an orthographic window of side
// 2 * half extent looking along the light's travel, depth linear and reversed.
// The frame math lives in runtime/src/gl/index_map_layouts.{h,cpp}.

layout(location = 0) in vec3 a_position_world;

layout(location = 0) uniform vec3 u_eye_world;         // sample (or window centre), m
layout(location = 1) uniform mat3 u_view_from_world;   // rows: right, up, forward
layout(location = 2) uniform int u_orthographic;       // 1: parallel layout
layout(location = 3) uniform float u_near_m;
layout(location = 4) uniform float u_far_m;            // orthographic only
layout(location = 5) uniform float u_half_extent_m;    // orthographic only

// The triangle's index: vertices are unshared, 3 per triangle, and
// gl_VertexID counts from the buffer's start in every (multi-)draw range.
flat out uint v_triangle;

void main() {
  v_triangle = uint(gl_VertexID) / 3u;
  // Subtract first, then rotate: a translation folded into a matrix loses
  // the small differences of large world coordinates.
  vec3 p = u_view_from_world * (a_position_world - u_eye_world);
  if (u_orthographic != 0) {
    gl_Position = vec4(p.xy / u_half_extent_m, (u_far_m - p.z) / (u_far_m - u_near_m), 1.0);
  } else {
    // Clip 0 <= z <= w keeps p.z >= near; window depth near / p.z.
    gl_Position = vec4(p.xy, u_near_m, p.z);
  }
}
