#version 450 core
// The runtime's displayed irradiance delta (lux, rgb) and the factor on the
// lightmap minus 1 (w: dimmed baked emitters) at a point of a static
// triangle side, at the resolution of the runtime patches: the n x n
// sub-triangle of the bake element under the point, and the delta
// interpolated between its welded vertices, as Runtime::irradianceAt does
// (runtime/src/receivers/runtime_patches.cpp RuntimePatches::subTriangle; tables
// built by runtime/src/receivers/delta_surface.cpp). A host links this file and
// binds Runtime::shadingResources()' delta_elements, delta_slots and
// vertex_deltas at these bindings (runtime/src/render/scene_renderer_bindings.h).

layout(std430, binding = 1) readonly buffer DeltaElements { uvec2 delta_element[]; };  // (n, first slot)
layout(std430, binding = 2) readonly buffer DeltaSlots { uvec4 delta_slot[]; };  // 3 welded vertices, used
layout(std430, binding = 3) readonly buffer VertexDeltas { vec4 vertex_delta[]; };  // lux, factor - 1

// `element` = bake triangle * 2 + side (1: the back); (w1, w2) = the
// barycentric weights of the bake triangle's corners 1 and 2 at the point.
// Shade with lightmap * (1 + w) + rgb.
vec4 svitRuntimeDelta(uint element, vec2 w) {
  uvec2 e = delta_element[element];
  int n = int(e.x);
  if (n == 0) return vec4(0.0);
  float u = clamp(w.x, 0.0, 1.0) * float(n), v = clamp(w.y, 0.0, 1.0) * float(n);
  int i = min(int(u), n - 1), j = min(int(v), n - 1);
  if (i + j > n - 1) j = n - 1 - i;  // on the far edge
  float fu = u - float(i), fv = v - float(j);
  bool flipped = fu + fv > 1.0 && i + j < n - 1;
  // Barycentrics in the sub-triangle; a flipped one has corners
  // (i+1, j), (i+1, j+1), (i, j+1).
  vec2 s = flipped ? vec2(fu + fv - 1.0, 1.0 - fu) : vec2(fu, fv);
  uvec4 corner = delta_slot[e.y + uint((i * n + j) * 2 + (flipped ? 1 : 0))];
  if (corner.w == 0u) return vec4(0.0);
  if ((element & 1u) == 1u) s = s.yx;  // back-side sub-triangles are wound the other way
  return vertex_delta[corner.x] * (1.0 - s.x - s.y) + vertex_delta[corner.y] * s.x + vertex_delta[corner.z] * s.y;
}
