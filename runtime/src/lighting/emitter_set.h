#pragma once
// The runtime's emitters and how the set grows: built from the bake on the
// first update with dynamic content (thesis 5.3 step 1: every baked light,
// the sun, the sky, and the bake patches carrying most of the reflected
// baseline flux), then shooters for the groups a bounce needs and for
// emissive objects.

#include <cstdint>
#include <vector>

#include "emitter.h"
#include "receivers/receivers.h"
#include "static_level.h"

namespace svit::gl {

/// Shooter groups per dynamic object: its triangles binned by the dominant
/// axis of their object-space normal (+x, -x, +y, -y, +z, -z).
inline constexpr uint32_t kObjectShooters = 6;

/// What building an emitter reads: the static level, every receiver
/// (static patches, then the objects' triangles) and the settings.
struct EmitterContext {
  const StaticLevel& level;
  const std::vector<Receiver>& receivers;
  const RuntimeSettings& settings;
};

struct EmitterSet {
  std::vector<Emitter> emitters;
  std::vector<uint32_t> group_emitter;  ///< per group: its emitter or kInvalidId
  bool baked_emitters_added = false;    ///< addBakedEmitters ran
};

/// Adds the baked emitters and the bright patch groups of the bake.
void addBakedEmitters(EmitterSet& set, const EmitterContext& context);

/// The emitter of `group` (a static shooter below static_groups, else an
/// object facing), made when it has none: with samples for `wanted_flux`
/// against the brightest `max_flux`; `bright` patches also shoot their
/// baseline.
uint32_t addGroupEmitter(EmitterSet& set, const EmitterContext& context, uint32_t group,
                         bool bright, double wanted_flux, double max_flux);

/// Erases the emitters of the groups [first_group, first_group + count)
/// (a removed object's facings; their light already retracted): their
/// records leave `emitters`, the later records move down (keeping their
/// order) and group_emitter follows; the groups have no emitter, free for
/// the next object in their slot. Returns the erased ids, ascending, for
/// emitterIdAfterErase on ids held elsewhere. Vectors keep their capacity,
/// so a steady add-and-remove allocates nothing here.
std::vector<uint32_t> eraseGroupEmitters(EmitterSet& set, uint32_t first_group, uint32_t count);

/// What emitter `id` (not erased) is after eraseGroupEmitters erased
/// `erased` (ascending).
uint32_t emitterIdAfterErase(uint32_t id, const std::vector<uint32_t>& erased);

/// A baked emitter's bake factors spread over the runtime patches
/// (Emitter::bake_shares), and its reach from them.
void initBakeShares(Emitter& e, const EmitterContext& context);

}  // namespace svit::gl
