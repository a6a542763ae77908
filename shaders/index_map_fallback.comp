#version 450 core
// Index shadow maps, "vanishing small polygons" (thesis 5.2): a triangle
// whose projection covers only a few texels is hit or missed by the texel
// centres all or nothing. Such a triangle is credited analytically instead:
// its exact solid angle (parallel light: its projected area over the
// window's) x the lobe toward its centroid x the fraction of its vertices the
// id map shows visible. It is flagged, and the reduction skips its texels,
// so its flux counts once. One invocation per (triangle, sample) pair.
//
// A vertex is visible when its texel shows the triangle itself, nothing, or
// a surface not in front of the vertex. A vertex on a finely tessellated
// surface is where texel-centre sampling fails: its texel shows a neighbour
// at about the vertex's depth, in front of it or behind by half a texel's
// slope. Two switchable fixes (IndexMapSettings): edge taps move the lookup
// half a texel toward the centroid and accept the triangle's own id anywhere
// in the 3x3 neighbourhood; neighbour ids accept a tap showing a triangle
// that shares the vertex (internal edges).

layout(local_size_x = 64) in;

const uint kNone = 0xffffffffu;
// Depth slack of the vertex test, relative to the vertex's depth: float
// depths (reversed near/z in a 32-bit float) are good to ~1e-7; an occluder
// nearer than 1e-5 of the distance is at the vertex for all practical use.
const float kDepthSlack = 1e-5;
// "Well in front" of a vertex, relative to its depth (see vertexVisibility).
const float kClearlyInFront = 0.25;

vec3 faceForward(int face);
vec3 faceUp(int face);
vec3 faceRight(int face);
int dominantFace(vec3 d);
float directionWeight(uint b, vec3 d);
uvec2 quantize(float q);
void accumulate(uint index, uvec2 v);
vec3 samplePosition(uint b);
float sampleNear(uint b);
float sampleFar(uint b);
float sampleHalfExtent(uint b);
float sampleScale(uint b);
mat3 sampleWorldFromCube(uint b);
bool sampleIsParallel(uint b);
uint sampleSlot(uint b);
void markSeen(uint b, uint t);
uint sampleOwnTriangle(uint b);
uint sampleFaceMask(uint b);
uint sampleHalfMask(uint b);
uint sampleFirstLayer(uint b);
bool sampleMayReach(uint b, vec3 lo, vec3 hi);

layout(binding = 0) uniform usampler2DArray u_id_map;    // (receiver, triangle)
layout(binding = 1) uniform sampler2DArray u_depth_map;  // reversed depth, 0 = nothing

layout(std430, binding = 0) readonly buffer Receivers { uvec2 receivers[]; };  // (front, back)
// Per (sample, triangle): u_generation when this batch found the triangle
// small in the sample's map; anything else (an older batch's) is "not small".
layout(std430, binding = 4) writeonly buffer SmallFlags { uint small_flags[]; };
layout(std430, binding = 5) readonly buffer Positions { float positions[]; };  // 9 per triangle
layout(std430, binding = 6) buffer Counter { uint credited_count; uint touched_count; };  // as index_map_common.comp
// Work items: (triangle, sample of the batch) pairs the sample may have
// drawn. Only those are visited, so a big level costs what the samples
// reach, not all of it.
layout(std430, binding = 7) readonly buffer Pairs { uvec2 pairs[]; };

layout(location = 0) uniform int u_resolution;
layout(location = 1) uniform uint u_receiver_count;
layout(location = 2) uniform uint u_triangle_count;
layout(location = 4) uniform float u_small_texels;  // "small": projection below this many texels
layout(location = 5) uniform int u_edge_taps;
layout(location = 6) uniform int u_neighbour_ids;
layout(location = 8) uniform uint u_pair_count;
layout(location = 11) uniform uint u_generation;  // this batch's small flags

// One sample's frame, read once per (triangle, sample).
struct Sample {
  vec3 position;
  mat3 cube_from_world;
  float near_m, far_m, half_extent_m;
  bool parallel;
  uint face_mask, half_mask, first_layer;
};

vec3 corner(uint t, int k) {
  uint i = 9u * t + 3u * uint(k);
  return vec3(positions[i], positions[i + 1u], positions[i + 2u]);
}

// Exact position equality: the triangles of one mesh share bit-equal corners.
bool sharesCorner(uint t, vec3 v) {
  uvec3 bits = floatBitsToUint(v);
  for (int k = 0; k < 3; ++k) {
    if (all(equal(floatBitsToUint(corner(t, k)), bits))) return true;
  }
  return false;
}

// Continuous texel coordinates of cube-coordinate offset `d` on `face`.
vec2 texelOn(Sample s, int face, vec3 d) {
  float scale = s.parallel ? s.half_extent_m : dot(d, faceForward(face));
  vec2 uv = vec2(dot(d, faceRight(face)), dot(d, faceUp(face))) / scale;
  return (uv * 0.5 + 0.5) * float(u_resolution);
}

// Where world point `p` lands in the sample's map: its face, texel position
// and depth along the face's forward axis. False when that part is not
// rendered.
bool mapPosition(Sample s, vec3 p, out int face, out vec2 texel, out float depth_m) {
  vec3 d = s.cube_from_world * (p - s.position);
  face = s.parallel ? 4 : dominantFace(d);
  depth_m = dot(d, faceForward(face));
  if ((s.face_mask & (1u << uint(face))) == 0u) return false;
  if (depth_m < s.near_m || (s.parallel && depth_m > s.far_m)) return false;
  texel = texelOn(s, face, d);
  float res = float(u_resolution);
  if (texel.x < 0.0 || texel.y < 0.0 || texel.x > res || texel.y > res) return false;
  if ((s.half_mask & (1u << uint(face))) != 0u && texel.y <= 0.5 * res) return false;
  return true;
}

// -1: the vertex is outside the rendered map; 0: hidden; 1: visible.
int vertexVisibility(Sample s, uint t, vec3 v, vec3 tri_centre) {
  int face;
  vec2 texel;
  float depth_m;
  if (!mapPosition(s, v, face, texel, depth_m)) return -1;
  if (u_edge_taps != 0) {
    vec3 dc = s.cube_from_world * (tri_centre - s.position);
    if (s.parallel || dot(dc, faceForward(face)) > 0.0) {
      vec2 toward = texelOn(s, face, dc) - texel;
      float len = length(toward);
      if (len > 0.0) texel += toward * min(1.0, 0.5 / len);
    }
  }
  int res = u_resolution;
  int first_row = (s.half_mask & (1u << uint(face))) != 0u ? res / 2 : 0;
  ivec2 base = clamp(ivec2(floor(texel)), ivec2(0, first_row), ivec2(res - 1));
  int layer = int(s.first_layer) + face;
  // The vertex's own texel: its id, its depth, a neighbour's id.
  uvec2 id = texelFetch(u_id_map, ivec3(base, layer), 0).xy;
  if (id.y == t) return 1;
  float depth = texelFetch(u_depth_map, ivec3(base, layer), 0).r;
  if (depth <= 0.0) return 1;  // cleared: nothing in front
  float tap_m = s.parallel ? s.far_m - depth * (s.far_m - s.near_m) : s.near_m / depth;
  float scale_m = s.parallel ? s.far_m : depth_m;
  if (tap_m >= depth_m - kDepthSlack * scale_m) return 1;
  // A vertex whose own texel shows a surface well in front of it (by a
  // quarter of its distance) is hidden: that surface shares no corner with
  // it (bar grazing views), and its own or a neighbour's id a texel away
  // would only put it on the occluder's silhouette, as would depth a texel
  // away, widening every silhouette by a texel of false visibility (a bias
  // that grows with the silhouettes a sample sees). Most hidden vertices
  // stop here, after two fetches.
  if (tap_m < depth_m - kClearlyInFront * scale_m) return 0;
  if (u_neighbour_ids != 0 && id.y != kNone && sharesCorner(id.y, v)) return 1;
  if (u_edge_taps == 0) return 0;
  // Edge taps: the 3x3 neighbourhood, by id only.
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) {
      ivec2 p = base + ivec2(dx, dy);
      if ((dx == 0 && dy == 0) || p.x < 0 || p.x >= res || p.y < first_row || p.y >= res) continue;
      uint tap = texelFetch(u_id_map, ivec3(p, layer), 0).y;
      if (tap == t) return 1;
      if (u_neighbour_ids != 0 && tap != kNone && tap != id.y && sharesCorner(tap, v)) return 1;
    }
  }
  return 0;
}

// Whether the triangle (corners v0-v2, n2 = (v1 - v0) x (v2 - v0)) is small
// in the sample's map; if so, its analytic share (fixed-point units, before
// visibility).
bool classify(Sample s, uint b, vec3 v0, vec3 v1, vec3 v2, vec3 n2, out float share) {
  share = 0.0;
  vec3 tri_centre = (v0 + v1 + v2) / 3.0;
  int face;
  vec2 texel;
  float depth_m;
  if (!mapPosition(s, tri_centre, face, texel, depth_m)) return false;
  float res = float(u_resolution);
  if (s.parallel) {
    vec3 travel = transpose(s.cube_from_world)[2];
    float projected_m2 = 0.5 * abs(dot(n2, travel));
    float window_m2 = 4.0 * s.half_extent_m * s.half_extent_m;
    if (projected_m2 >= u_small_texels * window_m2 / (res * res)) return false;
    share = projected_m2 / window_m2 * sampleScale(b) * res * res;
    return true;
  }
  vec3 d = tri_centre - s.position;
  float dist = length(d);
  // A cos / r^2 against the solid angle of the centroid's texel.
  float approx_sr = abs(dot(n2, d)) / (2.0 * dist * dist * dist);
  vec2 uv = texel / res * 2.0 - 1.0;
  float r2 = 1.0 + dot(uv, uv);
  float texel_sr = 4.0 / (res * res) / (r2 * sqrt(r2));
  if (approx_sr >= u_small_texels * texel_sr) return false;
  // Van Oosterom & Strackee (1983): tan(omega / 2) = |a . (b x c)| /
  // (abc + (a.b)c + (a.c)b + (b.c)a); the triple product from the edges,
  // a . ((b - a) x (c - a)), keeps its precision far away.
  vec3 a = v0 - s.position, c1 = v1 - s.position, c2 = v2 - s.position;
  float la = length(a), l1 = length(c1), l2 = length(c2);
  float triple = dot(a, n2);
  float denom = la * l1 * l2 + dot(a, c1) * l2 + dot(a, c2) * l1 + dot(c1, c2) * la;
  float omega = 2.0 * atan(abs(triple), denom);
  share = omega * directionWeight(b, s.cube_from_world * d);
  return true;
}

// Credits triangle t for sample b; writes its flag.
void creditTriangle(uint t, uint b, vec3 v0, vec3 v1, vec3 v2, vec3 n2, uvec2 sides) {
  Sample s;
  s.position = samplePosition(b);
  s.cube_from_world = transpose(sampleWorldFromCube(b));
  s.near_m = sampleNear(b);
  s.far_m = sampleFar(b);
  s.half_extent_m = sampleHalfExtent(b);
  s.parallel = sampleIsParallel(b);
  s.face_mask = sampleFaceMask(b);
  s.half_mask = sampleHalfMask(b);
  s.first_layer = sampleFirstLayer(b);
  // The side the sample sees (parallel light: the side facing against its
  // travel). When it receives nothing the texels are worthless to the
  // reduction anyway, so the flag may stay 0 and the work is skipped.
  bool front = s.parallel ? dot(n2, transpose(s.cube_from_world)[2]) < 0.0 : dot(n2, v0 - s.position) < 0.0;
  uint receiver = front ? sides.x : sides.y;
  float share = 0.0;
  bool small = receiver < u_receiver_count && t != sampleOwnTriangle(b) && classify(s, b, v0, v1, v2, n2, share);
  if (!small) return;
  small_flags[b * u_triangle_count + t] = u_generation;
  if (!(share > 0.0)) return;

  vec3 tri_centre = (v0 + v1 + v2) / 3.0;
  int visible = 0, testable = 0;
  vec3 corners[3] = vec3[3](v0, v1, v2);
  for (int k = 0; k < 3; ++k) {
    int vis = vertexVisibility(s, t, corners[k], tri_centre);
    if (vis >= 0) {
      ++testable;
      visible += vis;
    }
  }
  if (visible == 0) return;
  markSeen(b, t);  // seen, if only by a vertex: it must stay drawn
  accumulate(sampleSlot(b) * u_receiver_count + receiver, quantize(share * float(visible) / float(testable)));
  atomicAdd(credited_count, 1u);
}

void main() {
  // One invocation per pair; pairs over x and, past 65535 groups, z.
  uint group = gl_WorkGroupID.z * gl_NumWorkGroups.x + gl_WorkGroupID.x;
  uint item = group * gl_WorkGroupSize.x + gl_LocalInvocationID.x;
  if (item >= u_pair_count) return;
  uint t = pairs[item].x, b = pairs[item].y;
  vec3 v0 = corner(t, 0), v1 = corner(t, 1), v2 = corner(t, 2);
  // Outside the sample's reach the map drew nothing to test against; the
  // flag stays "not small" so its texels (if any) are reduced.
  if (!sampleMayReach(b, min(v0, min(v1, v2)), max(v0, max(v1, v2)))) return;
  vec3 n2 = cross(v1 - v0, v2 - v0);  // front normal x twice the area
  creditTriangle(t, b, v0, v1, v2, n2, receivers[t]);
}
