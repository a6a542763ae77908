#version 450 core
// Static geometry of a baked level: world-space triangles with lightmap
// UVs, and the runtime's irradiance delta interpolated at welded vertices
// (delta_to_vertices.comp), front and back side. Vertex layout:
// runtime/src/gl/scene_renderer_static_mesh.h (StaticVertex).

layout(location = 0) in vec3 a_position;    // world, metres
layout(location = 1) in vec3 a_normal;      // world, unit, front side
layout(location = 2) in vec2 a_uv0;
layout(location = 3) in vec2 a_uv1;
layout(location = 4) in vec2 a_uv_lightmap;  // page coordinates, v down the rows
layout(location = 5) in uvec2 a_delta_vertex;  // welded vertex of the front, back side

layout(std430, binding = 3) readonly buffer VertexDeltas { vec4 vertex_delta[]; };  // lux

layout(location = 0) uniform mat4 u_clip_from_world;
layout(location = 18) uniform int u_use_deltas;  // 0: no runtime deltas bound

out vec3 v_position;
out vec3 v_normal;
out vec2 v_uv0;
out vec2 v_uv1;
out vec2 v_uv_lightmap;
out vec3 v_delta_front;
out vec3 v_delta_back;

void main() {
  v_position = a_position;
  v_normal = a_normal;
  v_uv0 = a_uv0;
  v_uv1 = a_uv1;
  v_uv_lightmap = a_uv_lightmap;
  v_delta_front = u_use_deltas != 0 ? vertex_delta[a_delta_vertex.x].xyz : vec3(0.0);
  v_delta_back = u_use_deltas != 0 ? vertex_delta[a_delta_vertex.y].xyz : vec3(0.0);
  gl_Position = u_clip_from_world * vec4(a_position, 1.0);
}
