#pragma once
// A game's load on the generated house (samples/levels/house), frame after
// frame: tables slide, doors open and close, the baked lamps switch and dim,
// a runtime lamp dims and switches, props are added and removed every few
// frames, and the camera walks a loop through the rooms with importance
// caching and a sample budget. Each frame it checks what must hold for
// hours (no update error, no GL error, every statistic and delta finite)
// and now and then samples the memory resources() reports and the frame
// time. Deterministic for its seed (updates use sample budgets, never
// milliseconds), so two runs of the same seed must end on the same deltas
// bit for bit. Used by tests/soak/house_soak_test.cpp (short) and
// tests/bench/soak_bench.cpp (20,000 frames).

#include <cstdint>
#include <string>
#include <vector>

#include "svit/runtime.h"

namespace svit::soak {

/// Runtime settings for the soak: the house's importance-caching settings,
/// a budget of `samples_per_frame` point samples per update.
RuntimeSettings soakSettings(int samples_per_frame);

/// Memory and time at one frame.
struct SoakSample {
  uint64_t frame = 0;
  uint64_t host_bytes = 0;  ///< resources(): cpu_bytes summed
  uint64_t gpu_bytes = 0;   ///< resources(): gpu_bytes summed
  /// The heap glibc reports in use (mallinfo2().uordblks): the runtime's and
  /// everything else the process allocated (the GL driver's, the soak's).
  uint64_t heap_bytes = 0;
  /// resources()' "dynamic objects" line, host bytes: the objects' records
  /// and triangles, which must not grow while the live props stay the same.
  uint64_t object_bytes = 0;
  uint32_t emitters = 0;  ///< emitterStates().size(): emitter records kept
  uint32_t gl_objects = 0;
  uint32_t objects = 0;      ///< live dynamic objects
  uint32_t patches = 0;      ///< patchDeltas().size()
  double mean_frame_ms = 0;  ///< update() wall time, mean since the previous sample
  /// Host + GPU bytes of each resources() line, by name: what grew.
  std::vector<std::pair<std::string, uint64_t>> lines;
  /// Host bytes of each resources() line, by name (same order as `lines`).
  std::vector<std::pair<std::string, uint64_t>> host_lines;
};

/// The resources() line of the dynamic objects' records.
inline constexpr const char* kObjectsLine = "dynamic objects (triangles, receivers)";

/// The resources() lines whose bytes differ between two samples, as
/// "name: before -> after B", one per line.
std::string grownLines(const SoakSample& before, const SoakSample& after);

struct SoakReport {
  uint64_t frames = 0;
  uint64_t objects_added = 0, objects_removed = 0, light_changes = 0, door_moves = 0;
  uint64_t samples_rendered = 0;
  std::vector<SoakSample> samples;
  std::vector<std::string> failures;  ///< the first few broken promises, with their frame
  uint64_t failure_count = 0;
  std::vector<Rgb> final_deltas;  ///< patchDeltas() after the last frame
};

/// Runs `frames` frames on `runtime` (created over the house with
/// soakSettings), sampling memory every `sample_every` frames (a multiple of
/// the prop cycle, so every sample sees the same number of live props).
SoakReport runHouseSoak(Runtime& runtime, uint64_t seed, uint64_t frames, uint64_t sample_every);

/// The frames props are added at (every kPropEvery frames); sample_every
/// should be a multiple of it.
inline constexpr uint64_t kPropEvery = 5;

}  // namespace svit::soak
