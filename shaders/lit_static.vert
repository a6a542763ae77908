#version 450 core
// Static geometry of a baked level: world-space triangles with lightmap
// UVs, their bake elements (front, back side) and the barycentrics the
// fragment shader finds the runtime's delta at (svit_runtime_delta.frag).
// Vertices are unshared, 3 per triangle in corner order, so a corner's
// index within its triangle is gl_VertexID % 3. Vertex layout:
// runtime/src/render/scene_renderer_static_mesh.h (StaticVertex).

layout(location = 0) in vec3 a_position;    // world, metres
layout(location = 1) in vec3 a_normal;      // world, unit, front side
layout(location = 2) in vec2 a_uv0;
layout(location = 3) in vec2 a_uv1;
layout(location = 4) in vec2 a_uv_lightmap;  // page coordinates, v down the rows
layout(location = 5) in uvec2 a_delta_element;  // bake element of the front, back side

layout(location = 0) uniform mat4 u_clip_from_world;

out vec3 v_position;
out vec3 v_normal;
out vec2 v_uv0;
out vec2 v_uv1;
out vec2 v_uv_lightmap;
flat out uvec2 v_delta_element;
out vec2 v_corner_weights;  // barycentric weights of corners 1 and 2

void main() {
  v_position = a_position;
  v_normal = a_normal;
  v_uv0 = a_uv0;
  v_uv1 = a_uv1;
  v_uv_lightmap = a_uv_lightmap;
  v_delta_element = a_delta_element;
  int corner = gl_VertexID % 3;
  v_corner_weights = vec2(corner == 1 ? 1.0 : 0.0, corner == 2 ? 1.0 : 0.0);
  gl_Position = u_clip_from_world * vec4(a_position, 1.0);
}
