#pragma once
// Lightmap UVs and the texels they cover: authored TEXCOORD_1 when every
// static mesh has it, otherwise an xatlas atlas at a texel density; then
// exact texel rasterization (coverage, position, normal, validity) with
// sample points pulled out of walls so no light leaks.

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "svit/baker/bake_geometry.h"
#include "svit/baker/ray_caster.h"
#include "svit/scene.h"
#include "svit/status.h"

namespace svit::baker {

struct AtlasSettings {
  double texels_per_m = 32.0;  ///< xatlas texel density; also used to size authored-UV pages
  int max_page_size = 2048;    ///< texels per side of an atlas page, power of two not required
  int padding_texels = 2;      ///< gap between charts (xatlas), and dilation reach
  int threads = 0;             ///< 0 = all cores
  /// xatlas charts each instance in pieces of at most this many consecutive
  /// triangles (0: whole instances). Chart growing costs about faces^1.7 a
  /// piece (third_party_notes/xatlas.md), so bounded pieces keep the atlas
  /// linear in triangles; charts end at piece borders, which costs a few
  /// percent more charts and page texels (docs/bench/atlas_pieces.md).
  /// Authored UVs ignore it.
  size_t chart_piece_triangles = 1024;
  /// Per triangle: 1 where a double-sided triangle's back gets a face of
  /// its own (RadiositySolver::litBacks: light reaches it); a back left
  /// out reads black. Empty: every double-sided back gets one.
  std::vector<uint8_t> lit_backs;
};

/// Whether triangle t's back is a face of the atlas `settings` build.
inline bool hasBackFace(const BakeGeometry& geometry, const AtlasSettings& settings, size_t t) {
  return geometry.double_sided[t] && (settings.lit_backs.empty() || settings.lit_backs[t]);
}

/// Where every static triangle (BakeGeometry order) lies in the lightmap.
/// The lightmap's faces are the triangles' fronts, face t for triangle t,
/// then the backs of the double-sided ones that light reaches (a lightmap per side: each side
/// of a partition between a lit and a dark room gets its own light), face
/// triangleCount() + i for back_triangles[i]. The per-face arrays hold the
/// fronts first, then the backs.
struct LightmapAtlas {
  int page_width = 0;
  int page_height = 0;
  int page_count = 0;
  bool authored = false;                ///< true: from TEXCOORD_1, false: xatlas
  std::vector<uint32_t> triangle_page;  ///< per face
  /// 3 per face, page coordinates in [0, 1] (u right, v down the rows)
  std::vector<Vec2> triangle_uv;
  /// per face: chart id (unique across pages); seams are chart borders
  std::vector<uint32_t> triangle_chart;
  /// The double-sided triangles, ascending, whose backs are faces of their own.
  std::vector<uint32_t> back_triangles;

  size_t faceCount() const { return triangle_page.size(); }
  size_t frontCount() const { return triangle_page.size() - back_triangles.size(); }
  /// The triangle that face `f` is a side of.
  uint32_t faceTriangle(size_t f) const {
    return f < frontCount() ? uint32_t(f) : back_triangles[f - frontCount()];
  }
  bool isBack(size_t f) const { return f >= frontCount(); }
  /// The face of side `side` (0 front, 1 back) of triangle t: its front
  /// when the back has no face of its own.
  uint32_t face(uint32_t t, int side) const;
};

/// Builds the atlas. Instances of one mesh get their own texels.
/// - Authored: used when every static instance's mesh has TEXCOORD_1 inside
///   [0, 1]. Authored UVs of different meshes share one layout (a level
///   unwrapped together), so instance i goes to the first page that does not
///   hold another instance of its mesh; the page is square, sized from
///   texels_per_m and the area the page holds, at most max_page_size. The
///   backs of double-sided triangles keep their authored UVs on a twin of
///   their page (appended after the authored pages; only pages holding a
///   double-sided triangle get one).
/// - Otherwise xatlas charts every static instance's world-space triangles
///   separately (so instances never share texels) at texels_per_m with
///   `padding_texels`, into as many pages of at most max_page_size as needed.
///   Charting runs on `threads` workers; the atlas is the same for any number.
///   The backs of double-sided triangles are copies of their fronts' charts,
///   packed with the rest.
/// Errors: xatlas failure, max_page_size < 16, texels_per_m not > 0.
/// Thread-safe: yes (calls share only xatlas's print setting, set once).
Expected<LightmapAtlas> buildLightmapAtlas(const Scene& scene, const BakeGeometry& geometry,
                                           const AtlasSettings& settings);

/// One texel that some triangle covers.
struct TexelSample {
  uint32_t page = 0;
  uint32_t x = 0, y = 0;  ///< texel column and row
  uint32_t triangle = 0;  ///< the covering triangle with most area in the texel
  uint32_t face = 0;      ///< its face (LightmapAtlas): the triangle, or its back
  float u = 0, v = 0;     ///< barycentrics of the sample point in that triangle
  Vec3 position;          ///< world sample point (moved off walls when needed), metres
  Vec3 normal;            ///< world unit geometric normal of `face` (a back's points away)
  float coverage = 0;     ///< fraction of the texel's area covered by triangles, (0, 1]
};

/// TexelSet::texel_to_sample where no triangle covers the texel.
constexpr int32_t kNoSample = -1;
/// TexelSet::texel_to_sample where a triangle covers the texel but all of it
/// lies inside or under geometry (the floor under a wall or a crate): no
/// light reaches it, so its page texel is black, never dilated over from
/// lit neighbours (which would leak light under the wall into the bilinear
/// lookups on its dark side).
constexpr int32_t kBuriedTexel = -2;

/// All covered texels of all pages, and a per-texel index for lookups.
struct TexelSet {
  int page_width = 0, page_height = 0, page_count = 0;
  std::vector<TexelSample> samples;  ///< in (page, y, x) order
  /// page_count * width * height: the sample's index, kNoSample or kBuriedTexel
  std::vector<int32_t> texel_to_sample;

  int32_t sampleAt(uint32_t page, uint32_t x, uint32_t y) const {
    return texel_to_sample[(size_t(page) * size_t(page_height) + y) * size_t(page_width) + x];
  }
};

struct RasterSettings {
  /// Sample points whose short probe rays find a back face within this many
  /// texel sizes are inside or behind geometry and move out (or are dropped).
  double leak_probe_texels = 1.0;
  int threads = 0;
};

/// Rasterizes every triangle into its page with exact (polygon clipping)
/// coverage; texels touched by several triangles take the one covering most,
/// with the sample point at the centroid of the covered part clamped into
/// it. Sample points that lie inside or behind geometry (a probe ray from
/// them hits a back face first) are moved towards the covered part's visible
/// side, or buried (kBuriedTexel) when no point of the texel is outside.
/// Deterministic.
Expected<TexelSet> rasterizeTexels(const BakeGeometry& geometry, const LightmapAtlas& atlas,
                                   const RayCaster& caster, const RasterSettings& settings);

/// Buries (kBuriedTexel: black, never dilated over) every sample for which
/// `buried` is true, keeping the others in order. Returns how many.
size_t buryTexels(TexelSet& texels, const std::function<bool(const TexelSample&)>& buried);

/// The world points of the four corners of sample `s`'s texel square, each
/// clamped into the sample's triangle (its lightmap footprint on that
/// triangle's plane): what bilinear filtering spreads the texel over.
std::array<Vec3, 4> texelFootprint(const BakeGeometry& geometry, const LightmapAtlas& atlas,
                                   const TexelSample& s);

}  // namespace svit::baker
