#version 450 core
// Shared fragment functions of svit's shading (no main): per-pixel direct
// light of punctual and directional lights with soft (multi-tap PCF) depth
// shadows, the display transform (exposure, filmic curve, sRGB encode) and
// the false colour of irradiance deltas. Link this as a second fragment
// shader object beside lit_static.frag or lit_dynamic.frag (GLSL links
// several shader objects of one stage; those files declare the prototypes).
// Units: positions in metres, irradiance in lux, radiance in cd/m2.
// Bindings: runtime/src/gl/scene_renderer_bindings.h.

struct GpuLight {
  vec4 position;      // xyz world; w: 0 point, 1 spot, 2 directional
  vec4 direction;     // xyz unit travel direction; w: cos(outer cone)
  vec4 intensity;     // rgb candela (point, spot) or lux (directional); w: cos(inner cone)
  vec4 shadow;        // x: 0 none, 1 cube, 2 face; y: layer; z, w: near, far (cube)
  vec4 shadow_texel;  // x: texel size per metre of distance; y: texel size (m, orthographic);
                      // z, w: a masked light's mask channel and owner (lit_static.frag)
  mat4 shadow_from_world;
};

layout(std430, binding = 4) readonly buffer Lights { GpuLight lights[]; };
layout(binding = 3) uniform samplerCubeArrayShadow u_shadow_cubes;
layout(binding = 4) uniform sampler2DArrayShadow u_shadow_faces;

layout(location = 2) uniform float u_exposure;        // multiplies radiance before the curve
layout(location = 3) uniform int u_light_begin;       // lights shaded: [begin, end)
layout(location = 4) uniform int u_light_end;
layout(location = 5) uniform int u_shadow_taps;       // PCF taps, >= 1
layout(location = 6) uniform float u_shadow_texel;    // 1 / shadow map size
layout(location = 7) uniform float u_delta_reference; // lux shown fully saturated in false colour

const float kPi = 3.14159265358979;
// PCF kernel radius in shadow-map texels: wide enough to hide texel stairs,
// narrow enough to keep contact shadows.
const float kPcfRadiusTexels = 2.0;
// Normal offset of the lookup point, in texels of the map at that distance
// (with the depth pass's polygon offset this removes shadow acne).
const float kNormalOffsetTexels = 1.5;

// Interleaved gradient noise (Jimenez 2014): rotates the tap pattern per
// pixel, so the few taps read as fine grain instead of banding.
float svitPixelNoise() { return fract(52.9829189 * fract(dot(gl_FragCoord.xy, vec2(0.06711056, 0.00583715)))); }

// Vogel (golden-angle) disk sample i of n, unit radius, rotated by phi.
vec2 svitVogel(int i, int n, float phi) {
  float r = sqrt((float(i) + 0.5) / float(n));
  float theta = float(i) * 2.39996323 + phi;
  return r * vec2(cos(theta), sin(theta));
}

float svitShadowFace(GpuLight light, vec3 p, float phi, int taps) {
  vec4 clip = light.shadow_from_world * vec4(p, 1.0);
  if (clip.w <= 0.0) return 1.0;
  vec3 ndc = clip.xyz / clip.w;
  if (abs(ndc.x) > 1.0 || abs(ndc.y) > 1.0) return 1.0;  // outside the map: unshadowed
  vec2 uv = ndc.xy * 0.5 + 0.5;
  // Beyond the far plane compares as at it: a caster map (fitted to the
  // dynamic objects) still shadows what lies behind them.
  float ref = min(ndc.z * 0.5 + 0.5, 1.0);
  float lit = 0.0;
  for (int i = 0; i < taps; ++i) {
    vec2 o = svitVogel(i, taps, phi) * (kPcfRadiusTexels * u_shadow_texel);
    lit += texture(u_shadow_faces, vec4(uv + o, light.shadow.y, ref));
  }
  return lit / float(taps);
}

// `d`: from the light to the (offset) point, world metres.
float svitShadowCube(GpuLight light, vec3 d, float phi, int taps) {
  vec3 a = abs(d);
  float major = max(a.x, max(a.y, a.z));
  float n = light.shadow.z, f = light.shadow.w;
  // The depth a 90-degree face with planes n, f stores at eye depth `major`.
  float ref = min(0.5 * ((f + n) / (f - n) - 2.0 * f * n / ((f - n) * major)) + 0.5, 1.0);
  vec3 axis = d / max(length(d), 1e-30);
  vec3 t1 = normalize(cross(axis, abs(axis.y) < 0.99 ? vec3(0, 1, 0) : vec3(1, 0, 0)));
  vec3 t2 = cross(axis, t1);
  float radius = kPcfRadiusTexels * light.shadow_texel.x * major;  // metres on the face plane
  float lit = 0.0;
  for (int i = 0; i < taps; ++i) {
    vec2 o = svitVogel(i, taps, phi) * radius;
    lit += texture(u_shadow_cubes, vec4(d + o.x * t1 + o.y * t2, light.shadow.y), ref);
  }
  return lit / float(taps);
}

// Light `light`'s irradiance (lux) at p with unit normal n, unshadowed:
// inverse square, Lambert cosine, the glTF spot cone as the baker lights it
// (t^2 between the cone cosines), no range cut-off (the baker ignores range
// too). `distance_m`: to the light (0 for directional lights).
vec3 svitUnshadowedIrradiance(GpuLight light, vec3 p, vec3 n, out float distance_m) {
  int type = int(light.position.w);
  vec3 l;
  vec3 e;
  distance_m = 0.0;
  if (type == 2) {
    l = -light.direction.xyz;
    e = light.intensity.rgb;
  } else {
    vec3 v = light.position.xyz - p;
    float d2 = max(dot(v, v), 1e-12);
    distance_m = sqrt(d2);
    l = v / distance_m;
    e = light.intensity.rgb / d2;
    if (type == 1) {
      float c = dot(light.direction.xyz, -l);
      float t = clamp((c - light.direction.w) / max(light.intensity.w - light.direction.w, 1e-6), 0.0, 1.0);
      e *= t * t;
    }
  }
  return e * max(dot(n, l), 0.0);
}

// What of `light` its depth map lets through to p (1 without a map), with
// `taps` PCF taps (>= 1) in a pattern rotated by phi (radians).
float svitShadowVisibilityTaps(GpuLight light, vec3 p, vec3 n, float distance_m, float phi, int taps) {
  int kind = int(light.shadow.x);
  if (kind == 0) return 1.0;
  float texel_m = light.shadow_texel.x * distance_m + light.shadow_texel.y;
  vec3 q = p + n * (kNormalOffsetTexels * texel_m);
  return kind == 1 ? svitShadowCube(light, q - light.position.xyz, phi, taps)
                   : svitShadowFace(light, q, phi, taps);
}

// The same with the frame's PCF taps (u_shadow_taps).
float svitShadowVisibility(GpuLight light, vec3 p, vec3 n, float distance_m, float phi) {
  return svitShadowVisibilityTaps(light, p, n, distance_m, phi, max(u_shadow_taps, 1));
}

// Irradiance (lux) at world point p with unit normal n from the lights in
// [begin, end), shadowed where the light has a map.
vec3 svitDirectIrradianceRange(vec3 p, vec3 n, int begin, int end, float phi) {
  vec3 sum = vec3(0.0);
  for (int i = begin; i < end; ++i) {
    GpuLight light = lights[i];
    float distance_m;
    vec3 e = svitUnshadowedIrradiance(light, p, n, distance_m);
    if (max(e.r, max(e.g, e.b)) <= 0.0) continue;
    sum += e * svitShadowVisibility(light, p, n, distance_m, phi);
  }
  return sum;
}

// The same for this draw's lights, [u_light_begin, u_light_end), with the
// per-pixel pattern rotation.
vec3 svitDirectIrradiance(vec3 p, vec3 n) {
  return svitDirectIrradianceRange(p, n, u_light_begin, u_light_end, svitPixelNoise() * 2.0 * kPi);
}

float svitSrgbEncode(float c) {
  c = clamp(c, 0.0, 1.0);
  return c <= 0.0031308 ? 12.92 * c : 1.055 * pow(c, 1.0 / 2.4) - 0.055;
}

// Radiance (cd/m2, linear Rec.709) to display sRGB: exposure, then the
// filmic ACES fit of Narkowicz (2015), then the sRGB transfer curve.
vec3 svitDisplay(vec3 radiance) {
  vec3 x = max(radiance, vec3(0.0)) * u_exposure;
  vec3 curve = clamp((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
  return vec3(svitSrgbEncode(curve.r), svitSrgbEncode(curve.g), svitSrgbEncode(curve.b));
}

// False colour of an irradiance delta (lux) over a dimmed grey of the
// display colour `under`: red where light was added, blue where removed,
// saturating at u_delta_reference (square root: small deltas stay visible).
vec3 svitDeltaFalseColour(vec3 delta, vec3 under) {
  float y = dot(delta, vec3(0.2126, 0.7152, 0.0722));
  float s = clamp(abs(y) / max(u_delta_reference, 1e-30), 0.0, 1.0);
  vec3 grey = vec3(0.35 * dot(under, vec3(0.2126, 0.7152, 0.0722)));
  vec3 hue = y >= 0.0 ? vec3(1.0, 0.1, 0.05) : vec3(0.1, 0.3, 1.0);
  return mix(grey, hue, sqrt(s));
}
