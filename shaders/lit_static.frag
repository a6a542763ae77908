#version 450 core
// Static geometry: radiance = albedo x (lightmap irradiance + runtime delta
// (per runtime patch, svit_runtime_delta.frag, or the runtime's lightmap-space
// delta map) + runtime lights' direct irradiance + the masked baked lights'
// direct irradiance, shadow mask x caster map) / pi + emission, the
// emission scaled as its bake emitter is (a lamp dimmed or off).
// Albedo = base colour factor x base colour texture (sRGB-decoded by the
// texture format). Single-sided surfaces are black from behind; the lightmap
// holds irradiance in lux (docs/architecture.md "Units and conventions").
// Link with svit_shading.frag (the shared functions declared below).
// Bindings and uniform locations: runtime/src/gl/scene_renderer_bindings.h.

in vec3 v_position;
in vec3 v_normal;
in vec2 v_uv0;
in vec2 v_uv1;
in vec2 v_uv_lightmap;
flat in uvec2 v_delta_element;
in vec2 v_corner_weights;

layout(location = 0) out vec4 o_colour;    // display sRGB
// Linear radiance, cd/m2, before exposure (what svitDisplay is given); in
// the patch-delta view the false colour itself (SceneRenderer::readRadiance).
layout(location = 1) out vec4 o_radiance;

layout(binding = 0) uniform sampler2D u_base_texture;
layout(binding = 1) uniform sampler2D u_emissive_texture;
layout(binding = 2) uniform sampler2D u_lightmap;  // irradiance, lux
layout(binding = 8) uniform sampler2D u_delta_map;  // runtime delta in lightmap space, lux (Runtime::shadingResources)
layout(location = 19) uniform int u_use_delta_map;  // 0: none bound
layout(location = 18) uniform int u_use_deltas;  // 0: no runtime delta buffers bound

layout(location = 1) uniform int u_view;  // 0 baked only, 1 runtime, 2 patch delta (ShadingView)
layout(location = 8) uniform vec4 u_base_color;       // linear factor, alpha
layout(location = 9) uniform vec3 u_emissive;         // cd/m2
layout(location = 10) uniform ivec2 u_base_texture_use;     // (present, uv set)
layout(location = 11) uniform vec4 u_base_transform;        // scale.xy, offset.xy
layout(location = 12) uniform float u_base_rotation;        // radians
layout(location = 13) uniform ivec2 u_emissive_texture_use;
layout(location = 14) uniform vec4 u_emissive_transform;
layout(location = 15) uniform float u_emissive_rotation;
layout(location = 16) uniform ivec2 u_material_flags;  // (double sided, alpha mask)
layout(location = 17) uniform float u_alpha_cutoff;
layout(location = 24) uniform float u_emission_scale;  // the lamp's dimmer (SceneRenderer::setBakedEmitterScale)
// Masked baked lights (BakeShadowMasks): lights [begin, end) of the lights
// buffer, their static visibility in this page's mask layers.
layout(binding = 9) uniform usampler2DArray u_shadow_mask;
layout(location = 25) uniform int u_masked_begin;
layout(location = 26) uniform int u_masked_end;
// 1: the batch draws backs no baked light reaches (BakeBackUv kUnlitBackPage):
// they have no texels, so neither the lightmap nor the masks are read.
layout(location = 27) uniform int u_unlit_side;

vec3 svitDirectIrradiance(vec3 p, vec3 n);
struct GpuLight {
  vec4 position;
  vec4 direction;
  vec4 intensity;
  vec4 shadow;
  vec4 shadow_texel;
  mat4 shadow_from_world;
};
layout(std430, binding = 4) readonly buffer Lights { GpuLight lights[]; };
// Masked area lights' triangles: per light a header (x: element count),
// then per element its corners (wound to face the emitting side) and its
// luminance, cd/m2 (gl::AreaLightBuffer).
layout(std430, binding = 5) readonly buffer AreaLights { vec4 area[]; };
vec3 svitUnshadowedIrradiance(GpuLight light, vec3 p, vec3 n, out float distance_m);
float svitShadowVisibility(GpuLight light, vec3 p, vec3 n, float distance_m, float phi);
float svitShadowVisibilityTaps(GpuLight light, vec3 p, vec3 n, float distance_m, float phi, int taps);
layout(location = 5) uniform int u_shadow_taps;  // PCF taps of one map (svit_shading.frag)
float svitPixelNoise();
vec3 svitDisplay(vec3 radiance);
vec3 svitDeltaFalseColour(vec3 delta, vec3 under);
vec4 svitRuntimeDelta(uint element, vec2 corner_weights);

const float kPi = 3.14159265358979;
// Alpha of o_radiance: svit::SurfaceKind (the picture metric tells static
// surfaces from dynamic objects by it; the clear leaves 0).
const float kSurfaceKind = 1.0;

// KHR_texture_transform: offset + R(rotation) * (scale * uv), rotation
// counter-clockwise in UV space (runtime/src/scene/texture_sampling.cpp).
vec2 transformUv(vec2 uv, vec4 scale_offset, float rotation) {
  vec2 s = uv * scale_offset.xy;
  float c = cos(rotation), n = sin(rotation);
  return scale_offset.zw + vec2(c * s.x + n * s.y, -n * s.x + c * s.y);
}

// A masked light's static visibility at lightmap coordinates uv: bilinear
// over the four texels around, each counted only where its channel names
// this light (owner); what another light of the channel owns reads 0.
float maskVisibility(vec2 uv, int channel, int owner) {
  ivec2 size = textureSize(u_shadow_mask, 0).xy;
  vec2 f = uv * vec2(size) - 0.5;
  ivec2 base = ivec2(floor(f));
  vec2 a = f - vec2(base);
  float taps[4];
  for (int k = 0; k < 4; ++k) {
    ivec2 at = clamp(base + ivec2(k & 1, k >> 1), ivec2(0), size - 1);
    uint v = texelFetch(u_shadow_mask, ivec3(at, channel / 4), 0)[channel % 4];
    taps[k] = int(v >> 8) == owner ? float(v & 255u) / 255.0 : 0.0;
  }
  return mix(mix(taps[0], taps[1], a.x), mix(taps[2], taps[3], a.x), a.y);
}

// Sutherland-Hodgman against the receiver's plane dot(n, v) >= 0 (v
// relative to the receiver): a triangle becomes at most a quadrilateral.
int clipToHemisphere(vec3 c[3], vec3 n, out vec3 v[4]) {
  int count = 0;
  for (int i = 0; i < 3; ++i) {
    vec3 from = c[i], to = c[(i + 1) % 3];
    float h_from = dot(n, from), h_to = dot(n, to);
    if (h_from >= 0.0) v[count++] = from;
    if ((h_from >= 0.0) != (h_to >= 0.0)) v[count++] = from + (to - from) * (h_from / (h_from - h_to));
  }
  return count;
}

// Lambert's polygon formula: the cosine-weighted solid angle of a
// triangle at p, clipped to the hemisphere of n (polygon_irradiance.cpp).
float triangleCosineSolidAngle(vec3 c[3], vec3 n) {
  vec3 v[4];
  int count = clipToHemisphere(c, n, v);
  if (count < 3) return 0.0;
  float sum = 0.0;
  for (int i = 0; i < count; ++i) {
    vec3 a = normalize(v[i]), b = normalize(v[(i + 1) % count]);
    vec3 axis = cross(a, b);
    float s = length(axis);
    if (s > 1e-7) sum += atan(s, dot(a, b)) * dot(n, axis / s);
  }
  return min(abs(0.5 * sum), kPi);
}

// An area light's unshadowed irradiance at p: each element p is in front
// of gives its luminance x its cosine-weighted solid angle.
vec3 areaIrradiance(int offset, vec3 p, vec3 n) {
  int count = int(area[offset].x);
  vec3 e = vec3(0.0);
  for (int k = 0; k < count; ++k) {
    int at = offset + 1 + 4 * k;
    vec3 c[3] = vec3[3](area[at].xyz - p, area[at + 1].xyz - p, area[at + 2].xyz - p);
    vec3 emitting = cross(c[1] - c[0], c[2] - c[0]);  // faces away from p when p is in front
    if (dot(emitting, c[0]) >= 0.0) continue;
    e += area[at + 3].rgb * triangleCosineSolidAngle(c, n);
  }
  return e;
}

// What the dynamic objects let through of area light samples
// [first, first + count): their caster maps' visibilities weighted by the
// point-to-point form factor cos * cos / d^2 toward each sample. The
// samples' spread softens the edge, so the frame's PCF taps are shared
// between them (each map gets at least one, hardware-filtered).
float areaShadowVisibility(int first, int count, vec3 p, vec3 n, float phi) {
  int taps = max(max(u_shadow_taps, 1) / count, 1);
  float seen = 0.0, total = 0.0;
  for (int s = first; s < first + count; ++s) {
    GpuLight sample_light = lights[s];
    vec3 v = sample_light.position.xyz - p;
    float d2 = max(dot(v, v), 1e-12);
    float d = sqrt(d2);
    vec3 l = v / d;
    float w = max(dot(n, l), 0.0) * max(-dot(sample_light.direction.xyz, l), 0.0) / d2;
    if (w <= 0.0) continue;
    total += w;
    seen += w * svitShadowVisibilityTaps(sample_light, p, n, d, phi, taps);
  }
  return total > 0.0 ? seen / total : 1.0;
}

// A masked area light whose samples start at lights[i]: unshadowed x mask
// x dimmer x what the samples' caster maps let through.
vec3 maskedAreaIrradiance(int i, vec3 p, vec3 n, vec2 uv, float phi) {
  GpuLight head = lights[i];
  float mask = maskVisibility(uv, int(head.shadow_texel.z), int(head.shadow_texel.w));
  if (mask <= 0.0 || head.intensity.r <= 0.0) return vec3(0.0);
  vec3 e = areaIrradiance(int(head.direction.w), p, n);
  if (max(e.r, max(e.g, e.b)) <= 0.0) return vec3(0.0);
  return e * (mask * head.intensity.r * areaShadowVisibility(i, int(head.intensity.w), p, n, phi));
}

// The masked lights' direct light: unshadowed x static mask x what their
// caster maps (dynamic objects only) let through; dimmers are in the
// lights' intensities.
vec3 maskedIrradiance(vec3 p, vec3 n, vec2 uv) {
  vec3 sum = vec3(0.0);
  float phi = svitPixelNoise() * 6.28318530718;
  for (int i = u_masked_begin; i < u_masked_end; ++i) {
    GpuLight light = lights[i];
    if (int(light.position.w) == 3) {
      sum += maskedAreaIrradiance(i, p, n, uv, phi);
      i += int(light.intensity.w) - 1;  // past its samples
      continue;
    }
    float distance_m;
    vec3 e = svitUnshadowedIrradiance(light, p, n, distance_m);
    if (max(e.r, max(e.g, e.b)) <= 0.0) continue;
    float mask = maskVisibility(uv, int(light.shadow_texel.z), int(light.shadow_texel.w));
    if (mask <= 0.0) continue;
    sum += e * (mask * svitShadowVisibility(light, p, n, distance_m, phi));
  }
  return sum;
}

void main() {
  vec4 base = u_base_color;
  if (u_base_texture_use.x != 0) {
    vec2 uv = transformUv(u_base_texture_use.y == 1 ? v_uv1 : v_uv0, u_base_transform, u_base_rotation);
    base *= texture(u_base_texture, uv);
  }
  if (u_material_flags.y != 0 && base.a < u_alpha_cutoff) discard;
  bool front = gl_FrontFacing;
  if (!front && u_material_flags.x == 0) {
    o_colour = vec4(0.0, 0.0, 0.0, 1.0);  // single-sided: black from behind
    o_radiance = vec4(0.0, 0.0, 0.0, kSurfaceKind);
    return;
  }
  vec3 n = normalize(v_normal) * (front ? 1.0 : -1.0);
  vec3 irradiance = u_unlit_side != 0 ? vec3(0.0) : texture(u_lightmap, v_uv_lightmap).rgb;
  bool masked = u_masked_end > u_masked_begin && u_unlit_side == 0;
  vec3 emission = u_emissive * u_emission_scale;
  if (u_emissive_texture_use.x != 0) {
    vec2 uv = transformUv(u_emissive_texture_use.y == 1 ? v_uv1 : v_uv0, u_emissive_transform, u_emissive_rotation);
    emission *= texture(u_emissive_texture, uv).rgb;
  }
  // rgb: added irradiance; w: the lightmap's factor minus 1 (dimmed lamps).
  vec4 delta = vec4(0.0);
  if (u_use_delta_map != 0) {
    delta = texture(u_delta_map, v_uv_lightmap);
  } else if (u_use_deltas != 0) {
    delta = svitRuntimeDelta(front ? v_delta_element.x : v_delta_element.y, v_corner_weights);
  }
  vec3 change = irradiance * delta.w + delta.rgb;
  if (u_view == 2) {
    if (masked) irradiance += maskedIrradiance(v_position, n, v_uv_lightmap);
    o_colour = vec4(svitDeltaFalseColour(change, svitDisplay(base.rgb * irradiance / kPi + emission)), 1.0);
    o_radiance = vec4(o_colour.rgb, kSurfaceKind);
    return;
  }
  if (u_view == 1) irradiance += change + svitDirectIrradiance(v_position, n);
  // A delta may overshoot the baked value (a shadow deeper than the light).
  irradiance = max(irradiance, vec3(0.0));
  if (masked) irradiance += maskedIrradiance(v_position, n, v_uv_lightmap);
  o_radiance = vec4(base.rgb * irradiance / kPi + emission, kSurfaceKind);
  o_colour = vec4(svitDisplay(o_radiance.rgb), 1.0);
}
