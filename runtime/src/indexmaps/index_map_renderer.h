#pragma once
// Index shadow maps (thesis 5.2, docs/architecture/runtime-indexmaps.md
// "Index shadow maps"): from each point sample of an emitter, rasterise the
// scene with receiver ids as colour into an integer target laid out over the
// sample's emission lobe, then reduce every map on the GPU into per-receiver
// shares of the sample's flux (solid angle x normalised lobe weight per
// texel). Only the reduced per-receiver sums come back to the CPU, never a
// map.
//
// Internal to svit::runtime; needs a current OpenGL 4.5 core context on the
// calling thread for every call, destruction included (the Runtime checks it
// once at creation). Thread-safe: no; one GL thread.

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "gl/gl_memory.h"
#include "svit/math_types.h"
#include "svit/status.h"

namespace svit::gl {

/// A receiver id meaning "absorbs, receives nothing" (black back faces).
inline constexpr uint32_t kNoReceiver = 0xffffffffu;

/// Triangles an index map draws and the receiver each side stands for.
/// Receivers are dense ids 0..receiver_count-1 (static patches first, then
/// dynamic patches); the triangle index itself is kept for the small-polygon
/// fallback and vertex-visibility tests.
struct MapTriangles {
  std::vector<Vec3> positions;           ///< world, metres; 3 per triangle, CCW = front
  std::vector<uint32_t> front_receiver;  ///< per triangle; kNoReceiver = absorbs
  std::vector<uint32_t> back_receiver;   ///< per triangle; kNoReceiver = absorbs (single-sided)
  /// Optional, ascending: the triangles that begin a new part (a dynamic
  /// object); the renderer's culling runs never straddle two parts, so a
  /// run's box is one object's, not a door's and the next table's.
  std::vector<uint32_t> part_starts;
  size_t triangleCount() const { return front_receiver.size(); }
};

/// The same triangles renumbered in spatialRunOrder (index_map_culling.h),
/// so that the renderer's culling runs are compact: what a level's static
/// set should be given as, before anything keeps triangle numbers.
MapTriangles inRunOrder(const MapTriangles& triangles);

/// How a sample's directions are covered (thesis 5.2.4), cheapest first.
enum class MapLayout : uint32_t {
  kSingle = 0,    ///< one 90-degree face along the axis (narrow spots)
  kTriple = 1,    ///< three cube faces around the cube corner on the axis
  kHemicube = 2,  ///< full face + four half faces (cosine lobes)
  kCube = 3,      ///< six faces (isotropic points, wide spots)
  kParallel = 4,  ///< one orthographic raster (sun and sky directions)
};

/// The emission lobe of a point sample.
enum class Lobe : uint32_t {
  kCosine = 0,     ///< Lambertian surface: cos(theta)/pi about `axis`, front hemisphere
  kIsotropic = 1,  ///< point light: 1/(4 pi)
  /// glTF spot: t^2, t = clamp((cos - cos_outer) / (cos_inner - cos_outer)), normalised
  kSpot = 2,
  ///< (the baker's spotFalloff; integral 2 pi ((1 - ci) + (ci - co) / 3))
  kParallel = 3,  ///< parallel rays along `axis` through a square window
};

/// One point sample of an emitter.
struct PointSample {
  Vec3 position;  ///< world, metres; for kParallel the window centre, upwind of the scene
  Vec3 axis;      ///< unit: surface normal, spot direction or travel direction of parallel light
  Lobe lobe = Lobe::kCosine;
  float cos_inner = 1, cos_outer = 0;  ///< kSpot: full inside cos_inner, zero outside cos_outer
  float half_extent_m = 0;             ///< kParallel: half the window's side
  float roll_rad = 0;  ///< rotation of the map frame about `axis` (aliasing: vary per sample)
  /// share of its slot's flux this sample carries (a slot's weights sum to <= 1)
  float weight = 1;
  uint32_t slot = 0;  ///< accumulator row it adds into (one per emitter in a gather)
  /// Triangle the sample sits on (its own surface), never counted as a
  /// receiver of its own light; kNoReceiver-like 0xffffffff when none.
  uint32_t own_triangle = 0xffffffffu;
  /// Where its light can matter (an emitter's known reach): triangles in
  /// runs wholly outside the box are not drawn. Sound when every ray from
  /// the sample meets a drawn surface first inside the box (the first
  /// surfaces it lights, in a closed level); empty (the default): draw all.
  Aabb reach;
  /// Finer than `reach`: the static triangles the sample may see (a bit
  /// each, TriangleBits, sized for the static set): the raster draws no
  /// other static triangle, the small-polygon fallback visits only runs
  /// holding one. Sound when it holds every static triangle the same sample
  /// saw with no dynamic triangles set (gather's `seen`): objects only hide
  /// static surfaces. Null (the default): all. Must outlive gather().
  const std::vector<uint32_t>* static_triangles = nullptr;
};

/// Switches for the artifact handling of thesis 5.2 (all on by default; the
/// tests turn them off to show what each one fixes).
struct IndexMapSettings {
  int resolution = 128;        ///< texels per face edge (kParallel: per window edge)
  int max_batch_samples = 32;  ///< samples rendered before one reduction
  /// Triangles projecting to fewer than 4 texels are credited analytically
  /// (exact solid angle x lobe at the centroid x share of visible vertices)
  /// instead of by their texels, which hit or miss them all or nothing; the
  /// reduction skips their texels so nothing counts twice. Off: texels only.
  bool small_polygon_fallback = true;
  /// vertex tests: half-texel shrink toward the centroid + 3x3 id taps
  bool edge_taps = true;
  /// vertex tests: a tap showing a triangle sharing the vertex counts
  bool neighbour_ids = true;
  /// chooseLayout: largest share of the lobe a layout may miss
  double layout_miss_tolerance = 1e-3;
  /// Perspective faces draw their nearest chunks first and then only what
  /// those do not hide (index_map_occlusion.h): same maps and credits, far
  /// fewer triangles in a closed level. Off: every chunk in the frustum.
  bool occlusion_culling = true;
};

/// What one gather did.
struct GatherStats {
  uint32_t samples = 0;
  uint32_t faces_rendered = 0;      ///< raster passes (a cube = 6)
  uint64_t triangles_drawn = 0;     ///< triangles submitted over all faces (after culling)
  uint64_t triangles_hidden = 0;    ///< triangles occlusion culling left out (whole chunks)
  uint64_t texels = 0;              ///< texels reduced
  uint32_t fallback_triangles = 0;  ///< (sample, triangle) pairs credited by vertex visibility
  /// GL buffer (re)allocations since the previous gather (0 when steady)
  uint32_t buffer_allocations = 0;
  double render_ms = 0, reduce_ms = 0, readback_ms = 0;  ///< CPU wall time incl. glFinish per stage
};

/// A camera for IndexMapRenderer::countViewPixels: perspective from `eye`
/// along unit `forward`, with unit `right` and `up` and the tangents of the
/// half fields of view.
struct ViewFrame {
  Vec3 eye, right, up, forward;
  float tan_half_x = 1, tan_half_y = 1;
  float near_m = 0.05f;
};

class IndexMapRenderer {
 public:
  /// Compiles the shaders and allocates the map array for
  /// `settings.max_batch_samples` cubes (12 bytes per texel: 6 x res^2 x
  /// batch; at most 2 GiB). Errors, never a crash: kInvalidInput naming the
  /// setting (resolution outside [8, 8192], max_batch_samples outside
  /// [1, 1024], tolerance outside [0, 1], maps over 2 GiB), checked before
  /// any GL call; kUnsupported when no GL 4.5 context is current or the
  /// maps exceed the GL's limits; kInternal when a shader fails.
  static Expected<std::unique_ptr<IndexMapRenderer>> create(const IndexMapSettings& settings);
  ~IndexMapRenderer();

  /// Static triangles: uploaded once (proxies or full geometry). Buffers
  /// grow by half again when the triangles no longer fit, never shrink;
  /// GPU memory per triangle: 44 bytes, plus 4 x max_batch_samples with the
  /// small-polygon fallback. Triangle count x max_batch_samples must stay
  /// below 2^31 (gather() says so otherwise).
  /// A bad set (size mismatch, non-finite corner) is dropped and every
  /// gather() returns its kInvalidInput error until a good set replaces it.
  void setStaticTriangles(const MapTriangles& triangles);
  /// Dynamic triangles (ids after the static ones); call when any moved.
  /// An empty set draws nothing and allocates nothing. Errors as above.
  void setDynamicTriangles(const MapTriangles& triangles);
  /// Number of receivers the accumulators hold.
  void setReceiverCount(uint32_t receivers);

  /// The cheapest layout missing at most settings.layout_miss_tolerance of
  /// the sample's lobe (kSingle, kTriple, kHemicube, else kCube; parallel
  /// lobes kParallel).
  MapLayout chooseLayout(const PointSample& sample) const;
  /// Share of the sample's lobe that `layout` does not cover, in [0, 1],
  /// summed on the CPU from the texel weights at settings.resolution (so 0
  /// exactly for a covering layout); cached per lobe and spot cone.
  double missedShare(MapLayout layout, const PointSample& sample) const;

  /// Renders a map per sample (layout from chooseLayout) and reduces them:
  /// shares[slot * receiver_count + r] = sum over the slot's samples of
  /// weight x share of the sample's flux receiver r gets. `shares` is
  /// resized to slot_count * receiver_count. Deterministic (integer atomics).
  /// Texel weights are normalised by the discrete sum of the lobe over the
  /// whole cube, so a closed room gets exactly the sample's weight.
  /// Geometry nearer than max(1e-4 x scene diagonal, 1e-6 x |position|) to
  /// the sample is clipped; own_triangle is not drawn at all (place surface
  /// samples on or just above their triangle).
  /// Errors (kInvalidInput, `shares` untouched): a sample with a non-finite
  /// or zero axis, non-finite position/roll, negative weight, slot >=
  /// slot_count, spot cosines outside [-1, 1], a parallel sample without a
  /// positive half_extent_m; a bad triangle set (see the setters).
  /// GL state: restores framebuffers, viewport, scissor, depth, clip
  /// control, front face, program, VAO and the capabilities it touches;
  /// leaves shader-storage bindings 0-8 and texture units 0-1 changed.
  /// With `seen`: also which static triangles each slot's maps showed (a
  /// texel, or a vertex the fallback credited), ceil(static triangles / 32)
  /// words per slot, bit t % 32 of word t / 32: what a later gather of the
  /// same samples may pass as static_triangles.
  Status gather(std::span<const PointSample> samples, uint32_t slot_count,
                std::vector<float>& shares, GatherStats* stats = nullptr,
                std::vector<uint32_t>* seen = nullptr);

  /// The visible patches of a view (thesis 5.9): renders receiver ids from
  /// the camera into a width x height target (made on first use, remade
  /// when the size changes) with the triangles set, and counts the pixels
  /// of each receiver: pixels[r], resized to the receiver count. Pixels
  /// showing no receiver (sky, black backs) count for none. Deterministic.
  /// Errors: width or height outside [1, 4096], non-finite frame, a bad
  /// triangle set. GL state: as gather().
  Status countViewPixels(const ViewFrame& view, int width, int height,
                         std::vector<uint32_t>& pixels);

  const IndexMapSettings& settings() const;

  /// The GL objects behind the maps and their reduction (id and depth
  /// layers, geometry, samples, accumulators, fallback work items), and
  /// behind countViewPixels' target (empty until its first use): what the
  /// resource audit measures. Host copies of the triangle sets, in bytes.
  std::vector<GlObject> mapObjects() const;
  std::vector<GlObject> viewObjects() const;
  uint64_t hostBytes() const;

 private:
  struct Impl;
  explicit IndexMapRenderer(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace svit::gl
