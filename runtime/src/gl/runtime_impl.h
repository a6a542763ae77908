#pragma once
// The state behind svit::Runtime, shared by runtime.cpp (API, validation)
// and runtime_update.cpp (the per-frame pipeline).

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "bounce_solver.h"
#include "delta_surface.h"
#include "emitter_importance.h"
#include "emitter_samples.h"
#include "index_map_culling.h"
#include "index_map_renderer.h"
#include "receivers.h"
#include "refresh_scheduler.h"
#include "runtime_patches.h"
#include "svit/baked_surfaces.h"
#include "svit/lightmap_image.h"
#include "svit/runtime.h"

namespace svit {

namespace rt = gl;

/// Shooter groups per dynamic object: its triangles binned by the dominant
/// axis of their object-space normal (+x, -x, +y, -y, +z, -z).
inline constexpr uint32_t kObjectShooters = 6;

inline double lum(const glm::dvec3& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }
inline glm::dvec3 dvec(const Rgb& c) { return {c.r, c.g, c.b}; }

enum class EmitterKind {  // same order as svit::EmitterType
  kBakedLight,    ///< a static light of the bake (BakeData emitter index)
  kSun,           ///< the baked sun
  kSky,           ///< the baked sky
  kStaticPatch,   ///< a shooter (runtime patches within one bake patch): re-shoots its baseline (bright) and deltas
  kDynamicObject, ///< one facing of a dynamic object (kObjectShooters per object): emits and reflects
  kRuntimeLight,  ///< a light the game moves
};

/// An emitter's deltas as coefficients of its share sets (lm per unit share).
struct DeltaTerms {
  uint64_t current_revision = 0;  ///< of the `current` on_current applies to
  glm::dvec3 on_current{0.0};     ///< first-round flux through `current`
  glm::dvec3 on_baseline{0.0};    ///< through `baseline` (taking the baked light back)
  glm::dvec3 direct{0.0};         ///< runtime lights: direct flux through `current`
  bool operator==(const DeltaTerms&) const = default;
};

/// One emitter and its cached form factors (thesis 5.10's cache).
struct Emitter {
  EmitterKind kind = EmitterKind::kBakedLight;
  uint32_t index = 0;  ///< bake emitter (lights, sun, sky), shooter, object * kObjectShooters + bin, light id
  uint32_t bake_emitter = kInvalidId;  ///< BakeData::emitters index when the bake lists it
  bool needs_baseline = false; ///< baked emitters and bright patches: current minus baseline
  glm::dvec3 flux{0.0};        ///< lm: the flux its shares distribute (patches: baseline B x A)
  int sample_count = 1;
  std::vector<rt::PointSample> samples;
  rt::SparseShares current, baseline;
  uint64_t current_revision = 0;  ///< Impl::shares_revisions when `current` was last set
  /// What it adds to Impl::first_flux now (runtime_deltas.cpp): per unit
  /// share of `current` (at current_revision) and of `baseline`.
  DeltaTerms summed;
  bool has_current = false, has_baseline = false;
  bool stale = true;           ///< current out of date (something moved in its region)
  bool samples_stale = true;   ///< the emitter itself moved
  Aabb region;                 ///< samples and everything its shares light
  bool region_known = false;   ///< from its maps or the bake's factors; unknown = anything may matter
  Aabb source_box;             ///< where its light leaves from (samples, lamp, shooter patches)
  /// Static triangles its baseline maps showed (PointSample::
  /// static_triangles), for lit-set culling; empty = unknown, or its
  /// samples changed since (refreshSamples clears it).
  rt::TriangleBits lit_triangles;
  bool touched = false;        ///< a dynamic object in its reach (Impl::updateReach, once per update)
  bool reach_dirty = true;     ///< touched needs recomputing: invalidated, or its reach changed
  uint64_t refreshed_frame = 0;
  /// Baked emitters: the bake's baseline factors spread over the runtime
  /// patches by area, for importance and reach before the first map.
  rt::SparseShares bake_shares;
  bool bounce_requested = false;  ///< made because a bounce had delta to shoot through it
  // Importance caching (emitter_importance.h, refresh_scheduler.h).
  double importance = 0;        ///< for the last view
  uint32_t interval = 1;        ///< frames it may wait while out of date
  bool waiting = false;         ///< out of date and not yet refreshed
  uint64_t waiting_since = 0;   ///< frame it went out of date
  uint32_t queued_interval = 1; ///< its interval then
  double settled_importance = 0; ///< its importance in the last view it was up to date in
};

struct RuntimeLightState {
  Light light;
  bool enabled = true;
  float dimmer = 1;
  bool removed = false;
  uint32_t emitter = kInvalidId;
};

struct Runtime::Impl {
  Scene scene;
  BakeData bake;
  std::string bake_dir;
  RuntimeSettings settings;
  BakedSurfaces surfaces;
  std::vector<LightmapImage> pages;

  // Receivers: runtime patches, then per object one per triangle. Groups
  // (what shoots): bake patches, then objects.
  rt::RuntimePatches patches;
  std::vector<rt::Receiver> receivers;
  uint32_t static_receivers = 0;
  uint32_t static_groups = 0;
  rt::MapTriangles static_map;
  std::vector<std::vector<uint32_t>> patch_map_triangles;  ///< per runtime patch: its static map triangles
  /// Per whole block of kShareBlockReceivers static patches: the box of
  /// their bounds (reaches() tests a block before its patches).
  std::vector<Aabb> static_block_bounds;
  float sample_offset_m = 1e-4f;
  rt::ParallelWindow window{};

  std::vector<rt::DynamicObject> objects;
  std::vector<uint32_t> object_map_base;  ///< per object: its first triangle in the dynamic map set
  rt::MapTriangles dynamic_map;          ///< what the maps draw for the objects now
  std::vector<RuntimeLightState> lights;
  std::vector<int> scene_light_to_light;  ///< Scene::lights index -> light id (-1)
  std::vector<float> bake_emitter_scale;  ///< per BakeData emitter, 1 = as baked
  /// Per static receiver: the factor on its baked light the scaled emitters
  /// give (runtime_light_scale.cpp); per static group its area mean. Empty
  /// while every baked emitter is as baked.
  std::vector<double> light_scale, group_light_scale;

  std::vector<Emitter> emitters;
  std::vector<uint32_t> group_emitter;  ///< per group: its emitter or kInvalidId
  /// Per receiver: the sum of every emitter's DeltaTerms over its shares
  /// (the bounce's first round, and runtime lights' direct flux), kept by
  /// adding what changed (runtime_deltas.cpp).
  std::vector<glm::dvec3> first_flux, direct_flux;
  uint64_t shares_revisions = 0;         ///< counts every setting of an Emitter::current
  rt::BounceSolver bounce_solver;        ///< keeps the last frame's rounds (bounce_solver.h)

  // Results, per receiver.
  std::vector<glm::dvec3> delta_total;    ///< irradiance delta incl. runtime lights' direct light, lux
  std::vector<glm::dvec3> runtime_direct; ///< direct irradiance of runtime lights, lux (shaded per pixel)
  std::vector<Rgb> display;               ///< what shading adds (temporally blended), lux
  mutable std::vector<glm::dvec3> vertex_deltas;  ///< delta_total at the welded vertices (lazy)
  /// The light scale minus 1 (x) at the welded vertices, as the last
  /// uploadDisplay showed it; empty while every baked emitter is as baked.
  std::vector<glm::dvec3> vertex_scales;
  mutable bool vertex_deltas_stale = true;
  const std::vector<glm::dvec3>& vertexDeltas() const {
    if (vertex_deltas_stale) {
      vertex_deltas = rt::vertexValues(patches, delta_total);
      vertex_deltas_stale = false;
    }
    return vertex_deltas;
  }
  bool have_content = false;              ///< dynamic objects or runtime lights exist

  // Change tracking between updates.
  std::vector<Aabb> moved_boxes;
  bool dynamic_geometry_changed = false;
  bool lighting_changed = false;
  bool pending_wanted = false;  ///< the last bounce wanted shares it did not have
  uint64_t frame = 0;
  double ms_per_sample = 0.5;  ///< running estimate for the budget
  bool has_view = false;       ///< setView() called (and not cleared)
  RuntimeView view;
  std::vector<uint32_t> view_pixels;  ///< per receiver, from the last view pass
  rt::ViewWeights view_weights;       ///< the last view pass's weights (group shares: this update only)
  rt::GroupView group_view;           ///< what the groups' light shows, last view
  double top_importance = 0;          ///< the most important emitter's, last view

  // GL (created only when the level has runtime content).
  std::unique_ptr<rt::IndexMapRenderer> renderer;
  uint32_t delta_buffer = 0;
  uint32_t delta_buffer_receivers = 0;
  mutable std::vector<uint32_t> lightmap_textures;
  std::vector<uint32_t> delta_textures;  ///< per page, GL_RGB32F at half size (delta_atlas.h)
  rt::DeltaSurfaceBuffers delta_surface;  ///< per-pixel lookup of the static deltas (delta_surface.h)
  uint32_t gl_objects_created = 0;

  FrameStats update(double budget_ms);
  void updateObjectsLit();
  Status ensureRenderer();
  void initBakeShares(Emitter& e) const;
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
  void invalidateMoved();
  void refreshSamples(Emitter& e);
  Status gatherShares(std::vector<uint32_t> emitter_ids, bool baseline, FrameStats& stats);
  DeltaTerms deltaTerms(const Emitter& e) const;
  // Baked emitters' scales as a factor on the baked light (runtime_light_scale.cpp).
  bool isPrimaryBakedEmitter(const Emitter& e) const;
  void updateLightScale();
  double lightScaleOf(uint32_t receiver) const;
  /// Takes an emitter's terms on `current` out of first_flux/direct_flux;
  /// call before replacing `current`.
  void retractCurrent(Emitter& e);
  void setCurrent(Emitter& e, rt::SparseShares shares);
  /// Brings first_flux/direct_flux up to date with every emitter's terms.
  void sumEmitterDeltas();
  void solve(FrameStats& stats, std::vector<std::pair<double, uint32_t>>& wanted);
  void uploadDisplay(FrameStats& stats);
  uint32_t addGroupEmitter(uint32_t group, bool bright, double wanted_flux, double max_flux);
  uint32_t addObjectInternal(rt::DynamicObject object);
};

}  // namespace svit
