#pragma once
// Index shadow maps (thesis 5.2, DESIGN.md "Runtime: index shadow maps"):
// from each point sample of an emitter, rasterise the scene with receiver
// ids as colour into an integer target laid out over the sample's emission
// lobe, then reduce every map on the GPU into per-receiver shares of the
// sample's flux (solid angle x normalised lobe weight per texel). Only the
// reduced per-receiver sums come back to the CPU, never a map.
//
// Internal to svit::runtime; needs a current OpenGL 4.5 core context on the
// calling thread for every call (the Runtime checks it once at creation).

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

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
  size_t triangleCount() const { return front_receiver.size(); }
};

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
  kSpot = 2,       ///< glTF spot: smoothstep-free linear falloff between cone cosines, normalised
  kParallel = 3,   ///< parallel rays along `axis` through a square window
};

/// One point sample of an emitter.
struct PointSample {
  Vec3 position;   ///< world, metres; for kParallel the window centre, upwind of the scene
  Vec3 axis;       ///< unit: surface normal, spot direction or travel direction of parallel light
  Lobe lobe = Lobe::kCosine;
  float cos_inner = 1, cos_outer = 0;  ///< kSpot: full inside cos_inner, zero outside cos_outer
  float half_extent_m = 0;             ///< kParallel: half the window's side
  float roll_rad = 0;  ///< rotation of the map frame about `axis` (aliasing: vary per sample)
  float weight = 1;    ///< share of its slot's flux this sample carries (a slot's weights sum to <= 1)
  uint32_t slot = 0;   ///< accumulator row it adds into (one per emitter in a gather)
  /// Triangle the sample sits on (its own surface), never counted as a
  /// receiver of its own light; kNoReceiver-like 0xffffffff when none.
  uint32_t own_triangle = 0xffffffffu;
};

/// Switches for the artifact handling of thesis 5.2 (all on by default; the
/// tests turn them off to show what each one fixes).
struct IndexMapSettings {
  int resolution = 128;               ///< texels per face edge (kParallel: per window edge)
  int max_batch_samples = 32;         ///< samples rendered before one reduction
  bool small_polygon_fallback = true; ///< vertex visibility for triangles that got no texel
  bool edge_taps = true;              ///< half-texel shrink + 3x3 neighbour taps in vertex tests
  bool neighbour_ids = true;          ///< accept ids of triangles sharing the vertex
  double layout_miss_tolerance = 1e-3;  ///< chooseLayout: largest share of the lobe a layout may miss
};

/// What one gather did.
struct GatherStats {
  uint32_t samples = 0;
  uint32_t faces_rendered = 0;        ///< raster passes (a cube = 6)
  uint64_t texels = 0;                ///< texels reduced
  uint32_t fallback_triangles = 0;    ///< triangles credited by vertex visibility
  double render_ms = 0, reduce_ms = 0, readback_ms = 0;  ///< CPU wall time incl. glFinish per stage
};

class IndexMapRenderer {
 public:
  /// Compiles the shaders and allocates the map array for
  /// `settings.max_batch_samples` cubes. Error (never a crash) when no GL 4.5
  /// context is current, a setting is out of range, or a shader fails.
  static Expected<std::unique_ptr<IndexMapRenderer>> create(const IndexMapSettings& settings);
  ~IndexMapRenderer();

  /// Static triangles: uploaded once (proxies or full geometry).
  void setStaticTriangles(const MapTriangles& triangles);
  /// Dynamic triangles (ids after the static ones); call when any moved.
  /// An empty set draws nothing and allocates nothing.
  void setDynamicTriangles(const MapTriangles& triangles);
  /// Number of receivers the accumulators hold.
  void setReceiverCount(uint32_t receivers);

  /// The cheapest layout missing at most settings.layout_miss_tolerance of
  /// the sample's lobe.
  MapLayout chooseLayout(const PointSample& sample) const;
  /// Share of the sample's lobe that `layout` does not cover, in [0, 1].
  double missedShare(MapLayout layout, const PointSample& sample) const;

  /// Renders a map per sample (layout from chooseLayout) and reduces them:
  /// shares[slot * receiver_count + r] = sum over the slot's samples of
  /// weight x share of the sample's flux receiver r gets. `shares` is
  /// resized to slot_count * receiver_count. Deterministic (integer atomics).
  Status gather(std::span<const PointSample> samples, uint32_t slot_count, std::vector<float>& shares,
                GatherStats* stats = nullptr);

  const IndexMapSettings& settings() const;

 private:
  struct Impl;
  explicit IndexMapRenderer(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace svit::gl
