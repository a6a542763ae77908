#include "runtime_patches.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <string>
#include <tuple>

#include "scene/glm_interop.h"
#include "scene/numeric.h"

namespace svit::gl {
namespace {

struct Item {  // one sub-triangle before grouping
  glm::dvec3 p[3];
  Vec2 uv[3];
  uint32_t page = 0;
  uint32_t element = 0;
  uint32_t slot = 0;  ///< within the element's n*n*2 slots
  double area = 0;
  glm::dvec3 centroid{0.0};
};

glm::dvec3 dvec(const Vec3& v) { return {v.x, v.y, v.z}; }
glm::dvec3 dvec(const Rgb& c) { return {c.r, c.g, c.b}; }

int tessellation(double area, double max_area) {
  return std::clamp(int(std::ceil(std::sqrt(area / max_area))), 1, 256);
}

// Sub-triangle (i, j, flipped) of an n x n tessellation in barycentric
// steps: corners as (w1, w2) pairs.
void subCorners(int n, int i, int j, bool flipped, double w[3][2]) {
  const double s = 1.0 / n;
  if (!flipped) {
    const double c[3][2] = {{i * s, j * s}, {(i + 1) * s, j * s}, {i * s, (j + 1) * s}};
    std::copy(&c[0][0], &c[0][0] + 6, &w[0][0]);
  } else {
    const double c[3][2] = {{(i + 1) * s, j * s}, {(i + 1) * s, (j + 1) * s}, {i * s, (j + 1) * s}};
    std::copy(&c[0][0], &c[0][0] + 6, &w[0][0]);
  }
}

// Calls visit(slot, w) for every sub-triangle of an n x n tessellation, in
// slot order (slot = (i * n + j) * 2 + flipped), w its corners as subCorners
// gives them.
template <typename Visit>
void forEachSubTriangle(int n, Visit&& visit) {
  for (int i = 0; i < n; ++i) {
    for (int j = 0; i + j < n; ++j) {
      for (int flipped = 0; flipped < 2; ++flipped) {
        if (flipped && i + j >= n - 1) continue;
        double w[3][2];
        subCorners(n, i, j, flipped != 0, w);
        visit(uint32_t((i * n + j) * 2 + flipped), w);
      }
    }
  }
}

// Splits items[begin, end) by the median of centroids along the longest
// axis until a group's area fits; appends groups as index ranges.
void splitGroups(std::vector<Item*>& items, size_t begin, size_t end, double max_area,
                 std::vector<std::pair<size_t, size_t>>& groups) {
  double area = 0;
  glm::dvec3 lo(kNoUpperBound), hi(kNoLowerBound);
  for (size_t i = begin; i < end; ++i) {
    area += items[i]->area;
    lo = glm::min(lo, items[i]->centroid);
    hi = glm::max(hi, items[i]->centroid);
  }
  if (end - begin <= 1 || area <= max_area * 1.0001) {
    groups.push_back({begin, end});
    return;
  }
  const glm::dvec3 extent = hi - lo;
  const int axis =
      extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
  const size_t mid = begin + (end - begin) / 2;
  std::nth_element(items.begin() + long(begin), items.begin() + long(mid),
                   items.begin() + long(end), [axis](const Item* a, const Item* b) {
                     return a->centroid[axis] < b->centroid[axis] ||
                            (a->centroid[axis] == b->centroid[axis] &&
                             std::tie(a->element, a->slot) < std::tie(b->element, b->slot));
                   });
  splitGroups(items, begin, mid, max_area, groups);
  splitGroups(items, mid, end, max_area, groups);
}

void grow(Aabb& box, const glm::dvec3& p) {
  box.min = {std::min(box.min.x, float(p.x)), std::min(box.min.y, float(p.y)),
             std::min(box.min.z, float(p.z))};
  box.max = {std::max(box.max.x, float(p.x)), std::max(box.max.y, float(p.y)),
             std::max(box.max.z, float(p.z))};
}

}  // namespace

uint32_t RuntimePatches::subTriangle(uint32_t element, float w1, float w2, float& s1,
                                     float& s2) const {
  if (element >= element_n.size() || element_n[element] == 0) return kNoReceiver;
  const int n = element_n[element];
  const float u = std::clamp(w1, 0.0f, 1.0f) * n, v = std::clamp(w2, 0.0f, 1.0f) * n;
  int i = std::min(int(u), n - 1), j = std::min(int(v), n - 1);
  if (i + j > n - 1) j = n - 1 - i;  // on the far edge
  float fu = u - float(i), fv = v - float(j);
  const bool flipped = fu + fv > 1 && i + j < n - 1;
  if (flipped) {
    // Flipped corners: (i+1, j), (i+1, j+1), (i, j+1).
    // Barycentrics in the flipped triangle: weights of corners 1 and 2.
    s1 = fu + fv - 1;
    s2 = 1 - fu;
  } else {
    s1 = fu;
    s2 = fv;
  }
  const uint32_t slot = element_first_slot[element] + uint32_t((i * n + j) * 2 + (flipped ? 1 : 0));
  return slots[slot];
}

namespace {

// The bake patches' elements cut into sub-triangles of at most the runtime
// patch area: all of them, and each bake patch's (indices into items).
struct Tessellation {
  std::vector<Item> items;
  std::vector<std::vector<size_t>> patch_items;
};

// The lightmap of an element's side: a back's own, where it has one (or
// kUnlitBackPage: none, it reads black).
struct SideUv {
  uint32_t page = 0;
  const Vec2* uv = nullptr;  ///< 3 corners
};

SideUv sideUv(const BakeData& bake, uint32_t element) {
  const uint32_t t = element / 2;
  const BakeBackUv* back = element % 2 == 1 ? findBackUv(bake, t) : nullptr;
  if (back) return {back->page, back->uv};
  return {bake.triangle_uvs[t].page, bake.triangle_uvs[t].uv};
}

// Appends element `element`'s n x n sub-triangles (of surface triangle `t`,
// in bake patch `p`, lightmap `side`) to `tess`.
void tessellateElement(const BakedSurfaces& surfaces, const SideUv& side, uint32_t p,
                       uint32_t element, uint32_t t, int n, Tessellation& tess) {
  const Vec2* uv = side.uv;
  const glm::dvec3 a = dvec(surfaces.corner(t, 0)), b = dvec(surfaces.corner(t, 1)),
                   c = dvec(surfaces.corner(t, 2));
  forEachSubTriangle(n, [&](uint32_t slot, const double(&w)[3][2]) {
    Item item;
    for (int k = 0; k < 3; ++k) {
      item.p[k] = a + w[k][0] * (b - a) + w[k][1] * (c - a);
      item.uv[k] = {
          float((1 - w[k][0] - w[k][1]) * uv[0].x + w[k][0] * uv[1].x + w[k][1] * uv[2].x),
          float((1 - w[k][0] - w[k][1]) * uv[0].y + w[k][0] * uv[1].y + w[k][1] * uv[2].y)};
    }
    if (element % 2 == 1) {  // the back side faces the other way: reverse the winding
      std::swap(item.p[1], item.p[2]);
      std::swap(item.uv[1], item.uv[2]);
    }
    item.page = side.page;
    item.element = element;
    item.slot = slot;
    item.area = surfaces.area(t) / double(n * n);
    item.centroid = (item.p[0] + item.p[1] + item.p[2]) / 3.0;
    tess.patch_items[p].push_back(tess.items.size());
    tess.items.push_back(item);
  });
}

// Every bake patch's elements, tessellated; sets out's element tables and
// sizes its slots. Error: an element out of range.
Status tessellatePatches(const BakeData& bake, const BakedSurfaces& surfaces, size_t page_count,
                         double max_area_m2, RuntimePatches& out, Tessellation& tess) {
  tess.patch_items.resize(bake.patches.size());
  for (uint32_t p = 0; p < bake.patches.size(); ++p) {
    const BakePatch& patch = bake.patches[p];
    for (uint32_t e = 0; e < patch.element_count; ++e) {
      const uint32_t element = bake.patch_elements[patch.first_element + e];
      const uint32_t t = element / 2;
      if (t >= surfaces.triangleCount()) {
        return Status(StatusCode::kInvalidInput, "bake patch " + std::to_string(p) + ": element " +
                                                     std::to_string(element) + " is out of range");
      }
      const SideUv side = sideUv(bake, element);
      if (side.page >= page_count && side.page != kUnlitBackPage) {
        return Status(StatusCode::kInvalidInput,
                      "bake patch " + std::to_string(p) + ": element " + std::to_string(element) +
                          " is on lightmap page " + std::to_string(side.page) + " of " +
                          std::to_string(page_count));
      }
      const int n = tessellation(surfaces.area(t), max_area_m2);
      out.element_n[element] = uint16_t(n);
      out.element_first_slot[element] = uint32_t(out.slots.size());
      out.slots.resize(out.slots.size() + size_t(n * n * 2), kNoReceiver);
      tessellateElement(surfaces, side, p, element, t, n, tess);
    }
  }
  return Status();
}

// One runtime patch of bake patch `p` from the sub-triangles list[begin,
// end): its area-weighted normal, centroid, albedo, emission and baked
// irradiance, its sub-triangles appended to out.triangles.
void addReceiver(const Scene& scene, const BakeData& bake, const std::vector<LightmapImage>& pages,
                 const MaskedLightField& masked, uint32_t p, const std::vector<Item*>& list,
                 size_t begin, size_t end, RuntimePatches& out) {
  const uint32_t id = uint32_t(out.receivers.size());
  Receiver r;
  glm::dvec3 normal(0.0), centroid(0.0), albedo(0.0), emission(0.0), irradiance(0.0),
      masked_irradiance(0.0);
  double area = 0;
  Aabb box;
  for (size_t k = begin; k < end; ++k) {
    const Item& item = *list[k];
    const uint32_t t = item.element / 2;
    const BakeTriangleUv& tri = bake.triangle_uvs[t];
    const Mesh& mesh = scene.meshes[size_t(scene.instances[tri.instance].mesh)];
    const glm::dvec3 cross = glm::cross(item.p[1] - item.p[0], item.p[2] - item.p[0]);
    normal += cross;
    centroid += item.centroid * item.area;
    albedo += dvec(mesh.triangle_albedo[tri.mesh_triangle]) * item.area;
    emission += kPi * dvec(mesh.triangle_emission[tri.mesh_triangle]) * item.area;
    const Vec2 uv{(item.uv[0].x + item.uv[1].x + item.uv[2].x) / 3,
                  (item.uv[0].y + item.uv[1].y + item.uv[2].y) / 3};
    irradiance += dvec(samplePage(pages, item.page, uv)) * item.area;
    if (!masked.empty()) {  // what the lightmap leaves to the masked lights
      const glm::dvec3 side = cross / std::max(glm::length(cross), 1e-300);
      masked_irradiance += dvec(masked.bakedIrradiance(fromGlm(glm::vec3(item.centroid)),
                                                       fromGlm(glm::vec3(side)), item.page, uv)) *
                           item.area;
    }
    area += item.area;
    for (const glm::dvec3& q : item.p) grow(box, q);
    const uint32_t sub = uint32_t(out.triangles.triangleCount());
    out.slots[out.element_first_slot[item.element] + item.slot] = sub;
    for (int c = 0; c < 3; ++c) {
      out.triangles.positions.push_back(fromGlm(glm::vec3(item.p[c])));
      out.triangle_uvs.push_back(item.uv[c]);
    }
    out.triangles.front_receiver.push_back(id);
    out.triangles.back_receiver.push_back(kNoReceiver);
    out.triangle_page.push_back(item.page);
  }
  const double length = glm::length(normal);
  r.area_m2 = float(area);
  r.normal = length > 0 ? fromGlm(glm::vec3(normal / length)) : Vec3{0, 1, 0};
  r.centroid = fromGlm(glm::vec3(centroid / area));
  const glm::dvec3 rho = albedo / area;
  r.albedo = {float(rho.x), float(rho.y), float(rho.z)};
  out.receivers.push_back(r);
  out.emission.push_back(emission / area);
  out.baseline.push_back(emission / area + rho * ((irradiance + masked_irradiance) / area));
  out.masked_direct.push_back(masked_irradiance / area);
  out.lightmap_irradiance.push_back(irradiance / area);
  out.bake_patch.push_back(p);
  out.bounds.push_back(box);
  out.bake_members[p].push_back(id);
}

// Groups each bake patch's sub-triangles into runtime patches.
void groupReceivers(const Scene& scene, const BakeData& bake,
                    const std::vector<LightmapImage>& pages, const MaskedLightField& masked,
                    double max_area_m2, Tessellation& tess, RuntimePatches& out) {
  for (uint32_t p = 0; p < bake.patches.size(); ++p) {
    std::vector<Item*> list;
    for (size_t k : tess.patch_items[p]) list.push_back(&tess.items[k]);
    std::vector<std::pair<size_t, size_t>> groups;
    if (!list.empty()) splitGroups(list, 0, list.size(), max_area_m2, groups);
    for (auto [begin, end] : groups)
      addReceiver(scene, bake, pages, masked, p, list, begin, end, out);
  }
}

// Shooters: the same median splits one level up, over runtime patches.
void groupShooters(const BakeData& bake, double max_shooter_area_m2, RuntimePatches& out) {
  out.shooter.assign(out.receivers.size(), 0);
  for (uint32_t p = 0; p < bake.patches.size(); ++p) {
    std::vector<Item> centres;
    for (uint32_t r : out.bake_members[p]) {
      Item item;
      item.area = out.receivers[r].area_m2;
      item.centroid = dvec(out.receivers[r].centroid);
      item.element = r;
      centres.push_back(item);
    }
    std::vector<Item*> list;
    for (Item& item : centres) list.push_back(&item);
    std::vector<std::pair<size_t, size_t>> groups;
    if (!list.empty()) splitGroups(list, 0, list.size(), max_shooter_area_m2, groups);
    for (auto [begin, end] : groups) {
      std::vector<uint32_t> members;
      for (size_t k = begin; k < end; ++k) {
        members.push_back(list[k]->element);
        out.shooter[list[k]->element] = uint32_t(out.shooter_members.size());
      }
      std::sort(members.begin(), members.end());
      out.shooter_members.push_back(std::move(members));
      out.shooter_bake_patch.push_back(p);
    }
  }
}

// Welds corners by exact position and side (the tessellation of shared
// edges gives bit-identical points on both triangles only when their
// counts match; unmatched corners stay separate, which keeps hard edges).
void weldCorners(RuntimePatches& out) {
  std::map<std::tuple<float, float, float, int>, uint32_t> welded;
  const size_t subs = out.triangles.triangleCount();
  out.triangle_vertices.resize(subs * 3);
  for (size_t s = 0; s < subs; ++s) {
    const Receiver& r = out.receivers[out.triangles.front_receiver[s]];
    // Side key: the dominant axis and sign of the patch normal.
    const int side =
        std::abs(r.normal.x) >= std::abs(r.normal.y) && std::abs(r.normal.x) >= std::abs(r.normal.z)
            ? (r.normal.x > 0 ? 0 : 1)
            : (std::abs(r.normal.y) >= std::abs(r.normal.z) ? (r.normal.y > 0 ? 2 : 3)
                                                            : (r.normal.z > 0 ? 4 : 5));
    for (int c = 0; c < 3; ++c) {
      const Vec3& q = out.triangles.positions[s * 3 + size_t(c)];
      auto [it, inserted] = welded.try_emplace({q.x, q.y, q.z, side}, uint32_t(welded.size()));
      out.triangle_vertices[s * 3 + size_t(c)] = it->second;
    }
  }
  out.vertex_count = uint32_t(welded.size());
}

}  // namespace

Expected<RuntimePatches> buildRuntimePatches(const Scene& scene, const BakeData& bake,
                                             const BakedSurfaces& surfaces,
                                             const std::vector<LightmapImage>& pages,
                                             const MaskedLightField& masked, double max_area_m2,
                                             double max_shooter_area_m2) {
  RuntimePatches out;
  const size_t elements = surfaces.triangleCount() * 2;
  out.element_n.assign(elements, 0);
  out.element_first_slot.assign(elements, 0);
  out.bake_members.resize(bake.patches.size());
  Tessellation tess;
  if (Status s = tessellatePatches(bake, surfaces, pages.size(), max_area_m2, out, tess); !s.ok())
    return s;
  groupReceivers(scene, bake, pages, masked, max_area_m2, tess, out);
  groupShooters(bake, max_shooter_area_m2, out);
  weldCorners(out);
  return out;
}

namespace {

// A runtime patch's sub-triangle: its centroid, patch and index in
// RuntimePatches::triangles.
struct Original {
  glm::dvec3 centroid;
  uint32_t receiver, sub;
};

double areaOf(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  return 0.5 * glm::length(glm::cross(b - a, c - a));
}

// Per bake patch: its runtime patches' sub-triangles and their area.
struct PatchOriginals {
  std::vector<std::vector<Original>> originals;
  std::vector<double> area;
};

PatchOriginals originalsByPatch(const RuntimePatches& patches) {
  PatchOriginals out;
  out.originals.resize(patches.bake_members.size());
  out.area.assign(out.originals.size(), 0.0);
  for (size_t s = 0; s < patches.triangles.triangleCount(); ++s) {
    const uint32_t r = patches.triangles.front_receiver[s];
    const glm::dvec3 a = dvec(patches.triangles.positions[s * 3]),
                     b = dvec(patches.triangles.positions[s * 3 + 1]),
                     c = dvec(patches.triangles.positions[s * 3 + 2]);
    out.originals[patches.bake_patch[r]].push_back({(a + b + c) / 3.0, r, uint32_t(s)});
    out.area[patches.bake_patch[r]] += areaOf(a, b, c);
  }
  return out;
}

// Proxy face `f`'s bake patch (`group`) and corners; false when the patch
// has no sub-triangles to stand for.
bool proxyFace(const BakeProxyMesh& proxy, const PatchOriginals& po, size_t f, uint32_t& group,
               glm::dvec3 (&corner)[3]) {
  group = proxy.face_patch[f];
  if (group >= po.originals.size() || po.originals[group].empty()) return false;
  for (int k = 0; k < 3; ++k) corner[k] = dvec(proxy.positions[proxy.indices[f * 3 + size_t(k)]]);
  return true;
}

// Per bake patch: whether its proxy faces replace its sub-triangles. From
// its proxy's area and how many pieces of a quarter of a patch its faces
// would be cut into (n x n per face): a bake patch keeps its own
// sub-triangles unless its proxy is much simpler and covers about its own
// area. Flat walls and floors simplify to about what they were (and a
// wall's few proxy faces may all stand for one of its patches, leaving the
// others none), and their pieces would only blur the patch outlines, while
// detailed meshes shed most of their triangles.
std::vector<bool> chooseProxyPatches(const BakeProxyMesh& proxy, const PatchOriginals& po,
                                     double max_area_m2) {
  const size_t groups = po.originals.size();
  std::vector<double> proxy_area(groups, 0.0);
  std::vector<size_t> piece_count(groups, 0);
  const size_t faces = proxy.indices.size() / 3;
  for (size_t f = 0; f < faces; ++f) {
    uint32_t group;
    glm::dvec3 c[3];
    if (!proxyFace(proxy, po, f, group, c)) continue;
    const double area = areaOf(c[0], c[1], c[2]);
    const int n = tessellation(area, max_area_m2 / 4);
    proxy_area[group] += area;
    piece_count[group] += size_t(n) * size_t(n);
  }
  std::vector<bool> use_proxy(groups, false);
  for (size_t g = 0; g < groups; ++g) {
    const double coverage = po.area[g] > 0 ? proxy_area[g] / po.area[g] : 0.0;
    use_proxy[g] = double(piece_count[g]) < kProxyShare * double(po.originals[g].size()) &&
                   coverage > kProxyCoverage[0] && coverage < kProxyCoverage[1];
  }
  return use_proxy;
}

// The runtime patch of the sub-triangle of `originals` nearest `centroid`.
uint32_t nearestReceiver(const std::vector<Original>& originals, const glm::dvec3& centroid) {
  uint32_t best = originals.front().receiver;
  double best_d = kNoUpperBound;
  for (const Original& o : originals) {
    const double d = glm::dot(centroid - o.centroid, centroid - o.centroid);
    if (d < best_d) {
      best_d = d;
      best = o.receiver;
    }
  }
  return best;
}

// The chosen patches' proxy faces cut into those pieces, each standing for
// its nearest original sub-triangle's runtime patch, so the pieces follow
// the patch outlines closely.
std::vector<MapTriangles> cutProxyFaces(const BakeProxyMesh& proxy, const PatchOriginals& po,
                                        const std::vector<bool>& use_proxy, double max_area_m2) {
  std::vector<MapTriangles> pieces(po.originals.size());
  const size_t faces = proxy.indices.size() / 3;
  for (size_t f = 0; f < faces; ++f) {
    uint32_t group;
    glm::dvec3 c[3];
    if (!proxyFace(proxy, po, f, group, c) || !use_proxy[group]) continue;
    const int n = tessellation(areaOf(c[0], c[1], c[2]), max_area_m2 / 4);
    forEachSubTriangle(n, [&](uint32_t, const double(&w)[3][2]) {
      glm::dvec3 p[3];
      for (int k = 0; k < 3; ++k) p[k] = c[0] + w[k][0] * (c[1] - c[0]) + w[k][1] * (c[2] - c[0]);
      const glm::dvec3 centroid = (p[0] + p[1] + p[2]) / 3.0;
      const uint32_t best = nearestReceiver(po.originals[group], centroid);
      for (const glm::dvec3& q : p) pieces[group].positions.push_back(fromGlm(glm::vec3(q)));
      pieces[group].front_receiver.push_back(best);
      pieces[group].back_receiver.push_back(kNoReceiver);
    });
  }
  return pieces;
}

}  // namespace

MapTriangles proxyMapTriangles(const BakeData& bake, const RuntimePatches& patches,
                               double max_area_m2) {
  const PatchOriginals po = originalsByPatch(patches);
  const std::vector<bool> use_proxy = chooseProxyPatches(bake.proxy, po, max_area_m2);
  const std::vector<MapTriangles> pieces = cutProxyFaces(bake.proxy, po, use_proxy, max_area_m2);
  MapTriangles out;
  for (size_t g = 0; g < po.originals.size(); ++g) {
    if (use_proxy[g]) {
      const MapTriangles& p = pieces[g];
      out.positions.insert(out.positions.end(), p.positions.begin(), p.positions.end());
      out.front_receiver.insert(out.front_receiver.end(), p.front_receiver.begin(),
                                p.front_receiver.end());
      out.back_receiver.insert(out.back_receiver.end(), p.back_receiver.begin(),
                               p.back_receiver.end());
      continue;
    }
    for (const Original& o : po.originals[g]) {
      for (int k = 0; k < 3; ++k)
        out.positions.push_back(patches.triangles.positions[size_t(o.sub) * 3 + size_t(k)]);
      out.front_receiver.push_back(patches.triangles.front_receiver[o.sub]);
      out.back_receiver.push_back(patches.triangles.back_receiver[o.sub]);
    }
  }
  return out;
}

std::vector<glm::dvec3> vertexValues(const RuntimePatches& patches,
                                     const std::vector<glm::dvec3>& per_patch) {
  std::vector<glm::dvec3> sum(patches.vertex_count, glm::dvec3(0.0));
  std::vector<double> weight(patches.vertex_count, 0.0);
  const size_t subs = patches.triangles.triangleCount();
  for (size_t s = 0; s < subs; ++s) {
    const uint32_t r = patches.triangles.front_receiver[s];
    const glm::dvec3 a = dvec(patches.triangles.positions[s * 3]),
                     b = dvec(patches.triangles.positions[s * 3 + 1]),
                     c = dvec(patches.triangles.positions[s * 3 + 2]);
    const double area = 0.5 * glm::length(glm::cross(b - a, c - a));
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = patches.triangle_vertices[s * 3 + size_t(k)];
      sum[v] += per_patch[r] * area;
      weight[v] += area;
    }
  }
  for (size_t v = 0; v < sum.size(); ++v) {
    if (weight[v] > 0) sum[v] /= weight[v];
  }
  return sum;
}

}  // namespace svit::gl
