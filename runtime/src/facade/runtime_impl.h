#pragma once
// The state behind svit::Runtime: a façade over its named parts, and the
// per-frame pipeline that ties them together.
//
//   StaticLevel      static_level.h      the level, the bake and the runtime patches (read once)
//   receivers, objects, lights           what the game moves (runtime.cpp)
//   ChangeTracker    change_tracker.h    moved boxes and change flags between updates
//   EmitterSet       emitter_set.h       the emitters with their cached shares (emitter.h)
//   DeltaAccumulator delta_accumulator.h their first-round deltas summed per receiver
//   LightScale       light_scale.h       dimmed baked emitters as a factor on the lightmap
//   ViewRanking      (below)             what the camera sees, for importance caching
//   ShadingOutputs   shading_outputs.h   the deltas shading reads, and their GL objects
//
// The pipeline (runtime_update.cpp) is thesis 5.3: bring emitters' shares up
// to date where something moved (runtime_gather.cpp), within the budget
// and by importance for the view (runtime_importance.cpp); sum their deltas
// (runtime_deltas.cpp); bounce them (runtime_solve.cpp); publish them.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "change_tracker.h"
#include "indexmaps/emitter_samples.h"
#include "indexmaps/index_map_culling.h"
#include "indexmaps/index_map_renderer.h"
#include "lighting/bounce_solver.h"
#include "lighting/delta_accumulator.h"
#include "lighting/emitter.h"
#include "lighting/emitter_importance.h"
#include "lighting/emitter_set.h"
#include "lighting/light_scale.h"
#include "lighting/static_level.h"
#include "object_slots.h"
#include "receivers/receivers.h"
#include "receivers/runtime_patches.h"
#include "receivers/shading_outputs.h"
#include "refresh_scheduler.h"
#include "svit/runtime.h"

namespace svit {

namespace rt = gl;
using rt::Emitter;
using rt::EmitterKind;
using rt::kObjectShooters;

struct RuntimeLightState {
  Light light;
  bool enabled = true;
  float dimmer = 1;
  bool removed = false;
  uint32_t emitter = kInvalidId;
};

/// The last view pass: what the camera sees ranks the emitters (thesis 5.10).
struct ViewRanking {
  bool has_view = false;  ///< setView() called (and not cleared)
  RuntimeView view;
  std::vector<uint32_t> view_pixels;  ///< per receiver, from the last view pass
  /// the last view pass's weights (group shares: this update only)
  rt::ViewWeights weights;
  rt::GroupView group_view;   ///< what the groups' light shows, last view
  double top_importance = 0;  ///< the most important emitter's, last view
};

struct Runtime::Impl {
  RuntimeSettings settings;
  rt::StaticLevel level;

  // Receivers: runtime patches, then per object one per triangle. Groups
  // (what shoots): bake patches, then kObjectShooters per object slot.
  std::vector<rt::Receiver> receivers;
  Aabb level_box;  ///< of the static patches: where the ambient bounces (Receiver::shares_ambient)
  /// Public ObjectId -> slot (object_slots.h). Everything per object below
  /// (objects, object_map_base, the shooter groups and their emitters) is
  /// indexed by slot, and a removed object's slot goes to the next one added.
  rt::ObjectSlots object_slots;
  std::vector<rt::DynamicObject> objects;  ///< per slot; a free slot's is `removed`
  /// Receiver ranges (first, count) removed objects gave back; a new object
  /// takes the first that fits, so adding and removing props for hours
  /// keeps the receiver count (and every per-receiver table) flat.
  std::vector<std::pair<uint32_t, uint32_t>> free_receivers;
  std::vector<uint32_t> object_map_base;  ///< per slot: its first triangle in the dynamic map set
  rt::MapTriangles dynamic_map;           ///< what the maps draw for the objects now
  std::vector<RuntimeLightState> lights;
  std::vector<int> scene_light_to_light;  ///< Scene::lights index -> light id (-1)
  /// dynamic objects, runtime lights or scaled baked emitters
  bool have_content = false;

  rt::ChangeTracker changes;
  rt::EmitterSet emitter_set;
  rt::DeltaAccumulator accumulator;
  rt::LightScale light_scale;
  rt::BounceSolver bounce_solver;  ///< keeps the last frame's rounds (bounce_solver.h)
  ViewRanking ranking;
  rt::ShadingOutputs outputs;

  // GL (created only when the level has runtime content).
  std::unique_ptr<rt::IndexMapRenderer> renderer;
  double ms_per_sample = 0.5;  ///< running estimate for the budget
  uint32_t gl_objects_created = 0;

  Impl() = default;
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;

  rt::EmitterContext emitterContext() const { return {level, receivers, settings}; }

  // Creation and objects (runtime.cpp).
  /// The receivers and per-receiver state of the static level.
  void initStaticReceivers();
  /// The level's own dynamic content: its dynamic instances and lights.
  Status addLevelContent(Runtime& runtime);
  /// Adds `object` in a slot (a free one first); its public id, or
  /// kInvalidId when ids ran out.
  ObjectId addObjectInternal(rt::DynamicObject object);
  /// The live object `id` is, or null (never given, or removed).
  rt::DynamicObject* liveObject(ObjectId id);
  const rt::DynamicObject* liveObject(ObjectId id) const;
  /// Frees a removed object's slot for the next object: its record, its
  /// receivers, and its facings' emitters (their light retracted first).
  void releaseObject(uint32_t slot);
  /// Renumbers the emitter ids held outside the emitter set (runtime
  /// lights') after eraseGroupEmitters.
  void renumberEmitters(const std::vector<uint32_t>& erased);
  uint32_t takeReceivers(uint32_t count);
  /// Applies `change` to an object, places it again and records the boxes
  /// it left and entered: the one path every object change takes.
  template <typename Change>
  void changeObject(rt::DynamicObject& object, Change&& change);

  // The frame (runtime_update.cpp).
  FrameStats update(double budget_ms);
  bool anythingDue() const;
  /// The index-map renderer, made on the first update with runtime content.
  Status ensureRenderer();
  /// The bake's emitters (emitter_set.h), added on that first update too.
  void ensureBakedEmitters();
  void rebuildDynamicMaps();
  void addRuntimeLightEmitters();
  void settleUnreachedBakedEmitters();
  void rankEmitters(bool by_view, FrameStats& stats);
  Status refreshScheduled(const std::vector<rt::RefreshDecision>& decisions, bool by_view,
                          FrameStats& stats);
  bool shootWanted(std::vector<std::pair<double, uint32_t>>& wanted, double budget,
                   FrameStats& stats, Status& status);
  void publish(const Status& status, FrameStats& stats);

  // Shares (runtime_gather.cpp).
  void invalidateMoved();
  void refreshSamples(Emitter& e);
  std::vector<rt::PointSample> objectFacingSamples(const Emitter& e, uint64_t seed, uint64_t stream,
                                                   bool jitter) const;
  Status gatherShares(std::vector<uint32_t> emitter_ids, bool baseline, FrameStats& stats);
  std::vector<rt::PointSample> batchSamples(const std::vector<uint32_t>& ids, size_t begin,
                                            size_t end, bool baseline);
  rt::SparseShares sparseRow(const Emitter& e, const float* row, Aabb& region, Aabb& source) const;
  void storeShares(Emitter& e, const float* row, const uint32_t* seen, size_t seen_words,
                   bool baseline, FrameStats& stats);

  // Reach and importance (runtime_importance.cpp).
  std::vector<int32_t> receiverGroups() const;
  double emitterScale(const Emitter& e) const;
  bool reaches(const Emitter& e, const Aabb& box) const;
  /// Whether a dynamic object's facing emitter has emissive triangles.
  bool facingEmits(const Emitter& e) const;
  bool reachesAnyObject(const Emitter& e) const;
  /// A static patch without static-level maps that lit-set culling will
  /// give them before its next maps (gatherShares).
  bool wantsLitSetMaps(const Emitter& e) const;
  void updateReach();
  bool needsMaps(const Emitter& e) const;
  bool outOfDate(const Emitter& e) const;
  void rankForView(FrameStats& stats);
  rt::ImportanceQuery importanceQuery(const Emitter& e, bool current_only) const;
  void settleImportance(const std::vector<rt::RefreshDecision>& refreshed);
  std::vector<rt::RefreshCandidate> refreshCandidates();

  // Masked lights' direct light as shading shows it (runtime_masked.cpp).
  /// Every masked light's direct light at a static surface point (on the
  /// side `hit` names): baked
  /// mask x unshadowed irradiance x its scale x whether a dynamic object's
  /// triangle stands between the point and the light (a ray, as the
  /// shader's caster map tests it per pixel), lux.
  glm::dvec3 maskedDirectAt(const SurfaceHit& hit) const;
  /// Whether the segment from `from` along unit `direction` for
  /// `distance_m` meets a visible dynamic object's triangle.
  bool dynamicObjectBlocks(const glm::vec3& from, const glm::vec3& direction,
                           float distance_m) const;
  /// What of masked area light k the dynamic objects let through to
  /// `from` (unit normal `n`): its point samples' cosine-weighted share
  /// that no dynamic triangle hides.
  double areaVisibility(size_t k, const glm::vec3& from, const glm::vec3& n) const;

  // Deltas and the bounce (runtime_deltas.cpp, runtime_solve.cpp).
  rt::DeltaTerms deltaTerms(const Emitter& e) const;
  void solve(FrameStats& stats, std::vector<std::pair<double, uint32_t>>& wanted);
  void updateObjectsLit();
  void uploadDisplay(FrameStats& stats);
};

template <typename Change>
void Runtime::Impl::changeObject(rt::DynamicObject& object, Change&& change) {
  changes.noteBox(object.bounds);
  change(object);
  rt::placeObject(object);
  rt::updateObjectReceivers(object, level_box, receivers);
  changes.noteBox(object.bounds);
  changes.dynamic_geometry_changed = true;
}

}  // namespace svit
