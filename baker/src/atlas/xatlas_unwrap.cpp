// Lightmap UVs by xatlas (J. Young, github.com/jpcy/xatlas: chart growing
// after Sander et al., "Multi-Chart Geometry Images" 2003, LSCM
// parameterization after Levy et al. 2002, packing by rasterized chart
// masks), in two steps so that charting, by far xatlas's slowest part, runs
// on svit's workers; xatlas's own task scheduler races and is compiled out
// (third_party_notes/xatlas.md, "Quirks"):
// 1. chart: instances, in pieces of at most AtlasSettings::chart_piece_triangles
//    (chart growing is superlinear in a piece's faces), in groups of about
//    kXatlasGroupTriangles, each group in an
//    xatlas::Atlas of its own (AddMesh per piece, ComputeCharts, and a
//    PackCharts that only lays the charts out so that xatlas writes their
//    parameterization to its output), groups in parallel;
// 2. pack: every group's charts as UV meshes of one more atlas (AddUvMesh,
//    each chart its own material), and a copy of the charts of every
//    double-sided triangle for its back (a lightmap per side), packed with
//    padding and bilinear footprints into the pages, keeping each chart's
//    shape.

#include "xatlas_unwrap.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <mutex>
#include <string>

#include <glm/glm.hpp>
#include <xatlas.h>

#include "scene/glm_interop.h"
#include "util/parallel_for.h"

namespace svit::baker {
namespace {

/// Instances [first, end) of the ranges, charted in one xatlas::Atlas.
struct InstanceGroup {
  size_t first = 0, end = 0;
};

/// Consecutive instances, a group closed before it would pass
/// kXatlasGroupTriangles; an instance above it alone is a group of its own.
std::vector<InstanceGroup> instanceGroups(const std::vector<InstanceRange>& ranges) {
  std::vector<InstanceGroup> groups;
  size_t triangles = 0;
  for (size_t r = 0; r < ranges.size(); ++r) {
    const size_t n = ranges[r].end - ranges[r].first;
    if (groups.empty() || triangles + n > kXatlasGroupTriangles) {
      groups.push_back({r, r});
      triangles = 0;
    }
    groups.back().end = r + 1;
    triangles += n;
  }
  return groups;
}

struct AtlasDeleter {
  void operator()(xatlas::Atlas* a) const { xatlas::Destroy(a); }
};
using XatlasPtr = std::unique_ptr<xatlas::Atlas, AtlasDeleter>;

int discardPrint(const char*, ...) { return 0; }

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

// ---------------------------------------------------------------- chart

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

/// Gives xatlas one instance as a mesh, positions in texel units (metres x
/// texels_per_m, texelsPerUnit 1): xatlas drops faces of area <= FLT_EPSILON
/// in its input units, which in metres would drop legal sub-millimetre
/// triangles; in texels only those below 1.2e-7 texel^2, which cover nothing
/// anyway. Adds the instance's area to `area_m2`.
Status addXatlasMesh(xatlas::Atlas* xa, const Scene& scene, const BakeGeometry& geometry,
                     const InstanceRange& r, const AtlasSettings& settings, uint32_t mesh_count,
                     double* area_m2) {
  const double scale = settings.texels_per_m;
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
    *area_m2 += geometry.areas_m2[t];
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
  const xatlas::AddMeshError error = xatlas::AddMesh(xa, decl, mesh_count);
  if (error != xatlas::AddMeshError::Success) {
    return Status(StatusCode::kInternal, instanceLabel(scene, r.instance) +
                                             ": xatlas AddMesh failed: " + addMeshErrorName(error));
  }
  return Status();
}

/// Marks a face of a group's output that xatlas left out of every chart.
constexpr uint32_t kNoChart = ~0u;

/// One instance's charts as the packing atlas reads them (a UV mesh), and
/// the way back to the instance's triangles.
struct ChartedMesh {
  std::vector<float> uv;          ///< 2 per output vertex: texels of the group's layout
  std::vector<uint32_t> indices;  ///< 3 per face, in the instance's triangle order
  std::vector<uint32_t> chart;    ///< per face: chart of the group's atlas, or kNoChart
  std::vector<uint32_t> xref;     ///< per output vertex: corner (3 t + k) of the instance
};

struct ChartedGroup {
  Status status;
  double area_m2 = 0;
  std::vector<ChartedMesh> meshes;  ///< one per instance of the group
};

/// Lays a group's charts out, only so that xatlas writes each chart's
/// parameterization to its output: turned to its axis, scaled to
/// texelsPerUnit 1 (positions are in texels), stretched to whole texels and
/// shrunk to max_page_size as a direct PackCharts would. No padding, no
/// bilinear footprint, no quarter turns: the final packing places them.
xatlas::PackOptions layoutOptions(const AtlasSettings& settings) {
  xatlas::PackOptions layout;
  layout.texelsPerUnit = 1.0f;
  layout.maxChartSize = uint32_t(settings.max_page_size);
  layout.padding = 0;
  layout.bilinear = false;
  layout.rotateCharts = false;
  layout.bruteForce = false;
  return layout;
}

ChartedMesh chartedMesh(const xatlas::Mesh& out) {
  ChartedMesh m;
  m.uv.resize(size_t(out.vertexCount) * 2);
  m.xref.resize(out.vertexCount);
  for (uint32_t v = 0; v < out.vertexCount; ++v) {
    m.uv[v * 2 + 0] = out.vertexArray[v].uv[0];
    m.uv[v * 2 + 1] = out.vertexArray[v].uv[1];
    m.xref[v] = out.vertexArray[v].xref;
  }
  m.indices.assign(out.indexArray, out.indexArray + out.indexCount);
  m.chart.resize(out.indexCount / 3);
  for (size_t f = 0; f < m.chart.size(); ++f) {
    // All corners of a face share its chart.
    const int32_t chart = out.vertexArray[out.indexArray[f * 3]].chartIndex;
    m.chart[f] = chart < 0 ? kNoChart : uint32_t(chart);
  }
  return m;
}

/// Charts the group's instances in an atlas of its own (one thread) and
/// keeps their charts; the atlas is gone on return.
void chartGroup(const Scene& scene, const BakeGeometry& geometry,
                const std::vector<InstanceRange>& ranges, const InstanceGroup& group,
                const AtlasSettings& settings, ChartedGroup* out) {
  XatlasPtr xa(xatlas::Create());
  const uint32_t mesh_count = uint32_t(group.end - group.first);
  for (size_t r = group.first; r < group.end && out->status.ok(); ++r)
    out->status =
        addXatlasMesh(xa.get(), scene, geometry, ranges[r], settings, mesh_count, &out->area_m2);
  if (!out->status.ok()) return;
  xatlas::ChartOptions chart_options;  // defaults: xatlas's tuned weights
  xatlas::ComputeCharts(xa.get(), chart_options);
  xatlas::PackCharts(xa.get(), layoutOptions(settings));
  if (xa->meshCount != mesh_count) {
    out->status =
        Status(StatusCode::kInternal, instanceLabel(scene, ranges[group.first].instance) +
                                          ": xatlas returned " + std::to_string(xa->meshCount) +
                                          " of " + std::to_string(mesh_count) + " meshes");
    return;
  }
  for (uint32_t m = 0; m < xa->meshCount; ++m) out->meshes.push_back(chartedMesh(xa->meshes[m]));
}

/// The back copies of an instance's double-sided triangles' charts (a
/// lightmap per side): the faces of `front` whose triangle's back is a face
/// (hasBackFace), with their layout UVs and charts; empty when it has none.
ChartedMesh backCopy(const BakeGeometry& geometry, const AtlasSettings& settings,
                     const InstanceRange& r, const ChartedMesh& front) {
  ChartedMesh back;
  std::vector<uint32_t> vertex_of(front.xref.size(), kNoChart);
  for (size_t f = 0; f < front.chart.size(); ++f) {
    if (!hasBackFace(geometry, settings, r.first + front.xref[front.indices[f * 3]] / 3)) continue;
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = front.indices[f * 3 + size_t(k)];
      if (vertex_of[v] == kNoChart) {
        vertex_of[v] = uint32_t(back.xref.size());
        back.xref.push_back(front.xref[v]);
        back.uv.push_back(front.uv[v * 2 + 0]);
        back.uv.push_back(front.uv[v * 2 + 1]);
      }
      back.indices.push_back(vertex_of[v]);
    }
    back.chart.push_back(front.chart[f]);
  }
  return back;
}

/// A UV mesh of the packing atlas: an instance's charts, or the back
/// copies of its double-sided triangles' charts.
struct PackedMesh {
  const ChartedMesh* charted = nullptr;
  size_t range = 0;  ///< its instance, in the ranges
  bool back = false;
};

// ---------------------------------------------------------------- pack

/// Gives the packing atlas every instance's charts as a UV mesh, each chart
/// its own material: xatlas finds a UV mesh's charts by joining faces whose
/// UVs coincide, and charts laid out without padding may touch. The meshes
/// must outlive the last AddUvMesh: xatlas takes a declaration equal
/// (pointers included) to an earlier one for another instance of that mesh.
Status addUvMeshes(xatlas::Atlas* xa, const Scene& scene, const std::vector<InstanceRange>& ranges,
                   const std::vector<PackedMesh>& packed) {
  for (const PackedMesh& p : packed) {
    const ChartedMesh& m = *p.charted;
    xatlas::UvMeshDecl decl;
    decl.vertexUvData = m.uv.data();
    decl.vertexStride = sizeof(float) * 2;
    decl.vertexCount = uint32_t(m.xref.size());
    decl.indexData = m.indices.data();
    decl.indexCount = uint32_t(m.indices.size());
    decl.indexFormat = xatlas::IndexFormat::UInt32;
    decl.faceMaterialData = m.chart.data();
    const xatlas::AddMeshError error = xatlas::AddUvMesh(xa, decl);
    if (error != xatlas::AddMeshError::Success) {
      return Status(StatusCode::kInternal,
                    instanceLabel(scene, ranges[p.range].instance) +
                        ": xatlas AddUvMesh failed: " + addMeshErrorName(error));
    }
  }
  return Status();
}

/// Packs the charts. One page sized to fit is tried first, unless the
/// texels cannot fit in one page even when packed perfectly; then fixed
/// max_page_size pages. Returns whether it paged.
bool packXatlasCharts(xatlas::Atlas* xa, const AtlasSettings& settings, double total_m2) {
  xatlas::ComputeCharts(xa);  // of UV meshes: their charts, by material and shared UVs
  xatlas::PackOptions pack;
  pack.texelsPerUnit = 1.0f;  // UV-mesh charts are in texels of their layout already
  pack.padding = uint32_t(settings.padding_texels);
  pack.bilinear = true;
  pack.bruteForce = false;  // random placement from a fixed seed: deterministic and much faster
  pack.maxChartSize = uint32_t(settings.max_page_size);
  // The layout turned every chart to its axis: turning again would only
  // add rounding to shapes already aligned to whole texels.
  pack.rotateChartsToAxis = false;
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

// ---------------------------------------------------------------- read back

/// Triangle t's corner k as packed, checked against what was given and
/// the page.
Status readCorner(const xatlas::Atlas& xa, const Scene& scene, const BakeGeometry& geometry,
                  const AtlasSettings& settings, const xatlas::Vertex& v, bool charted, size_t t,
                  size_t face, int k, LightmapAtlas& atlas) {
  // xatlas places vertices at >= 0 and within the page up to float rounding
  // of its own texel-centre alignment; a hundredth of a texel is far above
  // that rounding and far below anything a bug would produce.
  constexpr double kUvSlackTexels = 0.01;
  const std::string label = instanceLabel(scene, geometry.instance[t]) + " triangle " +
                            std::to_string(geometry.mesh_triangle[t]);
  if (!charted) {
    // Legal but too small for xatlas (flattenStaticGeometry's test is
    // relative, xatlas's absolute): not a bug of ours, not bad data.
    return Status(StatusCode::kUnsupported,
                  label + ": xatlas left it out of the atlas (area " +
                      std::to_string(geometry.areas_m2[t]) + " m2 is below 1.2e-7 texel^2 at " +
                      std::to_string(settings.texels_per_m) + " texels/m)");
  }
  if (v.atlasIndex < 0 || v.chartIndex < 0) {
    return Status(StatusCode::kUnsupported,
                  label + ": xatlas charted it but left it out when packing (its charted " +
                      "UV area is below 1.2e-7 texel^2)");
  }
  const double x = v.uv[0], y = v.uv[1];
  if (!(x >= 0.0 && y >= 0.0 && x <= xa.width + kUvSlackTexels &&
        y <= xa.height + kUvSlackTexels) ||
      v.atlasIndex >= atlas.page_count) {
    return Status(StatusCode::kInternal,
                  label + ": xatlas placed a corner at (" + std::to_string(x) + ", " +
                      std::to_string(y) + ") page " + std::to_string(v.atlasIndex) +
                      ", outside the " + std::to_string(atlas.page_count) + " pages of " +
                      std::to_string(xa.width) + "x" + std::to_string(xa.height));
  }
  atlas.triangle_uv[face * 3 + size_t(k)] = {float(std::min(1.0, x / xa.width)),
                                             float(std::min(1.0, y / xa.height))};
  // All corners of a face share its chart (and the chart's page).
  atlas.triangle_page[face] = uint32_t(v.atlasIndex);
  atlas.triangle_chart[face] = uint32_t(v.chartIndex);
  return Status();
}

/// Reads the packed corners back into `atlas` (sized by the caller): packed
/// vertex j of UV mesh m is vertex j of its charted mesh, whose xref names
/// the corner of its instance; a back copy's is the corner of the back face.
Status readXatlasCorners(const xatlas::Atlas& xa, const Scene& scene, const BakeGeometry& geometry,
                         const std::vector<InstanceRange>& ranges,
                         const std::vector<PackedMesh>& packed, const AtlasSettings& settings,
                         LightmapAtlas& atlas) {
  std::vector<uint8_t> corner_done(atlas.faceCount() * 3, 0);
  for (size_t m = 0; m < packed.size(); ++m) {
    const InstanceRange& r = ranges[packed[m].range];
    const ChartedMesh& laid = *packed[m].charted;
    const xatlas::Mesh& out = xa.meshes[m];
    if (out.vertexCount != laid.xref.size() || out.indexCount != laid.indices.size()) {
      return Status(StatusCode::kInternal, instanceLabel(scene, r.instance) + ": xatlas packed " +
                                               std::to_string(out.vertexCount) + " vertices of " +
                                               std::to_string(laid.xref.size()));
    }
    for (uint32_t i = 0; i < out.indexCount; ++i) {
      const uint32_t xref = laid.xref[out.indexArray[i]];
      if (xref >= (r.end - r.first) * 3) {
        return Status(StatusCode::kInternal, instanceLabel(scene, r.instance) +
                                                 ": xatlas output vertex refers to input vertex " +
                                                 std::to_string(xref) + " of " +
                                                 std::to_string((r.end - r.first) * 3));
      }
      const size_t t = r.first + xref / 3;
      const size_t face = atlas.face(uint32_t(t), packed[m].back ? 1 : 0);
      const int k = int(xref % 3);
      const bool in_chart = laid.chart[i / 3] != kNoChart;
      if (Status s = readCorner(xa, scene, geometry, settings, out.vertexArray[out.indexArray[i]],
                                in_chart, t, face, k, atlas);
          !s.ok())
        return s;
      corner_done[face * 3 + size_t(k)] = 1;
    }
  }
  for (size_t c = 0; c < corner_done.size(); ++c) {
    if (!corner_done[c]) {
      const size_t t = atlas.faceTriangle(c / 3);
      return Status(StatusCode::kInternal, instanceLabel(scene, geometry.instance[t]) +
                                               " triangle " +
                                               std::to_string(geometry.mesh_triangle[t]) +
                                               ": missing from xatlas's output");
    }
  }
  return Status();
}

/// Charts all groups on settings.threads workers; each writes only its own
/// entry, so the result is the same for any number.
std::vector<ChartedGroup> chartGroups(const Scene& scene, const BakeGeometry& geometry,
                                      const std::vector<InstanceRange>& ranges,
                                      const AtlasSettings& settings) {
  const std::vector<InstanceGroup> groups = instanceGroups(ranges);
  std::vector<ChartedGroup> charted(groups.size());
  parallelFor(groups.size(), 1, resolveThreads(settings.threads), [&](size_t begin, size_t end) {
    for (size_t g = begin; g < end; ++g)
      chartGroup(scene, geometry, ranges, groups[g], settings, &charted[g]);
  });
  return charted;
}

}  // namespace

Expected<LightmapAtlas> buildWithXatlas(const Scene& scene, const BakeGeometry& geometry,
                                        const std::vector<InstanceRange>& ranges,
                                        const AtlasSettings& settings) {
  // xatlas prints warnings with printf by default; a library must not write
  // to the tools' stdout. SetPrint is process-global (set before any worker
  // starts), but xatlas is private to svit_baker, so nothing else relies on
  // its printing.
  static std::once_flag silence;
  std::call_once(silence, [] { xatlas::SetPrint(&discardPrint, false); });

  const std::vector<ChartedGroup> groups = chartGroups(scene, geometry, ranges, settings);
  double total_m2 = 0;  // summed in group order: the same for any thread count
  std::vector<PackedMesh> packed;
  for (const ChartedGroup& group : groups) {
    if (!group.status.ok()) return group.status;
    total_m2 += group.area_m2;
    for (const ChartedMesh& m : group.meshes) packed.push_back({&m, packed.size(), false});
  }
  std::vector<ChartedMesh> backs;
  backs.reserve(ranges.size());  // packed points into it
  for (size_t r = 0; r < ranges.size(); ++r) {
    backs.push_back(backCopy(geometry, settings, ranges[r], *packed[r].charted));
    if (!backs.back().chart.empty()) packed.push_back({&backs.back(), r, true});
  }
  LightmapAtlas atlas;
  for (uint32_t t = 0; t < geometry.triangleCount(); ++t) {
    if (hasBackFace(geometry, settings, t)) {
      atlas.back_triangles.push_back(t);
      total_m2 += geometry.areas_m2[t];
    }
  }
  XatlasPtr xa(xatlas::Create());
  if (Status s = addUvMeshes(xa.get(), scene, ranges, packed); !s.ok()) return s;
  const bool paged = packXatlasCharts(xa.get(), settings, total_m2);
  if (xa->width == 0 || xa->height == 0 || xa->meshCount != packed.size()) {
    return Status(StatusCode::kInternal, scene.source_path + ": xatlas produced an empty atlas (" +
                                             std::to_string(xa->width) + "x" +
                                             std::to_string(xa->height) + ", " +
                                             std::to_string(xa->meshCount) + " meshes)");
  }

  atlas.authored = false;
  atlas.page_width = int(xa->width);
  atlas.page_height = int(xa->height);
  atlas.page_count = paged ? int(xa->atlasCount) : 1;
  const size_t faces = geometry.triangleCount() + atlas.back_triangles.size();
  atlas.triangle_page.assign(faces, 0);
  atlas.triangle_uv.assign(faces * 3, Vec2{});
  atlas.triangle_chart.assign(faces, 0);
  if (Status s = readXatlasCorners(*xa, scene, geometry, ranges, packed, settings, atlas); !s.ok())
    return s;
  return atlas;
}

}  // namespace svit::baker
