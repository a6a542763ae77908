#version 450 core
// Dynamic objects where the runtime has them this frame: world-space
// triangles with per-triangle albedo and emission, and the runtime's
// irradiance of each triangle's patch (w = 1 once the runtime has lit the
// object). Vertex layout:
// runtime/src/render/scene_renderer_dynamic_objects.h (DynamicVertex).

layout(location = 0) in vec3 a_position;  // world, metres
layout(location = 1) in vec3 a_normal;    // world, unit, front side
layout(location = 2) in vec3 a_albedo;
layout(location = 3) in vec3 a_emission;  // cd/m2
layout(location = 4) in vec3 a_centroid;  // the triangle's, world
layout(location = 5) in vec3 a_face_normal;  // the triangle's, unit
layout(location = 6) in uvec2 a_patch_sided;  // (patch in the delta buffer or 0xffffffff, double sided)

layout(std430, binding = 0) readonly buffer PatchDeltas { vec4 patch_delta[]; };  // lux

layout(location = 0) uniform mat4 u_clip_from_world;
layout(location = 18) uniform int u_use_deltas;  // 0: no runtime delta buffer bound

out vec3 v_position;
out vec3 v_normal;
flat out vec3 v_albedo;
flat out vec3 v_emission;
flat out vec3 v_centroid;
flat out vec3 v_face_normal;
flat out vec3 v_patch_irradiance;
flat out uint v_patch_lit;  // 1: the runtime's value holds every emitter reaching the object
flat out uint v_double_sided;

void main() {
  v_position = a_position;
  v_normal = a_normal;
  v_albedo = a_albedo;
  v_emission = a_emission;
  v_centroid = a_centroid;
  v_face_normal = a_face_normal;
  bool has_patch = u_use_deltas != 0 && a_patch_sided.x != 0xffffffffu;
  v_patch_irradiance = has_patch ? patch_delta[a_patch_sided.x].xyz : vec3(0.0);
  v_patch_lit = has_patch && patch_delta[a_patch_sided.x].w > 0.5 ? 1u : 0u;
  v_double_sided = a_patch_sided.y;
  gl_Position = u_clip_from_world * vec4(a_position, 1.0);
}
