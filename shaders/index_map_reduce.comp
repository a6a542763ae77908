#version 450 core
// Index shadow maps (thesis 5.2): reduces a batch of id maps into per-receiver
// shares of each sample's flux. Each invocation walks a run of kRun texels of
// one row and sums consecutive texels of the same receiver before one atomic
// add, so the atomics fall with the map's coherence. Every texel is rounded
// to 64-bit fixed point on its own, so run lengths and the order of the
// atomics never change the result (deterministic).

layout(local_size_x = 64) in;

const uint kNone = 0xffffffffu;
const int kRun = 16;

struct FaceWeights {
  vec3 forward, right, up, axis;
  uint lobe;
  float cos_inner, cos_outer, scale;
  bool uniform_texels;
};
FaceWeights faceWeights(uint b, int face);
float texelWeight(FaceWeights w, ivec2 texel);
uvec2 quantize(float q);
uvec2 add64(uvec2 a, uvec2 b);
void accumulate(uint index, uvec2 v);
uint sampleSlot(uint b);
void markSeen(uint b, uint t);

layout(binding = 0) uniform usampler2DArray u_id_map;  // (receiver, triangle) per texel

// Per rendered layer: x sample in batch, y cube face, z first row, w texture layer.
layout(std430, binding = 2) readonly buffer Layers { uvec4 layers[]; };
// Per (sample, triangle): u_generation when the fallback credits the
// triangle analytically, so its texels are skipped here.
layout(std430, binding = 4) readonly buffer SmallFlags { uint small_flags[]; };

layout(location = 1) uniform uint u_receiver_count;
layout(location = 2) uniform uint u_triangle_count;
layout(location = 3) uniform int u_skip_small;
layout(location = 11) uniform uint u_generation;  // this batch's small flags

layout(location = 0) uniform int u_resolution;

bool isSmall(uint b, uint triangle) {
  return small_flags[b * u_triangle_count + triangle] == u_generation;
}

void main() {
  uvec4 layer = layers[gl_WorkGroupID.y];
  int runs_per_row = (u_resolution + kRun - 1) / kRun;
  int run = int(gl_GlobalInvocationID.x);
  int row = run / runs_per_row;
  if (row >= u_resolution || row < int(layer.z)) return;
  int col0 = (run - row * runs_per_row) * kRun;
  uint b = layer.x;
  int face = int(layer.y);
  uint row_base = sampleSlot(b) * u_receiver_count;
  FaceWeights weights = faceWeights(b, face);

  uint current = kNone, marked = kNone;
  uvec2 sum = uvec2(0u);
  for (int i = 0; i < kRun; ++i) {
    int col = col0 + i;
    if (col >= u_resolution) break;
    uvec2 id = texelFetch(u_id_map, ivec3(col, row, int(layer.w)), 0).xy;
    // Any triangle shown, absorbing or small ones too, hides what is behind it.
    if (id.y != kNone && id.y != marked) {
      markSeen(b, id.y);
      marked = id.y;
    }
    if (id.x >= u_receiver_count) continue;  // nothing, or an absorbing side
    if (u_skip_small != 0 && isSmall(b, id.y)) continue;
    uvec2 q = quantize(texelWeight(weights, ivec2(col, row)));
    if (id.x != current) {
      if (current != kNone) accumulate(row_base + current, sum);
      current = id.x;
      sum = q;
    } else {
      sum = add64(sum, q);
    }
  }
  if (current != kNone) accumulate(row_base + current, sum);
}
