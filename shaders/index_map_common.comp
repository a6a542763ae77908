#version 450 core
// Shared by index_map_reduce.comp and index_map_fallback.comp, linked into
// each program as a second compute shader object: the per-sample records,
// the cube faces, the lobe profiles and the fixed-point accumulators. The
// CPU twin is runtime/src/indexmaps/index_map_layouts.cpp; keep them in step.

const uint kNone = 0xffffffffu;
const uint kLobeCosine = 0u;
const uint kLobeIsotropic = 1u;
const uint kLobeSpot = 2u;
const uint kLobeParallel = 3u;

// One sample of the batch (IndexMapRenderer's SampleGpu, std430).
struct SampleGpu {
  vec4 position_near;  // xyz world position (parallel: window centre), w near plane, m
  vec4 cube_x_far;     // world_from_cube column 0; w far plane (parallel), m
  vec4 cube_y_half;    // world_from_cube column 1; w half window side (parallel), m
  vec4 cube_z_scale;   // world_from_cube column 2; w fixed-point units per (sr x profile), or per texel (parallel)
  vec4 axis_cube;      // xyz lobe axis in cube coordinates
  vec4 lobe_params;    // x cos_inner, y cos_outer
  uvec4 info;          // x lobe, y layout, z slot, w own triangle
  uvec4 faces;         // x rendered face mask, y half-face mask, z first layer
  vec4 reach_lo;       // xyz: the box its light can matter in (PointSample::reach); everywhere when unset
  vec4 reach_hi;
};
layout(std430, binding = 1) readonly buffer Samples { SampleGpu samples[]; };

// Per (slot, receiver): a 64-bit fixed-point sum as (low, high) words.
layout(std430, binding = 3) buffer Accumulators { uint acc[]; };
// Which blocks of kCellBlock accumulators (slot * receivers + receiver,
// counted from 0) hold a sum: a flag each, and the list of the flagged
// ones, in the order they were first added to. Only those come back to the
// CPU (index_map_compact.comp), so a read-back costs what the samples lit,
// not slots x the level's receivers.
const uint kCellBlock = 64u;
layout(std430, binding = 9) buffer TouchedFlags { uint touched[]; };
layout(std430, binding = 10) buffer TouchedList { uint touched_list[]; };
// Triangles the fallback credited; blocks in touched_list.
layout(std430, binding = 6) buffer Counter { uint credited_count; uint touched_count; };

layout(location = 0) uniform int u_resolution;

// Which static triangles each slot's maps showed: a bit per triangle,
// u_seen_words words per slot; u_seen_words 0 = not asked for. What the
// runtime's lit-set culling draws (PointSample::static_triangles).
layout(std430, binding = 8) buffer SeenTriangles { uint seen[]; };
layout(location = 9) uniform uint u_seen_words;
layout(location = 10) uniform uint u_static_triangles;

// Accessors, so the programs that link this file need not repeat SampleGpu.
vec3 samplePosition(uint b) { return samples[b].position_near.xyz; }
float sampleNear(uint b) { return samples[b].position_near.w; }
float sampleFar(uint b) { return samples[b].cube_x_far.w; }
float sampleHalfExtent(uint b) { return samples[b].cube_y_half.w; }
float sampleScale(uint b) { return samples[b].cube_z_scale.w; }
mat3 sampleWorldFromCube(uint b) {
  return mat3(samples[b].cube_x_far.xyz, samples[b].cube_y_half.xyz, samples[b].cube_z_scale.xyz);
}
bool sampleIsParallel(uint b) { return samples[b].info.x == kLobeParallel; }
uint sampleSlot(uint b) { return samples[b].info.z; }
uint sampleOwnTriangle(uint b) { return samples[b].info.w; }
uint sampleFaceMask(uint b) { return samples[b].faces.x; }
uint sampleHalfMask(uint b) { return samples[b].faces.y; }
uint sampleFirstLayer(uint b) { return samples[b].faces.z; }
// Records that sample b's map shows triangle t (static ones only).
void markSeen(uint b, uint t) {
  if (u_seen_words == 0u || t >= u_static_triangles) return;
  atomicOr(seen[samples[b].info.z * u_seen_words + t / 32u], 1u << (t % 32u));
}
// Whether a box [lo, hi] may meet the sample's reach (the maps drew nothing outside it).
bool sampleMayReach(uint b, vec3 lo, vec3 hi) {
  return all(lessThanEqual(samples[b].reach_lo.xyz, hi)) && all(lessThanEqual(lo, samples[b].reach_hi.xyz));
}

const vec3 kFaceForward[6] = vec3[6](vec3(1, 0, 0), vec3(-1, 0, 0), vec3(0, 1, 0), vec3(0, -1, 0),
                                     vec3(0, 0, 1), vec3(0, 0, -1));
const vec3 kFaceUp[6] = vec3[6](vec3(0, 0, 1), vec3(0, 0, 1), vec3(0, 0, 1), vec3(0, 0, 1),
                                vec3(0, 1, 0), vec3(0, 1, 0));

vec3 faceForward(int face) { return kFaceForward[face]; }
vec3 faceUp(int face) { return kFaceUp[face]; }
vec3 faceRight(int face) { return cross(kFaceForward[face], kFaceUp[face]); }

// The cube face a direction (cube coordinates) falls on: the dominant axis.
int dominantFace(vec3 d) {
  vec3 a = abs(d);
  if (a.x >= a.y && a.x >= a.z) return d.x >= 0.0 ? 0 : 1;
  if (a.y >= a.z) return d.y >= 0.0 ? 2 : 3;
  return d.z >= 0.0 ? 4 : 5;
}

float lobeProfile(uint lobe, float cos_inner, float cos_outer, float c) {
  if (lobe == kLobeCosine) return max(c, 0.0);
  if (lobe == kLobeIsotropic) return 1.0;
  if (lobe == kLobeSpot) {
    if (cos_inner <= cos_outer) return c >= cos_outer ? 1.0 : 0.0;
    float t = clamp((c - cos_outer) / (cos_inner - cos_outer), 0.0, 1.0);
    return t * t;
  }
  return 0.0;
}

// Fixed-point weight of the lobe toward `d` (cube coordinates, any length),
// per steradian: profile x (sample weight x 2^40 / normaliser).
float directionWeight(uint b, vec3 d) {
  float c = dot(d, samples[b].axis_cube.xyz) / length(d);
  return lobeProfile(samples[b].info.x, samples[b].lobe_params.x, samples[b].lobe_params.y, c) *
         samples[b].cube_z_scale.w;
}

// Per-texel weights of one sample's face, set up once per run of texels.
struct FaceWeights {
  vec3 forward, right, up, axis;  // cube coordinates
  uint lobe;
  float cos_inner, cos_outer, scale;
  bool uniform_texels;  // parallel: every texel carries `scale`
};

FaceWeights faceWeights(uint b, int face) {
  FaceWeights w;
  w.forward = faceForward(face);
  w.right = faceRight(face);
  w.up = faceUp(face);
  w.axis = samples[b].axis_cube.xyz;
  w.lobe = samples[b].info.x;
  w.cos_inner = samples[b].lobe_params.x;
  w.cos_outer = samples[b].lobe_params.y;
  w.scale = samples[b].cube_z_scale.w;
  w.uniform_texels = w.lobe == kLobeParallel;
  return w;
}

// Fixed-point weight of texel (i, j): solid angle by the midpoint rule,
// (2/res)^2 / (1 + u^2 + v^2)^(3/2), x profile x scale; parallel: uniform.
float texelWeight(FaceWeights w, ivec2 texel) {
  if (w.uniform_texels) return w.scale;
  float h = 2.0 / float(u_resolution);
  vec2 uv = (vec2(texel) + 0.5) * h - 1.0;
  vec3 d = w.forward + uv.x * w.right + uv.y * w.up;
  float r2 = dot(d, d);
  float inv_r = inversesqrt(r2);
  float omega = h * h * inv_r * inv_r * inv_r;
  return omega * lobeProfile(w.lobe, w.cos_inner, w.cos_outer, dot(d, w.axis) * inv_r) * w.scale;
}

// Rounds a non-negative fixed-point value (< 2^64) to (low, high) words. A
// float has 24 significant bits, so q - high * 2^32 is exact.
uvec2 quantize(float q) {
  q = roundEven(max(q, 0.0));
  float high = floor(q * (1.0 / 4294967296.0));
  float low = q - high * 4294967296.0;
  return uvec2(uint(low), uint(high));
}

uvec2 add64(uvec2 a, uvec2 b) {
  uint carry;
  uint low = uaddCarry(a.x, b.x, carry);
  return uvec2(low, a.y + b.y + carry);
}

// acc[index] += v. The low word's wrap carries into the high word; the
// number of wraps depends only on the total, so the result is the same in
// any order of the atomic adds (deterministic).
void accumulate(uint index, uvec2 v) {
  if (v.x == 0u && v.y == 0u) return;
  uint old = atomicAdd(acc[2u * index], v.x);
  uint high = v.y + (old + v.x < old ? 1u : 0u);
  if (high != 0u) atomicAdd(acc[2u * index + 1u], high);
  // The first add to a block lists it (the plain read spares the atomic
  // once it is flagged; the exchange decides).
  uint block = index / kCellBlock;
  if (touched[block] == 0u && atomicExchange(touched[block], 1u) == 0u) {
    touched_list[atomicAdd(touched_count, 1u)] = block;
  }
}
