#pragma once
// svit::Runtime — what a game links to keep the baked lighting right while
// objects and lights move (thesis ch. 5, docs/architecture/runtime-facade.md
// "A frame"). The bake holds the static solution; the runtime tracks
// per-patch irradiance deltas against it, computed from index shadow maps
// rendered from point samples of emitters, bounced, and compensated as
// ambient; the host shades with the lightmaps plus those deltas (GLSL in
// shaders/, see shadingSources()).
//
// Threading: every member needs the GL context that was current at create()
// to be current on the calling thread; no member is thread-safe.
// Pay for what is used: a level with no dynamic objects and no runtime
// lights renders no map and allocates nothing per frame.

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "svit/bake_file.h"
#include "svit/math_types.h"
#include "svit/resource_use.h"
#include "svit/scene.h"
#include "svit/status.h"

namespace svit {

/// Tuning of the runtime; defaults suit a game at 60 Hz on a real GPU.
struct RuntimeSettings {
  /// Static geometry in index maps: the bake's LOD proxies (true) or the
  /// full static triangles cut into runtime patches (false). With proxies,
  /// each bake patch whose proxy takes under half its own sub-triangles
  /// (detailed meshes) is drawn as its proxy faces re-cut to a quarter of a
  /// patch, each piece standing for the nearest runtime patch; every other
  /// bake patch (flat walls and floors, which simplify to about what they
  /// were) keeps its own sub-triangles, so its patch outlines are exact.
  bool use_proxies = true;
  /// Runtime patches over the static surfaces (the bake's patches cut to
  /// about this many): the resolution of dynamic shadows and deltas.
  int target_patches = 1024;
  /// Shooters: groups of runtime patches that emit as one (hierarchical
  /// shooting); about this many over the static surfaces, <= target_patches.
  int target_shooters = 128;
  int map_resolution = 128;  ///< texels per map face edge, 16..2048
  /// Point samples per emitter: from min to max, in proportion to flux.
  int min_samples_per_emitter = 1;
  int max_samples_per_emitter = 16;
  /// Static patches re-shot as secondary emitters: the brightest ones whose
  /// baseline flux covers this share of all reflected flux, in (0, 1]. They
  /// are also all the static level's light a dynamic object receives, and
  /// the dim groups are most of what lights a face in another object's
  /// shadow: lower values leave such faces dark. 1 takes every lit group,
  /// the long tail of dim ones at one sample each, many times the emitters
  /// on a large level (docs/performance.md has the figures).
  double secondary_emitter_share = 0.99;
  int max_bounces = 4;  ///< rounds of delta bounces per update, >= 0
  /// stop bouncing below this share of the first round's |delta|
  double bounce_stop_share = 0.005;
  bool ambient_compensation = true;  ///< unshot delta energy as ambient (thesis 5.5)
  /// Temporal smoothing of the displayed deltas (thesis 4.2.5): each frame
  /// moves this share of the way to the new value; 1 = off. In (0, 1].
  float temporal_blend = 1.0f;
  /// Artifact handling of thesis 5.2 (on by default; tests switch it off).
  bool small_polygon_fallback = true;
  bool edge_taps = true;
  bool neighbour_ids = true;
  bool jitter_map_roll = true;  ///< rotate each sample's map frame (aliasing)
  /// Lit-set culling: once an emitter's static-level maps exist (its
  /// baseline), its later maps draw only the runs of static triangles those
  /// maps showed, plus the dynamic objects. Exact for emitters whose samples
  /// stay put (objects only hide static surfaces, so nothing else can show),
  /// and fewer triangles than the box of its reach wherever walls hide part
  /// of that box. Emitters whose samples move keep the box. Off: box only.
  bool lit_set_culling = true;
  /// Maps of samples with no lit set (moving ones, first maps) draw the
  /// nearest geometry first and then only what it does not hide (two-pass
  /// occlusion culling): same result, and from inside a room the rest of
  /// a closed level is not drawn. Off: everything in the map's frustum.
  bool occlusion_culling = true;
  uint64_t seed = 1;  ///< sample placement; same seed, same result

  /// Importance caching (thesis 5.9-5.10), used while a view is set
  /// (setView): an id pass from the camera counts the pixels of every
  /// visible patch; each emitter's cached shares give its importance for
  /// that view (light it puts on visible pixels, directly and through the
  /// secondary emitters it lights); emitters whose maps are out of date
  /// refresh most important first, the rest at intervals that double each
  /// time their importance falls by 4x. Off (or no view): brightest first.
  bool importance_caching = true;
  int view_pass_width = 128;      ///< id pass pixels across (height by aspect), 16..1024
  int max_refresh_interval = 32;  ///< frames an unimportant out-of-date emitter may wait, 1..1024
  /// A budget in point samples (one map each) per update, 0 = none; unlike
  /// milliseconds it gives the same schedule on every machine.
  int max_samples_per_frame = 0;
  /// Reference mode: every emitter with a dynamic object in its reach is
  /// re-rendered every update, ignoring views and budgets (what caching is
  /// measured against).
  bool refresh_all = false;
  /// Lightmap-space delta pages (ShadingResources::delta_textures) for hosts
  /// that shade with lightmap(uv) * (1 + delta(uv).a) + delta(uv).rgb. The per-pixel lookup
  /// (ShadingResources::vertex_deltas) shows the same deltas without them:
  /// a host shading with it (SceneRenderer does when the pages are absent)
  /// sets this false and pays neither the textures nor their per-update
  /// rasterisation on the CPU.
  bool delta_textures = true;
};

/// A dynamic object the game adds at run time (the level's own dynamic nodes
/// are added by create()).
struct DynamicMesh {
  std::string name;               ///< for messages and statistics
  std::vector<Vec3> positions;    ///< object space, metres
  std::vector<uint32_t> indices;  ///< 3 per triangle, CCW front
  Rgb albedo{0.5f, 0.5f, 0.5f};   ///< diffuse reflectance, each in [0, 1)
  Rgb emission{0, 0, 0};          ///< emitted luminance, cd/m2 (>= 0)
  bool double_sided = false;
};

using ObjectId = uint32_t;
using LightId = uint32_t;
inline constexpr uint32_t kInvalidId = 0xffffffffu;

/// The camera the importance of emitters is judged for (Runtime::setView).
struct RuntimeView {
  Vec3 position{0, 0, 0};
  Vec3 look_at{0, 0, -1};
  Vec3 up{0, 1, 0};
  float yfov_rad = 1.0471975512f;  ///< vertical field of view, (0, pi)
  float aspect = 16.0f / 9.0f;     ///< width / height, > 0
  float near_m = 0.05f;            ///< > 0
};

/// Why an emitter's maps were rendered in an update.
enum class RefreshReason : uint32_t {
  kImportant = 0,  ///< out of date and among the important ones (refreshes every frame)
  /// its importance rose since it went out of date (a door opened, the view turned)
  kPromoted = 1,
  kRoundRobin = 2,    ///< out of date and unimportant: its interval ran out
  kLightChanged = 3,  ///< dimmed or switched without cached shares to scale
  kBounce = 4,        ///< a new secondary emitter a bounce needed
  kRefreshAll = 5,    ///< RuntimeSettings::refresh_all
  kNoView = 6,        ///< no view set (or caching off): brightest first
};
const char* refreshReasonName(RefreshReason reason);

/// What kind of light an emitter is (EmitterState).
enum class EmitterType : uint32_t {
  kBakedLight = 0,  ///< a static light of the bake
  kSun = 1,
  kSky = 2,
  /// a group of static patches: a lamp's emissive surface or a bright secondary emitter
  kStaticPatch = 3,
  kDynamicObject = 4,  ///< one facing of a dynamic object (emissive, or reflecting a bounce)
  kRuntimeLight = 5,
};

/// One emitter of the runtime and its cache (Runtime::emitterStates).
struct EmitterState {
  EmitterType type = EmitterType::kBakedLight;
  uint32_t bake_emitter = kInvalidId;  ///< BakeData::emitters index, or kInvalidId
  uint32_t light = kInvalidId;         ///< LightId of a runtime light, or kInvalidId
  /// for the current view: lux x pixels it accounts for (0 without a view)
  double importance = 0;
  uint32_t interval = 1;         ///< frames it may wait while out of date, by importance
  bool out_of_date = false;      ///< something moved in its reach since its last refresh
  bool has_maps = false;         ///< cached shares exist
  uint64_t refreshed_frame = 0;  ///< update() count of its last refresh, 0 = never
  uint32_t samples = 0;
};

/// One emitter refreshed by an update, and why.
struct EmitterRefresh {
  uint32_t emitter = 0;  ///< emitterStates() index (until the next removeObject())
  RefreshReason reason = RefreshReason::kImportant;
  double importance = 0;
};

/// What one update() did, by stage. Times are CPU wall clock including a
/// GL finish per stage (so they are honest on any driver).
struct FrameStats {
  double maps_ms = 0;       ///< rendering index maps
  double reduction_ms = 0;  ///< GPU reduction + read-back of per-patch sums
  double bounce_ms = 0;     ///< CPU: the emitters' deltas summed, bounce rounds and ambient
  double upload_ms = 0;     ///< delta buffer upload for shading
  double total_ms = 0;
  uint32_t emitters_refreshed = 0;  ///< emitters whose maps were rendered this frame
  uint32_t emitters_pending = 0;    ///< emitters still out of date (budget ran out)
  uint32_t samples_rendered = 0;    ///< point samples (one map each)
  uint32_t faces_rendered = 0;      ///< raster passes (a cube map is 6)
  uint64_t triangles_drawn = 0;     ///< triangles the raster passes submitted (after culling)
  uint64_t triangles_hidden = 0;    ///< triangles occlusion culling found hidden and left out
  uint64_t texels_reduced = 0;
  uint32_t fallback_triangles = 0;  ///< small polygons credited by vertex visibility
  uint32_t bounce_rounds = 0;
  double unshot_share = 0;                ///< delta energy compensated as ambient / total |delta|
  uint32_t gl_objects_created = 0;        ///< buffers/textures allocated during this update
  double view_ms = 0;                     ///< camera id pass and importance (0 without a view)
  uint32_t visible_patches = 0;           ///< patches the view pass saw
  std::vector<EmitterRefresh> refreshes;  ///< which emitters refreshed and why, in order
  bool idle = false;                      ///< nothing to do: no dynamic content changed
  std::string error;  ///< empty, or why the update could not finish (a GL failure)
};

/// What the host binds to shade static geometry (shadingSources()).
struct ShadingResources {
  /// GL buffer (std430 vec4 per patch, patchDeltas() order): displayed
  /// irradiance delta, lux, RGB in xyz; w: the factor on the lightmap under
  /// a static patch minus 1 (baked emitters dimmed or off:
  /// setBakedEmitterScale; shade with lightmap * (1 + w) + xyz), and for a
  /// dynamic object's patch 1 once every emitter reaching the object has
  /// rendered since it appeared (0: shade it by the probe grid). 0 when the
  /// level has no runtime content.
  uint32_t patch_delta_buffer = 0;
  uint32_t patch_count = 0;
  /// Lightmap pages as GL_RGB32F textures (irradiance, lux), bake page order.
  std::vector<uint32_t> lightmap_textures;
  /// The displayed static deltas per runtime patch, looked up per pixel by
  /// shaders/svit_runtime_delta.frag (svitRuntimeDelta(element, weights)):
  /// per bake element (static triangle * 2 + side) its tessellation (uvec2
  /// n, first slot); per slot the welded vertices of its sub-triangle
  /// (uvec4, w = 1 when used); per welded vertex the delta (vec4: lux, and
  /// the lightmap's factor minus 1). Exactly what irradianceAt adds, at any
  /// mesh resolution. 0 until the
  /// first update that had runtime content.
  uint32_t delta_elements = 0;
  uint32_t delta_slots = 0;
  uint32_t vertex_deltas = 0;
  /// Per page (RGBA32F): the displayed delta (lux, RGB; alpha the factor
  /// minus 1, as above) in the same lightmap
  /// coordinates at half resolution, interpolated across runtime patches;
  /// shade with lightmap(uv) * (1 + delta(uv).a) + delta(uv).rgb. Empty until the first update that
  /// had runtime content.
  std::vector<uint32_t> delta_textures;
};

/// The runtime's view of one dynamic object.
struct ObjectInfo {
  std::string name;
  int instance = -1;  ///< Scene::instances index, -1 for addObject objects
  Mat4 world_from_object;
  uint32_t first_patch = 0;  ///< its patches (one per triangle) in patchDeltas()
  uint32_t patch_count = 0;
  bool visible = true;
  std::vector<Vec3> world_positions;   ///< current, 3 per triangle (unshared), metres
  std::vector<Rgb> triangle_albedo;    ///< per triangle
  std::vector<Rgb> triangle_emission;  ///< per triangle, cd/m2
};

/// A runtime patch of static geometry (what patchDeltas() indexes, before
/// the dynamic objects' patches).
struct PatchInfo {
  Vec3 centroid;  ///< world, metres
  Vec3 normal;    ///< unit
  float area_m2 = 0;
  Rgb albedo;
  Rgb baseline_exitance;        ///< baked exitance under it, lm/m2 (emission + albedo x lightmap)
  uint32_t bake_patch = 0;      ///< the bake patch (cluster-tree node) it was cut from
  std::vector<Vec3> triangles;  ///< its sub-triangles, 3 corners each, world metres
};

/// A runtime light as the game last set it.
struct RuntimeLightInfo {
  Light light;  ///< position, direction, colour, intensity (before the dimmer), cone
  bool enabled = true;
  float dimmer = 1;  ///< multiplies intensity
};

class Runtime {
 public:
  /// Builds the runtime for `scene` (as loaded by loadLevel) and its bake
  /// (readBakeFile of `bake_dir`/bake.svit; lightmap pages are read from
  /// `bake_dir`). The scene's dynamic instances become objects (ids in
  /// instance order, see objectForNode) and its dynamic lights runtime lights.
  /// Errors (nothing created): no current OpenGL 4.5 context; a bake of
  /// another level (level hash differs); a bake without runtime sections for
  /// a level that has dynamic content; a setting out of range (named);
  /// unreadable lightmap pages; a shader that does not compile.
  static Expected<std::unique_ptr<Runtime>> create(const Scene& scene, const BakeData& bake,
                                                   const std::string& bake_dir,
                                                   const RuntimeSettings& settings = {});
  ~Runtime();
  Runtime(const Runtime&) = delete;
  Runtime& operator=(const Runtime&) = delete;

  // ---- dynamic objects ----
  /// The object made from a dynamic scene node, or kInvalidId.
  ObjectId objectForNode(int node) const;
  /// Adds an object under a new id (one above the last given). Errors: empty
  /// or malformed mesh (index out of range, non-finite position, albedo
  /// outside [0, 1)), non-finite transform; kUnsupported once 2^32 - 1 ids
  /// have been given (ids are never reused).
  Expected<ObjectId> addObject(const DynamicMesh& mesh, const Mat4& world_from_object);
  /// Moves an object (teleports are fine). Errors: unknown id, non-finite matrix.
  Status setObjectTransform(ObjectId object, const Mat4& world_from_object);
  /// Replaces an object's object-space positions (same count). Errors: unknown
  /// id, count differs, non-finite value.
  Status deformObject(ObjectId object, std::span<const Vec3> positions);
  /// Hides (false) or shows an object without removing it.
  Status setObjectVisible(ObjectId object, bool visible);
  /// Removes an object; its id is never reused (refused from then on, as an
  /// unknown id), while what the runtime kept for it is reused by the next
  /// object added. Error: unknown id.
  Status removeObject(ObjectId object);
  Expected<ObjectInfo> objectInfo(ObjectId object) const;
  /// Ids of the objects not removed, ascending.
  std::vector<ObjectId> objects() const;

  // ---- lights ----
  /// The runtime light made from Scene::lights[index] (a dynamic light), or kInvalidId.
  LightId lightForSceneLight(int scene_light_index) const;
  /// Adds a runtime light (point or spot; `dynamic` is implied). Errors:
  /// non-finite or negative values, directional type (use the sun).
  Expected<LightId> addLight(const Light& light);
  /// Replaces a runtime light's position, direction, colour, intensity, cone.
  Status setLight(LightId light, const Light& value);
  /// Switches a runtime light on or off.
  Status setLightEnabled(LightId light, bool enabled);
  /// Scales a runtime light's intensity (dimmer), >= 0.
  Status setLightDimmer(LightId light, float scale);
  /// Scales a baked emitter (BakeData::emitters index: a lamp's emissive
  /// patch, a baked light, the sun or the sky): 1 = as baked, 0 = off.
  Status setBakedEmitterScale(uint32_t bake_emitter, float scale);
  /// Ids of the runtime lights, ascending, and their state.
  std::vector<LightId> lights() const;
  Expected<RuntimeLightInfo> lightInfo(LightId light) const;

  // ---- per frame ----
  /// The camera the next updates rank emitters for (importance caching).
  /// Errors: a non-finite value, position = look_at, up along the view,
  /// field of view outside (0, pi), aspect or near <= 0.
  Status setView(const RuntimeView& view);
  /// Forgets the view: updates refresh brightest first again.
  void clearView();
  /// Changes RuntimeSettings::max_samples_per_frame (0 = none) from the next
  /// update on: a quality setting, or none while loading so the first
  /// update settles everything. Error: negative.
  Status setSampleBudget(int max_samples_per_frame);
  /// Every emitter the runtime keeps (index = EmitterRefresh::emitter) with
  /// its importance for the last update's view. Indices hold until the next
  /// removeObject(): a removed object's emitters leave the list and the
  /// later ones move down (keeping their order).
  std::vector<EmitterState> emitterStates() const;
  /// Brings the lighting up to date within about `budget_ms` of work
  /// (0 = no limit: settle fully). Emitters that did not fit stay pending
  /// and are refreshed by later calls. Returns what it did.
  FrameStats update(double budget_ms = 0);

  // ---- results ----
  /// Runtime irradiance (lux, RGB) at a static surface point: the baked
  /// lightmap there (as svit-probe reads it) times the factor dimmed baked
  /// emitters give it, plus the patch delta. Points
  /// farther than `max_distance_m` from static geometry give NaN.
  Rgb irradianceAt(const Vec3& point, const Vec3& normal, float max_distance_m = 0.05f) const;
  /// Displayed irradiance delta of every patch (static runtime patches,
  /// then one per dynamic triangle), lux: what shading adds to the lightmap
  /// (runtime lights' direct light excluded: shaders add it per pixel).
  const std::vector<Rgb>& patchDeltas() const;
  /// Number of static runtime patches (the first entries of patchDeltas()).
  uint32_t staticPatchCount() const;
  /// One static runtime patch. Error: index out of range.
  Expected<PatchInfo> patchInfo(uint32_t patch) const;
  /// Irradiance a dynamic object's patch receives (lux), all light included.
  Expected<Rgb> objectPatchIrradiance(ObjectId object, uint32_t triangle) const;
  ShadingResources shadingResources() const;
  /// What the runtime holds now, one line per buffer or table, with GL
  /// storage measured through GL queries and host bytes from container
  /// sizes; what it left out says why (a static level: only the lightmap
  /// pages). Needs the context current. Cheap; not for every frame.
  std::vector<ResourceUse> resources() const;
  const BakeData& bake() const;
  const Scene& scene() const;

 private:
  struct Impl;
  explicit Runtime(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace svit
