#version 450 core
// Dynamic objects: radiance = albedo x E / pi + emission, with
//   E = indirect + direct of the baked lights and the sun (per pixel)
//       [+ direct of the runtime lights, per pixel, in the runtime view].
// Indirect light (emissive surfaces and bounces) comes from the bake's L1 SH
// probe grid, trilinear. In the runtime view it is corrected by the
// runtime's irradiance of the triangle's patch (its delta buffer entry: all
// light the runtime computes except the runtime lights' direct light, which
// is shaded here per pixel): the triangle's indirect light is what the
// runtime gives minus the baked lights' direct light at the centroid, and the
// probe grid only spreads it over the triangle (the probes' value at the
// centroid is moved onto the runtime's). An object the runtime has not lit
// yet (w of its delta-buffer entry 0: not every emitter reaching it has
// rendered) keeps the probes' light. Link with svit_shading.frag.
// Bindings: runtime/src/gl/scene_renderer_bindings.h.

in vec3 v_position;
in vec3 v_normal;
flat in vec3 v_albedo;
flat in vec3 v_emission;
flat in vec3 v_centroid;
flat in vec3 v_face_normal;
flat in vec3 v_patch_irradiance;
flat in uint v_patch_lit;
flat in uint v_double_sided;

layout(location = 0) out vec4 o_colour;    // display sRGB
// Linear radiance, cd/m2, before exposure (what svitDisplay is given); in
// the patch-delta view the false colour itself (SceneRenderer::readRadiance).
layout(location = 1) out vec4 o_radiance;

// Per colour channel: radiance SH coefficients (Y00, Y1-1, Y10, Y11), cd/m2 x sr.
layout(binding = 5) uniform sampler3D u_probe_r;
layout(binding = 6) uniform sampler3D u_probe_g;
layout(binding = 7) uniform sampler3D u_probe_b;

layout(location = 1) uniform int u_view;  // 0 baked only, 1 runtime, 2 patch delta
layout(location = 19) uniform vec3 u_probe_origin;   // centre of probe (0, 0, 0), metres
layout(location = 20) uniform vec3 u_probe_spacing;  // metres
layout(location = 21) uniform vec3 u_probe_dims;
layout(location = 22) uniform int u_use_probes;
layout(location = 23) uniform int u_baked_light_end;  // lights [0, this) are baked lights and the sun

vec3 svitDirectIrradianceRange(vec3 p, vec3 n, int begin, int end, float phi);
vec3 svitDirectIrradiance(vec3 p, vec3 n);
vec3 svitDisplay(vec3 radiance);
vec3 svitDeltaFalseColour(vec3 delta, vec3 under);

const float kPi = 3.14159265358979;
// Alpha of o_radiance: svit::SurfaceKind (the picture metric tells static
// surfaces from dynamic objects by it; the clear leaves 0).
const float kSurfaceKind = 2.0;

// Irradiance (lux) from the probe grid: radiance SH convolved with the
// clamped cosine, E(n) = pi c0 Y00 + 2pi/3 sum_m c1m Y1m(n), with
// Y00 = 0.282095 and Y1m = 0.488603 (y, z, x) (baker/.../runtime_sections.h).
vec3 probeIrradiance(vec3 p, vec3 n) {
  if (u_use_probes == 0) return vec3(0.0);
  vec3 uvw = ((p - u_probe_origin) / u_probe_spacing + 0.5) / u_probe_dims;
  vec4 basis = vec4(kPi * 0.282095, (2.0 * kPi / 3.0) * 0.488603 * vec3(n.y, n.z, n.x));
  vec3 e = vec3(dot(texture(u_probe_r, uvw), basis), dot(texture(u_probe_g, uvw), basis),
                dot(texture(u_probe_b, uvw), basis));
  return max(e, vec3(0.0));  // L1 rings below zero opposite bright light
}

void main() {
  bool front = gl_FrontFacing;
  if (!front && v_double_sided == 0u) {
    o_colour = vec4(0.0, 0.0, 0.0, 1.0);
    o_radiance = vec4(0.0, 0.0, 0.0, kSurfaceKind);
    return;
  }
  float side = front ? 1.0 : -1.0;
  vec3 n = normalize(v_normal) * side;
  vec3 indirect = probeIrradiance(v_position, n);
  vec3 correction = vec3(0.0);
  if (u_view != 0 && v_patch_lit != 0u) {
    vec3 nf = v_face_normal * side;
    // Fixed PCF rotation: every pixel of the triangle gets the same estimate.
    vec3 baked_direct = svitDirectIrradianceRange(v_centroid, nf, 0, u_baked_light_end, 0.0);
    correction = v_patch_irradiance - baked_direct - probeIrradiance(v_centroid, nf);
    // The runtime's own estimate for the triangle replaces the probes'
    // variation across it: probes gathered with few rays are noisy, the
    // triangle's index-map irradiance is not.
    if (u_view == 1) indirect = probeIrradiance(v_centroid, nf);
  }
  vec3 direct = svitDirectIrradiance(v_position, n);
  if (u_view == 2) {
    vec3 shown = v_albedo * (indirect + direct) / kPi + v_emission;
    o_colour = vec4(svitDeltaFalseColour(correction, svitDisplay(shown)), 1.0);
    o_radiance = vec4(o_colour.rgb, kSurfaceKind);
    return;
  }
  vec3 irradiance = max(indirect + correction, vec3(0.0)) + direct;
  o_radiance = vec4(v_albedo * irradiance / kPi + v_emission, kSurfaceKind);
  o_colour = vec4(svitDisplay(o_radiance.rgb), 1.0);
}
