#version 450 core
// Interpolates the runtime's per-patch irradiance deltas at the static
// mesh's welded vertices: delta[v] = sum_i weight_i * patch_delta[patch_i],
// weights = shares of the area of the triangle sides around v (they sum to
// 1). Lists built once by the SceneRenderer (scene_renderer_static_mesh.cpp);
// bindings in runtime/src/gl/scene_renderer_bindings.h.

layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer PatchDeltas { vec4 patch_delta[]; };  // lux
layout(std430, binding = 1) readonly buffer Offsets { uint offsets[]; };          // vertex_count + 1
layout(std430, binding = 2) readonly buffer Entries { uvec2 entries[]; };         // (patch, weight bits)
layout(std430, binding = 3) writeonly buffer VertexDeltas { vec4 vertex_delta[]; };

layout(location = 0) uniform uint u_vertex_count;

void main() {
  uint v = gl_GlobalInvocationID.x;
  if (v >= u_vertex_count) return;
  vec3 sum = vec3(0.0);
  for (uint i = offsets[v]; i < offsets[v + 1u]; ++i) {
    uvec2 e = entries[i];
    sum += uintBitsToFloat(e.y) * patch_delta[e.x].xyz;
  }
  vertex_delta[v] = vec4(sum, 0.0);
}
