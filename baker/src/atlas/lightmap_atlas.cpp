// Lightmap atlas: authored TEXCOORD_1 pages, or an unwrap by xatlas
// (xatlas_unwrap.cpp; the quirks we rely on are in third_party_notes/xatlas.md).

#include "svit/baker/lightmap_atlas.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>
#include <tuple>

#include "atlas_instances.h"
#include "xatlas_unwrap.h"

namespace svit::baker {
namespace {

double uvTriangleArea(const Vec2& a, const Vec2& b, const Vec2& c) {
  return 0.5 * std::fabs((double(b.x) - a.x) * (double(c.y) - a.y) -
                         (double(b.y) - a.y) * (double(c.x) - a.x));
}

// ---------------------------------------------------------------- authored

/// Authored UVs are used only when every static instance's mesh has them,
/// finite, inside [0, 1], and covering some area (a mesh exported with an
/// all-zero TEXCOORD_1 would otherwise get no texels at all).
bool authoredUvsUsable(const Scene& scene, const BakeGeometry& geometry,
                       const std::vector<InstanceRange>& ranges) {
  for (const InstanceRange& r : ranges) {
    const Mesh& mesh = scene.meshes[size_t(scene.instances[r.instance].mesh)];
    if (mesh.uv1.empty() || mesh.uv1.size() != mesh.positions.size()) return false;
    double uv_area = 0;
    for (size_t t = r.first; t < r.end; ++t) {
      const size_t mt = geometry.mesh_triangle[t];
      Vec2 uv[3];
      for (int k = 0; k < 3; ++k) {
        uv[k] = mesh.uv1[mesh.indices[mt * 3 + size_t(k)]];
        // NaN too
        if (!(uv[k].x >= 0.0f && uv[k].x <= 1.0f && uv[k].y >= 0.0f && uv[k].y <= 1.0f))
          return false;
      }
      uv_area += uvTriangleArea(uv[0], uv[1], uv[2]);
    }
    if (!(uv_area > 0.0)) return false;
  }
  return true;
}

/// Union-find with path halving; the smaller root wins so that roots (and
/// hence chart numbering) do not depend on the order of unions.
uint32_t findRoot(std::vector<uint32_t>& parent, uint32_t i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

/// Charts of authored UVs: triangles of one instance joined where a corner
/// coincides in both world position and UV (continuous in the lightmap).
/// Ids are numbered by first triangle, consecutively across instances.
void authoredCharts(const BakeGeometry& geometry, const std::vector<InstanceRange>& ranges,
                    LightmapAtlas* atlas) {
  uint32_t next_chart = 0;
  atlas->triangle_chart.assign(geometry.triangleCount(), 0);
  for (const InstanceRange& r : ranges) {
    const size_t n = r.end - r.first;
    // position, uv, local triangle
    using Key = std::tuple<float, float, float, float, float, uint32_t>;
    std::vector<Key> corners;
    corners.reserve(n * 3);
    for (size_t t = r.first; t < r.end; ++t) {
      for (int k = 0; k < 3; ++k) {
        const Vec3& p = geometry.corner(t, k);
        const Vec2& uv = atlas->triangle_uv[t * 3 + size_t(k)];
        corners.emplace_back(p.x, p.y, p.z, uv.x, uv.y, uint32_t(t - r.first));
      }
    }
    // all keys distinct per (corner, triangle): deterministic
    std::sort(corners.begin(), corners.end());
    std::vector<uint32_t> parent(n);
    std::iota(parent.begin(), parent.end(), 0u);
    for (size_t i = 1; i < corners.size(); ++i) {
      const Key& a = corners[i - 1];
      const Key& b = corners[i];
      if (std::get<0>(a) != std::get<0>(b) || std::get<1>(a) != std::get<1>(b) ||
          std::get<2>(a) != std::get<2>(b) || std::get<3>(a) != std::get<3>(b) ||
          std::get<4>(a) != std::get<4>(b)) {
        continue;
      }
      const uint32_t ra = findRoot(parent, std::get<5>(a)), rb = findRoot(parent, std::get<5>(b));
      if (ra != rb) parent[std::max(ra, rb)] = std::min(ra, rb);
    }
    std::vector<uint32_t> chart_of_root(n, ~0u);
    for (size_t i = 0; i < n; ++i) {
      const uint32_t root = findRoot(parent, uint32_t(i));
      if (chart_of_root[root] == ~0u) chart_of_root[root] = next_chart++;
      atlas->triangle_chart[r.first + i] = chart_of_root[root];
    }
  }
}

/// The backs of the double-sided triangles light reaches as faces of their
/// own: their authored UVs on a twin of their page, appended after the
/// authored pages (only pages that hold such a back get one), their charts
/// numbered after the fronts'.
void addAuthoredBacks(const BakeGeometry& geometry, const AtlasSettings& settings,
                      LightmapAtlas* atlas) {
  const size_t count = geometry.triangleCount();
  std::vector<int> twin(size_t(atlas->page_count), -1);
  int twins = 0;
  uint32_t charts = 0;
  for (size_t t = 0; t < count; ++t) charts = std::max(charts, atlas->triangle_chart[t] + 1);
  for (size_t t = 0; t < count; ++t) {
    if (!hasBackFace(geometry, settings, t)) continue;
    int& page = twin[atlas->triangle_page[t]];
    if (page < 0) page = atlas->page_count + twins++;
    atlas->back_triangles.push_back(uint32_t(t));
  }
  for (uint32_t t : atlas->back_triangles) {
    atlas->triangle_page.push_back(uint32_t(twin[atlas->triangle_page[t]]));
    for (int k = 0; k < 3; ++k) atlas->triangle_uv.push_back(atlas->triangle_uv[t * 3 + size_t(k)]);
    atlas->triangle_chart.push_back(charts + atlas->triangle_chart[t]);
  }
  atlas->page_count += twins;
}

Expected<LightmapAtlas> buildAuthored(const Scene& scene, const BakeGeometry& geometry,
                                      const std::vector<InstanceRange>& ranges,
                                      const AtlasSettings& settings) {
  LightmapAtlas atlas;
  atlas.authored = true;
  const size_t count = geometry.triangleCount();
  atlas.triangle_page.assign(count, 0);
  atlas.triangle_uv.resize(count * 3);
  // Instance i of a mesh goes to page i: the first page holding no other
  // instance of that mesh (authored UVs of one level share one layout).
  std::vector<uint32_t> instances_of_mesh(scene.meshes.size(), 0);
  std::vector<double> page_world_m2, page_uv_area;
  for (const InstanceRange& r : ranges) {
    const int mesh_index = scene.instances[r.instance].mesh;
    const Mesh& mesh = scene.meshes[size_t(mesh_index)];
    const uint32_t page = instances_of_mesh[size_t(mesh_index)]++;
    if (page >= page_world_m2.size()) {
      page_world_m2.resize(page + 1, 0.0);
      page_uv_area.resize(page + 1, 0.0);
    }
    for (size_t t = r.first; t < r.end; ++t) {
      atlas.triangle_page[t] = page;
      const size_t mt = geometry.mesh_triangle[t];
      for (int k = 0; k < 3; ++k)
        atlas.triangle_uv[t * 3 + size_t(k)] = mesh.uv1[mesh.indices[mt * 3 + size_t(k)]];
      page_world_m2[page] += geometry.areas_m2[t];
      page_uv_area[page] += uvTriangleArea(atlas.triangle_uv[t * 3], atlas.triangle_uv[t * 3 + 1],
                                           atlas.triangle_uv[t * 3 + 2]);
    }
  }
  // A page of side s holds s^2 * uv_area texels over world_m2 square metres;
  // texels_per_m^2 of them per square metre gives s. The densest-needing
  // page sets the common size (TexelSet has one page size).
  double side = 16.0;
  for (size_t p = 0; p < page_world_m2.size(); ++p) {
    if (page_uv_area[p] > 0.0)
      side = std::max(side, settings.texels_per_m * std::sqrt(page_world_m2[p] / page_uv_area[p]));
  }
  const int size = int(std::min(double(settings.max_page_size), std::ceil(side)));
  atlas.page_width = atlas.page_height = size;
  atlas.page_count = int(page_world_m2.size());
  authoredCharts(geometry, ranges, &atlas);
  addAuthoredBacks(geometry, settings, &atlas);
  return atlas;
}

}  // namespace

uint32_t LightmapAtlas::face(uint32_t t, int side) const {
  if (side == 0) return t;
  const auto it = std::lower_bound(back_triangles.begin(), back_triangles.end(), t);
  if (it == back_triangles.end() || *it != t) return t;
  return uint32_t(frontCount() + size_t(it - back_triangles.begin()));
}

Expected<LightmapAtlas> buildLightmapAtlas(const Scene& scene, const BakeGeometry& geometry,
                                           const AtlasSettings& settings) {
  if (!(settings.texels_per_m > 0.0) || !std::isfinite(settings.texels_per_m)) {
    return Status(StatusCode::kInvalidInput, "atlas settings: texels_per_m " +
                                                 std::to_string(settings.texels_per_m) +
                                                 " must be finite and > 0");
  }
  if (settings.max_page_size < 16) {
    return Status(StatusCode::kInvalidInput, "atlas settings: max_page_size " +
                                                 std::to_string(settings.max_page_size) +
                                                 " must be >= 16");
  }
  if (settings.padding_texels < 0 || settings.padding_texels * 2 >= settings.max_page_size / 2) {
    return Status(StatusCode::kInvalidInput,
                  "atlas settings: padding_texels " + std::to_string(settings.padding_texels) +
                      " must be >= 0 and leave most of a " +
                      std::to_string(settings.max_page_size) + "-texel page for charts");
  }
  const size_t count = geometry.triangleCount();
  if (count == 0)
    return Status(StatusCode::kInvalidInput,
                  scene.source_path + ": no static triangles to put in a lightmap");
  if (geometry.positions.size() != count * 3 || geometry.normals.size() != count ||
      geometry.instance.size() != count || geometry.mesh_triangle.size() != count) {
    return Status(StatusCode::kInvalidInput,
                  scene.source_path + ": bake geometry arrays disagree in length");
  }
  if (!settings.lit_backs.empty() && settings.lit_backs.size() != count) {
    return Status(StatusCode::kInvalidInput,
                  "atlas settings: lit_backs holds " + std::to_string(settings.lit_backs.size()) +
                      " triangles, the geometry " + std::to_string(count));
  }
  for (size_t t = 0; t < count; ++t) {
    const uint32_t i = geometry.instance[t];
    const bool ok =
        i < scene.instances.size() && scene.instances[i].mesh >= 0 &&
        size_t(scene.instances[i].mesh) < scene.meshes.size() &&
        geometry.mesh_triangle[t] < scene.meshes[size_t(scene.instances[i].mesh)].triangleCount();
    if (!ok) {
      return Status(StatusCode::kInvalidInput,
                    scene.source_path + ": bake geometry triangle " + std::to_string(t) +
                        " names instance " + std::to_string(i) + " / mesh triangle " +
                        std::to_string(geometry.mesh_triangle[t]) + " that this scene lacks");
    }
  }
  const std::vector<InstanceRange> ranges = instanceRanges(geometry);
  if (authoredUvsUsable(scene, geometry, ranges))
    return buildAuthored(scene, geometry, ranges, settings);
  return buildWithXatlas(scene, geometry, rangePieces(ranges, settings.chart_piece_triangles),
                         settings);
}

}  // namespace svit::baker
