#version 450 core
// Index maps, last stage: the accumulator blocks the gather added to
// (index_map_common.comp's touched_list) copied into one packed buffer for
// a single read-back, and zeroed with their flags, so the next gather
// starts from zero without clearing slots x receivers accumulators. One
// work group per listed block, one invocation per accumulator.

layout(local_size_x = 64) in;  // = kCellBlock

layout(std430, binding = 3) buffer Accumulators { uint acc[]; };  // (low, high) per cell
layout(std430, binding = 9) buffer TouchedFlags { uint touched[]; };
layout(std430, binding = 10) readonly buffer TouchedList { uint touched_list[]; };
// Per listed block i: its kCellBlock cells' (low, high) words from 2 * 64 * i.
layout(std430, binding = 11) writeonly buffer Packed { uint copied[]; };

layout(location = 0) uniform uint u_listed;  // blocks in touched_list
layout(location = 1) uniform uint u_cells;   // accumulators in use

void main() {
  // Blocks over x and, past 65535 groups, z.
  uint item = gl_WorkGroupID.z * gl_NumWorkGroups.x + gl_WorkGroupID.x;
  if (item >= u_listed) return;
  uint block = touched_list[item];
  uint lane = gl_LocalInvocationID.x;
  uint cell = block * 64u + lane;
  uint to = 2u * (item * 64u + lane);
  // Past the last cell in use the copy is left unwritten: the CPU reads
  // only cells in use.
  if (cell < u_cells) {
    copied[to] = acc[2u * cell];
    copied[to + 1u] = acc[2u * cell + 1u];
    acc[2u * cell] = 0u;
    acc[2u * cell + 1u] = 0u;
  }
  if (lane == 0u) touched[block] = 0u;
}
