// Lightmap atlas: authored TEXCOORD_1 pages, or an unwrap by xatlas
// (J. Young, github.com/jpcy/xatlas: chart growing after Sander et al.,
// "Multi-Chart Geometry Images" 2003, LSCM parameterization after Levy et
// al. 2002, packing by rasterized chart masks). Quirks we rely on are listed
// in third_party_notes/xatlas.md.

#include "svit/baker/lightmap_atlas.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <mutex>
#include <numeric>
#include <string>
#include <tuple>

#include <glm/glm.hpp>
#include <xatlas.h>

#include "glm_interop.h"

namespace svit::baker {
namespace {

/// Static triangles of one instance: BakeGeometry keeps them contiguous.
struct InstanceRange {
  uint32_t instance = 0;
  size_t first = 0, end = 0;  ///< triangles [first, end) of BakeGeometry
};

std::vector<InstanceRange> instanceRanges(const BakeGeometry& geometry) {
  std::vector<InstanceRange> ranges;
  for (size_t t = 0; t < geometry.triangleCount(); ++t) {
    if (ranges.empty() || ranges.back().instance != geometry.instance[t])
      ranges.push_back({geometry.instance[t], t, t});
    ranges.back().end = t + 1;
  }
  return ranges;
}

std::string instanceLabel(const Scene& scene, uint32_t instance) {
  const Instance& in = scene.instances[instance];
  return scene.source_path + ": instance " + std::to_string(instance) + " (mesh '" +
         scene.meshes[size_t(in.mesh)].name + "')";
}

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
  return atlas;
}

// ---------------------------------------------------------------- xatlas

struct AtlasDeleter {
  void operator()(xatlas::Atlas* a) const { xatlas::Destroy(a); }
};

int discardPrint(const char*, ...) { return 0; }

/// World-space unit vertex normals of a triangle, from the mesh's (smooth or
/// split) normals, so xatlas sees the mesh's hard edges as normal seams
/// rather than a seam at every edge. Falls back to the face normal.
void cornerNormals(const Scene& scene, const BakeGeometry& geometry, size_t t,
                   const glm::mat3& normal_from_object, float* out) {
  const Instance& instance = scene.instances[geometry.instance[t]];
  const Mesh& mesh = scene.meshes[size_t(instance.mesh)];
  const size_t mt = geometry.mesh_triangle[t];
  const Vec3& face = geometry.normals[t];
  for (int k = 0; k < 3; ++k) {
    glm::vec3 n = toGlm(face);
    if (mesh.normals.size() == mesh.positions.size()) {
      const glm::vec3 m =
          normal_from_object * toGlm(mesh.normals[mesh.indices[mt * 3 + size_t(k)]]);
      const float length = glm::length(m);
      if (std::isfinite(length) && length > 0.0f) n = m / length;
    }
    out[k * 3 + 0] = n.x;
    out[k * 3 + 1] = n.y;
    out[k * 3 + 2] = n.z;
  }
}

const char* addMeshErrorName(xatlas::AddMeshError error) {
  switch (error) {
    case xatlas::AddMeshError::Success: return "success";
    case xatlas::AddMeshError::Error: return "unspecified error";
    case xatlas::AddMeshError::IndexOutOfRange: return "index out of range";
    case xatlas::AddMeshError::InvalidFaceVertexCount: return "invalid face vertex count";
    case xatlas::AddMeshError::InvalidIndexCount: return "index count not a multiple of 3";
  }
  return "unknown error";
}

using XatlasPtr = std::unique_ptr<xatlas::Atlas, AtlasDeleter>;

/// Gives xatlas every instance as one mesh, positions in texel units
/// (metres x texels_per_m, texelsPerUnit 1): xatlas drops faces of area <=
/// FLT_EPSILON in its input units, which in metres would drop legal
/// sub-millimetre triangles; in texels only those below 1.2e-7 texel^2,
/// which cover nothing anyway. Adds the static area to `total_m2`.
Status addXatlasMeshes(xatlas::Atlas* xa, const Scene& scene, const BakeGeometry& geometry,
                       const std::vector<InstanceRange>& ranges, const AtlasSettings& settings,
                       double* total_m2) {
  const double scale = settings.texels_per_m;
  for (const InstanceRange& r : ranges) {
    const size_t n = r.end - r.first;
    std::vector<float> positions(n * 9), normals(n * 9);
    std::vector<uint32_t> indices(n * 3);
    const glm::mat3 world(toGlm(scene.instances[r.instance].world_from_object));
    const glm::mat3 normal_from_object = glm::transpose(glm::inverse(world));
    for (size_t i = 0; i < n; ++i) {
      const size_t t = r.first + i;
      for (int k = 0; k < 3; ++k) {
        const Vec3& p = geometry.corner(t, k);
        positions[i * 9 + size_t(k) * 3 + 0] = float(double(p.x) * scale);
        positions[i * 9 + size_t(k) * 3 + 1] = float(double(p.y) * scale);
        positions[i * 9 + size_t(k) * 3 + 2] = float(double(p.z) * scale);
        indices[i * 3 + size_t(k)] = uint32_t(i * 3 + size_t(k));
      }
      cornerNormals(scene, geometry, t, normal_from_object, &normals[i * 9]);
      *total_m2 += geometry.areas_m2[t];
    }
    xatlas::MeshDecl decl;
    decl.vertexPositionData = positions.data();
    decl.vertexPositionStride = sizeof(float) * 3;
    decl.vertexNormalData = normals.data();
    decl.vertexNormalStride = sizeof(float) * 3;
    decl.vertexCount = uint32_t(n * 3);
    decl.indexData = indices.data();
    decl.indexCount = uint32_t(n * 3);
    decl.indexFormat = xatlas::IndexFormat::UInt32;  // the default is UInt16
    const xatlas::AddMeshError error = xatlas::AddMesh(xa, decl, uint32_t(ranges.size()));
    if (error != xatlas::AddMeshError::Success) {
      return Status(
          StatusCode::kInternal,
          instanceLabel(scene, r.instance) + ": xatlas AddMesh failed: " + addMeshErrorName(error));
    }
  }
  return Status();
}

/// Charts and packs. One page sized to fit is tried first, unless the
/// texels cannot fit in one page even when packed perfectly; then fixed
/// max_page_size pages. Returns whether it paged.
bool packXatlasCharts(xatlas::Atlas* xa, const AtlasSettings& settings, double total_m2) {
  xatlas::ChartOptions chart_options;  // defaults: xatlas's tuned weights
  xatlas::ComputeCharts(xa, chart_options);
  xatlas::PackOptions pack;
  pack.texelsPerUnit = 1.0f;  // positions are already in texels
  pack.padding = uint32_t(settings.padding_texels);
  pack.bilinear = true;
  pack.bruteForce = false;  // random placement from a fixed seed: deterministic and much faster
  pack.maxChartSize = uint32_t(settings.max_page_size);
  const double texels = total_m2 * settings.texels_per_m * settings.texels_per_m;
  const double page_texels = double(settings.max_page_size) * double(settings.max_page_size);
  bool paged = texels > page_texels;
  if (!paged) {
    xatlas::PackCharts(xa, pack);
    paged = xa->width > uint32_t(settings.max_page_size) ||
            xa->height > uint32_t(settings.max_page_size);
  }
  if (paged) {
    pack.resolution = uint32_t(settings.max_page_size);
    xatlas::PackCharts(xa, pack);
  }
  return paged;
}

/// Reads xatlas's corners back into `atlas` (sized by the caller), checking
/// each against what was given and the page.
Status readXatlasCorners(const xatlas::Atlas& xa, const Scene& scene, const BakeGeometry& geometry,
                         const std::vector<InstanceRange>& ranges, const AtlasSettings& settings,
                         LightmapAtlas& atlas) {
  std::vector<uint8_t> corner_done(geometry.triangleCount() * 3, 0);
  // xatlas places vertices at >= 0 and within the page up to float rounding
  // of its own texel-centre alignment; a hundredth of a texel is far above
  // that rounding and far below anything a bug would produce.
  constexpr double kUvSlackTexels = 0.01;
  for (size_t m = 0; m < ranges.size(); ++m) {
    const InstanceRange& r = ranges[m];
    const xatlas::Mesh& out = xa.meshes[m];
    for (uint32_t i = 0; i < out.indexCount; ++i) {
      const xatlas::Vertex& v = out.vertexArray[out.indexArray[i]];
      const size_t t = r.first + v.xref / 3;
      const int k = int(v.xref % 3);
      if (v.xref >= (r.end - r.first) * 3) {
        return Status(StatusCode::kInternal, instanceLabel(scene, r.instance) +
                                                 ": xatlas output vertex refers to input vertex " +
                                                 std::to_string(v.xref) + " of " +
                                                 std::to_string((r.end - r.first) * 3));
      }
      if (v.atlasIndex < 0 || v.chartIndex < 0) {
        // Legal but too small for xatlas (flattenStaticGeometry's test is
        // relative, xatlas's absolute): not a bug of ours, not bad data.
        return Status(StatusCode::kUnsupported,
                      instanceLabel(scene, r.instance) + " triangle " +
                          std::to_string(geometry.mesh_triangle[t]) +
                          ": xatlas left it out of the atlas (area " +
                          std::to_string(geometry.areas_m2[t]) + " m2 is below 1.2e-7 texel^2 at " +
                          std::to_string(settings.texels_per_m) + " texels/m)");
      }
      const double x = v.uv[0], y = v.uv[1];
      if (!(x >= 0.0 && y >= 0.0 && x <= xa.width + kUvSlackTexels &&
            y <= xa.height + kUvSlackTexels) ||
          v.atlasIndex >= atlas.page_count) {
        return Status(StatusCode::kInternal,
                      instanceLabel(scene, r.instance) + " triangle " +
                          std::to_string(geometry.mesh_triangle[t]) +
                          ": xatlas placed a corner at (" + std::to_string(x) + ", " +
                          std::to_string(y) + ") page " + std::to_string(v.atlasIndex) +
                          ", outside the " + std::to_string(atlas.page_count) + " pages of " +
                          std::to_string(xa.width) + "x" + std::to_string(xa.height));
      }
      atlas.triangle_uv[t * 3 + size_t(k)] = {float(std::min(1.0, x / xa.width)),
                                              float(std::min(1.0, y / xa.height))};
      // All corners of a face share its chart (and the chart's page).
      atlas.triangle_page[t] = uint32_t(v.atlasIndex);
      atlas.triangle_chart[t] = uint32_t(v.chartIndex);
      corner_done[t * 3 + size_t(k)] = 1;
    }
  }
  for (size_t c = 0; c < corner_done.size(); ++c) {
    if (!corner_done[c]) {
      const size_t t = c / 3;
      return Status(StatusCode::kInternal, instanceLabel(scene, geometry.instance[t]) +
                                               " triangle " +
                                               std::to_string(geometry.mesh_triangle[t]) +
                                               ": missing from xatlas's output");
    }
  }
  return Status();
}

Expected<LightmapAtlas> buildWithXatlas(const Scene& scene, const BakeGeometry& geometry,
                                        const std::vector<InstanceRange>& ranges,
                                        const AtlasSettings& settings) {
  // xatlas prints warnings with printf by default; a library must not write
  // to the tools' stdout. SetPrint is process-global, but xatlas is private
  // to svit_baker, so nothing else relies on its printing.
  static std::once_flag silence;
  std::call_once(silence, [] { xatlas::SetPrint(&discardPrint, false); });

  XatlasPtr xa(xatlas::Create());
  double total_m2 = 0;
  if (Status s = addXatlasMeshes(xa.get(), scene, geometry, ranges, settings, &total_m2); !s.ok())
    return s;
  const bool paged = packXatlasCharts(xa.get(), settings, total_m2);
  if (xa->width == 0 || xa->height == 0 || xa->meshCount != ranges.size()) {
    return Status(StatusCode::kInternal, scene.source_path + ": xatlas produced an empty atlas (" +
                                             std::to_string(xa->width) + "x" +
                                             std::to_string(xa->height) + ", " +
                                             std::to_string(xa->meshCount) + " meshes)");
  }

  LightmapAtlas atlas;
  atlas.authored = false;
  atlas.page_width = int(xa->width);
  atlas.page_height = int(xa->height);
  atlas.page_count = paged ? int(xa->atlasCount) : 1;
  const size_t count = geometry.triangleCount();
  atlas.triangle_page.assign(count, 0);
  atlas.triangle_uv.assign(count * 3, Vec2{});
  atlas.triangle_chart.assign(count, 0);
  if (Status s = readXatlasCorners(*xa, scene, geometry, ranges, settings, atlas); !s.ok())
    return s;
  return atlas;
}

}  // namespace

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
  return buildWithXatlas(scene, geometry, ranges, settings);
}

}  // namespace svit::baker
