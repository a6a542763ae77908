// Exact texel rasterization of lightmap triangles: each triangle's UV
// polygon is clipped against every texel square it overlaps (Sutherland &
// Hodgman, "Reentrant Polygon Clipping", CACM 1974), which gives the covered
// area and its centroid. Sample points inside or behind geometry are found
// with short probe rays that meet a back face, and moved across it or
// buried (black: the floor under a wall): the usual leak guard of production lightmappers (Unity's
// texel validity / backface tolerance, Bakery's sample adjustment). The probes reach about a texel,
// so they fix texels that straddle a surface; a texel deep inside a solid stays (its lighting sees
// black back faces; unseen).
//
// Work is split into bands of rows of one page; each band reads the
// triangles that overlap it in triangle order and writes only its own
// samples, so results do not depend on the thread count.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "svit/baker/lightmap_atlas.h"
#include "util/parallel_for.h"

namespace svit::baker {
namespace {

// rows per work item: small enough to balance, large enough to batch rays
constexpr int kBandRows = 8;

// Clipped areas below this (texel^2) are round-off of a triangle that only
// touches the texel along an edge or corner: such a part is at most a texel
// long and, with coordinates up to ~1e4 texels in double, ~1e-12 wide.
constexpr double kMinArea = 1e-9;

// A point whose barycentrics lie this far outside [0, 1] (dimensionless) is
// on the triangle's edge up to the float rounding of its UVs (relative
// 6e-8): it is clamped onto the edge rather than treated as outside.
constexpr double kBaryTolerance = 1e-6;

// Move candidates sit this fraction of the way from a vertex (or edge
// midpoint) of the covered part back towards its centroid: strictly inside
// the part, so never exactly on a world edge where a wall may stand.
constexpr double kCandidateInset = 0.05;

struct Pt {
  double x = 0, y = 0;
};

/// Convex polygon; a triangle clipped by 4 half-planes has at most 7 corners.
struct Poly {
  int n = 0;
  Pt p[8];
};

/// Sutherland-Hodgman against one axis-aligned half-plane: keeps points with
/// coordinate `axis` >= bound (keep_above) or <= bound.
void clipHalfPlane(const Poly& in, Poly* out, int axis, double bound, bool keep_above) {
  out->n = 0;
  if (in.n == 0) return;
  auto coord = [axis](const Pt& q) { return axis == 0 ? q.x : q.y; };
  auto inside = [&](const Pt& q) { return keep_above ? coord(q) >= bound : coord(q) <= bound; };
  for (int i = 0; i < in.n; ++i) {
    const Pt& a = in.p[i];
    const Pt& b = in.p[(i + 1) % in.n];
    const bool a_in = inside(a), b_in = inside(b);
    if (a_in) out->p[out->n++] = a;
    if (a_in != b_in) {
      // b_in != a_in: coord(b) != coord(a)
      const double s = (bound - coord(a)) / (coord(b) - coord(a));
      Pt q{a.x + s * (b.x - a.x), a.y + s * (b.y - a.y)};
      if (axis == 0)
        q.x = bound;
      else
        q.y = bound;  // exact on the clip line
      out->p[out->n++] = q;
    }
  }
}

void clipToBox(const Poly& in, Poly* out, double x0, double x1, double y0, double y1) {
  Poly a, b;
  clipHalfPlane(in, &a, 0, x0, true);
  clipHalfPlane(a, &b, 0, x1, false);
  clipHalfPlane(b, &a, 1, y0, true);
  clipHalfPlane(a, out, 1, y1, false);
}

void clipToRows(const Poly& in, Poly* out, double y0, double y1) {
  Poly a;
  clipHalfPlane(in, &a, 1, y0, true);
  clipHalfPlane(a, out, 1, y1, false);
}

void clipToColumns(const Poly& in, Poly* out, double x0, double x1) {
  Poly a;
  clipHalfPlane(in, &a, 0, x0, true);
  clipHalfPlane(a, out, 0, x1, false);
}

/// Unsigned area and centroid of a convex polygon, computed relative to
/// `origin` (the texel corner) so large page coordinates do not cancel.
double areaCentroid(const Poly& poly, Pt origin, Pt* centroid) {
  double twice_area = 0, cx = 0, cy = 0;
  for (int i = 0; i < poly.n; ++i) {
    const double ax = poly.p[i].x - origin.x, ay = poly.p[i].y - origin.y;
    const double bx = poly.p[(i + 1) % poly.n].x - origin.x,
                 by = poly.p[(i + 1) % poly.n].y - origin.y;
    const double c = ax * by - bx * ay;
    twice_area += c;
    cx += (ax + bx) * c;
    cy += (ay + by) * c;
  }
  if (twice_area == 0.0) return 0.0;
  *centroid = {origin.x + cx / (3.0 * twice_area), origin.y + cy / (3.0 * twice_area)};
  return 0.5 * std::fabs(twice_area);
}

/// A face's UVs (LightmapAtlas: a triangle's front or back) in texel units of its page.
struct UvTriangle {
  Pt c[3];
  double twice_signed_area = 0;
};

UvTriangle uvTriangle(const LightmapAtlas& atlas, size_t face) {
  UvTriangle tri;
  for (int k = 0; k < 3; ++k) {
    const Vec2& uv = atlas.triangle_uv[face * 3 + size_t(k)];
    tri.c[k] = {double(uv.x) * atlas.page_width, double(uv.y) * atlas.page_height};
  }
  tri.twice_signed_area = (tri.c[1].x - tri.c[0].x) * (tri.c[2].y - tri.c[0].y) -
                          (tri.c[1].y - tri.c[0].y) * (tri.c[2].x - tri.c[0].x);
  return tri;
}

Poly asPoly(const UvTriangle& tri) {
  Poly poly;
  poly.n = 3;
  for (int k = 0; k < 3; ++k) poly.p[k] = tri.c[k];
  return poly;
}

/// Barycentrics (u, v) of `p` in the UV triangle: p = (1-u-v) c0 + u c1 + v c2.
void barycentric(const UvTriangle& tri, Pt p, double* u, double* v) {
  const double px = p.x - tri.c[0].x, py = p.y - tri.c[0].y;
  const double e1x = tri.c[1].x - tri.c[0].x, e1y = tri.c[1].y - tri.c[0].y;
  const double e2x = tri.c[2].x - tri.c[0].x, e2y = tri.c[2].y - tri.c[0].y;
  // Only called for triangles that cover some texel area, so the UV area is
  // positive; the guard keeps a sliver's round-off from dividing by zero.
  if (tri.twice_signed_area == 0.0) {
    *u = *v = 1.0 / 3.0;
    return;
  }
  *u = (px * e2y - py * e2x) / tri.twice_signed_area;
  *v = (e1x * py - e1y * px) / tri.twice_signed_area;
}

bool insideBarycentric(double u, double v) {
  return u >= -kBaryTolerance && v >= -kBaryTolerance && u + v <= 1.0 + kBaryTolerance;
}

void clampBarycentric(double* u, double* v) {
  *u = std::max(0.0, *u);
  *v = std::max(0.0, *v);
  const double s = *u + *v;
  if (s > 1.0) {
    *u /= s;
    *v /= s;
  }
}

Vec3 worldPoint(const BakeGeometry& geometry, size_t t, double u, double v) {
  const Vec3& a = geometry.corner(t, 0);
  const Vec3& b = geometry.corner(t, 1);
  const Vec3& c = geometry.corner(t, 2);
  const double w = 1.0 - u - v;
  return {float(w * a.x + u * b.x + v * c.x), float(w * a.y + u * b.y + v * c.y),
          float(w * a.z + u * b.z + v * c.z)};
}

/// Texel range [lo, hi] that a coordinate interval [a, b] overlaps in a page of `size` texels.
void texelSpan(double a, double b, int size, int* lo, int* hi) {
  *lo = std::clamp(int(std::floor(a)), 0, size - 1);
  *hi = std::clamp(int(std::ceil(b)) - 1, *lo, size - 1);
}

// ---------------------------------------------------------------- leak probes

/// Probe directions: the normal and 8 directions in the tangent plane
/// (Duff et al., "Building an Orthonormal Basis, Revisited", JCGT 2017).
constexpr int kProbes = 9;

void probeDirections(const Vec3& n, Vec3 out[kProbes]) {
  const double sign = std::copysign(1.0, double(n.z));
  const double a = -1.0 / (sign + n.z);
  const double b = double(n.x) * n.y * a;
  const double tx = 1.0 + sign * n.x * n.x * a, ty = sign * b, tz = -sign * n.x;
  const double bx = b, by = sign + n.y * n.y * a, bz = -double(n.y);
  const double h = std::sqrt(0.5);
  const double dirs[8][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {h, h}, {h, -h}, {-h, h}, {-h, -h}};
  for (int i = 0; i < 8; ++i) {
    out[i] = {float(dirs[i][0] * tx + dirs[i][1] * bx), float(dirs[i][0] * ty + dirs[i][1] * by),
              float(dirs[i][0] * tz + dirs[i][1] * bz)};
  }
  out[8] = n;
}

void appendProbes(const Vec3& p, const Vec3& n, float magnitude_m, float length_m,
                  std::vector<Ray>* rays) {
  Vec3 dirs[kProbes];
  probeDirections(n, dirs);
  const Vec3 origin = offsetRayOrigin(p, n, magnitude_m);
  for (const Vec3& d : dirs) {
    Ray ray;
    ray.origin = origin;
    ray.direction = d;
    ray.t_near = 0.0f;
    ray.t_far = length_m;
    rays->push_back(ray);
  }
}

/// First probe (in direction order) whose closest hit is the back of a
/// one-sided triangle, or -1. A double-sided surface has no inside, and the
/// lighting treats one-sided backs as black, so only those betray a leak.
int firstBackHit(const BakeGeometry& geometry, const RayHit* hits) {
  for (int i = 0; i < kProbes; ++i) {
    if (hits[i].hit() && !hits[i].front && !geometry.double_sided[hits[i].triangle]) return i;
  }
  return -1;
}

struct BandInput {
  const BakeGeometry* geometry;
  const LightmapAtlas* atlas;
  const RayCaster* caster;
  const RasterSettings* settings;
  const std::vector<uint32_t>* band_start;
  const std::vector<uint32_t>* band_faces;
  int bands_per_page;
};

/// The rows [y_begin, y_end) of one page that a band covers.
struct BandRows {
  uint32_t page = 0;
  int y_begin = 0, y_end = 0;
  size_t texels = 0;
};

/// Per texel of a band: the best face, its covered area and centroid, and
/// the sums over all faces for coverage and the texel-wide centroid.
struct BandCoverage {
  std::vector<double> best_area, sum_area, sum_x, sum_y;
  std::vector<uint32_t> best_face;
  std::vector<Pt> best_centroid;
};

/// Clips every face of the band against each texel it overlaps.
BandCoverage coverBand(const BandInput& in, size_t band, const BandRows& rows) {
  const LightmapAtlas& atlas = *in.atlas;
  const int w = atlas.page_width;
  const size_t texels = rows.texels;
  const uint32_t first = (*in.band_start)[band], last = (*in.band_start)[band + 1];
  BandCoverage c;
  c.best_area.assign(texels, 0.0);
  c.sum_area.assign(texels, 0.0);
  c.sum_x.assign(texels, 0.0);
  c.sum_y.assign(texels, 0.0);
  c.best_face.assign(texels, RayHit::kNone);
  c.best_centroid.resize(texels);
  for (uint32_t i = first; i < last; ++i) {
    const uint32_t f = (*in.band_faces)[i];  // ascending: ties keep the lower index
    const Poly tri = asPoly(uvTriangle(atlas, f));
    for (int y = rows.y_begin; y < rows.y_end; ++y) {
      Poly row;
      clipToRows(tri, &row, y, y + 1);
      if (row.n < 3) continue;
      double min_x = row.p[0].x, max_x = row.p[0].x;
      for (int k = 1; k < row.n; ++k) {
        min_x = std::min(min_x, row.p[k].x);
        max_x = std::max(max_x, row.p[k].x);
      }
      int x_lo, x_hi;
      texelSpan(min_x, max_x, w, &x_lo, &x_hi);
      for (int x = x_lo; x <= x_hi; ++x) {
        Poly part;
        clipToColumns(row, &part, x, x + 1);
        if (part.n < 3) continue;
        Pt centroid;
        const double area = areaCentroid(part, {double(x), double(y)}, &centroid);
        if (!(area > kMinArea)) continue;
        const size_t j = size_t(y - rows.y_begin) * size_t(w) + size_t(x);
        c.sum_area[j] += area;
        c.sum_x[j] += area * centroid.x;
        c.sum_y[j] += area * centroid.y;
        if (area > c.best_area[j]) {
          c.best_area[j] = area;
          c.best_face[j] = f;
          c.best_centroid[j] = centroid;
        }
      }
    }
  }
  return c;
}

/// One sample per covered texel, on its winning face, in (y, x) order.
std::vector<TexelSample> placeSamples(const BandInput& in, const BandRows& rows,
                                      const BandCoverage& c) {
  const BakeGeometry& geometry = *in.geometry;
  const LightmapAtlas& atlas = *in.atlas;
  const int w = atlas.page_width;
  std::vector<TexelSample> samples;
  for (size_t j = 0; j < rows.texels; ++j) {
    if (c.best_face[j] == RayHit::kNone) continue;
    const uint32_t f = c.best_face[j];
    const uint32_t t = atlas.faceTriangle(f);
    const UvTriangle tri = uvTriangle(atlas, f);
    // The centroid of everything covered represents the whole texel (at
    // the texel centre inside a chart, as bilinear lookup assumes); it is
    // used when it lies on the winning triangle, else the winner's own
    // covered centroid (a chart border or corner).
    Pt point{c.sum_x[j] / c.sum_area[j], c.sum_y[j] / c.sum_area[j]};
    double u, v;
    barycentric(tri, point, &u, &v);
    if (!insideBarycentric(u, v)) {
      point = c.best_centroid[j];
      barycentric(tri, point, &u, &v);
    }
    clampBarycentric(&u, &v);
    TexelSample s;
    s.page = rows.page;
    s.x = uint32_t(j % size_t(w));
    s.y = uint32_t(rows.y_begin + int(j / size_t(w)));
    s.triangle = t;
    s.face = f;
    s.u = float(u);
    s.v = float(v);
    s.position = worldPoint(geometry, t, u, v);
    const Vec3& n = geometry.normals[t];
    s.normal = atlas.isBack(f) ? Vec3{-n.x, -n.y, -n.z} : n;
    s.coverage = float(std::min(1.0, c.sum_area[j]));
    samples.push_back(s);
  }
  return samples;
}

/// World length of `probe_texels` texels on a face: sqrt(world area / UV area) per texel.
float probeLength(const BandInput& in, uint32_t face) {
  const double uv_area = 0.5 * std::fabs(uvTriangle(*in.atlas, face).twice_signed_area);
  return float(in.settings->leak_probe_texels *
               std::sqrt(double(in.geometry->areas_m2[in.atlas->faceTriangle(face)]) / uv_area));
}

/// A place a leaking sample may move to.
struct Candidate {
  size_t pending;
  double u, v;
  Vec3 position;
  double along;  ///< metres moved along the probe that found the back face
};

/// Candidates of the leaking samples, in their trial order, and which
/// samples leak.
struct LeakCandidates {
  std::vector<Candidate> candidates;
  std::vector<uint8_t> leaking;  ///< per sample
};

/// Leaking samples: candidates are the inset vertices and edge midpoints of
/// the winner's covered part, tried in order of how far they move along the
/// probe that saw the back face (the outside lies beyond that face; ties
/// keep polygon order).
LeakCandidates findLeakCandidates(const BandInput& in, const std::vector<TexelSample>& pending,
                                  const std::vector<Ray>& rays, const std::vector<RayHit>& hits) {
  const BakeGeometry& geometry = *in.geometry;
  LeakCandidates out;
  std::vector<Candidate>& candidates = out.candidates;
  out.leaking.assign(pending.size(), 0);
  for (size_t i = 0; i < pending.size(); ++i) {
    const int probe = firstBackHit(geometry, &hits[i * kProbes]);
    if (probe < 0) continue;
    out.leaking[i] = 1;
    const TexelSample& s = pending[i];
    const uint32_t t = s.triangle;
    const UvTriangle tri = uvTriangle(*in.atlas, s.face);
    Poly part;
    clipToBox(asPoly(tri), &part, s.x, s.x + 1.0, s.y, s.y + 1.0);
    Pt centroid;
    if (!(areaCentroid(part, {double(s.x), double(s.y)}, &centroid) > 0.0)) continue;
    const Vec3& d = rays[i * kProbes + size_t(probe)].direction;
    const size_t begin = candidates.size();
    for (int k = 0; k < part.n; ++k) {
      const Pt& a = part.p[k];
      const Pt& b = part.p[(k + 1) % part.n];
      for (const Pt& q : {a, Pt{0.5 * (a.x + b.x), 0.5 * (a.y + b.y)}}) {
        Candidate c;
        c.pending = i;
        const Pt uv{q.x + kCandidateInset * (centroid.x - q.x),
                    q.y + kCandidateInset * (centroid.y - q.y)};
        barycentric(tri, uv, &c.u, &c.v);
        clampBarycentric(&c.u, &c.v);
        c.position = worldPoint(geometry, t, c.u, c.v);
        c.along = (double(c.position.x) - s.position.x) * d.x +
                  (double(c.position.y) - s.position.y) * d.y +
                  (double(c.position.z) - s.position.z) * d.z;
        candidates.push_back(c);
      }
    }
    std::stable_sort(candidates.begin() + std::ptrdiff_t(begin), candidates.end(),
                     [](const Candidate& a, const Candidate& b) { return a.along > b.along; });
  }
  return out;
}

constexpr size_t kCandidateRays = kProbes + 1;  // its probes, then the path from the sample

/// Moves each leaking sample to its first candidate that is taken: the
/// straight path from the sample to it meets a one-sided back face first
/// (it crossed to the far side of the surface; without this a point deeper
/// inside a solid, just out of the short probes' reach, would pass as
/// outside), and its own probes find no back face. Returns which moved.
std::vector<uint8_t> moveLeakingSamples(const BandInput& in,
                                        const std::vector<Candidate>& candidates,
                                        std::vector<TexelSample>& pending) {
  const BakeGeometry& geometry = *in.geometry;
  std::vector<Ray> candidate_rays;
  candidate_rays.reserve(candidates.size() * kCandidateRays);
  for (const Candidate& c : candidates) {
    const TexelSample& s = pending[c.pending];
    const float magnitude = cornerMagnitude(geometry, s.triangle);
    appendProbes(c.position, s.normal, magnitude, probeLength(in, s.face), &candidate_rays);
    // Both ends offset alike, so the path runs parallel to a flat surface
    // instead of diving into it at the far end.
    Ray path;
    path.origin = offsetRayOrigin(s.position, s.normal, magnitude);
    const Vec3 to = offsetRayOrigin(c.position, s.normal, magnitude);
    path.direction = {to.x - path.origin.x, to.y - path.origin.y, to.z - path.origin.z};
    path.t_far = 1.0f;
    candidate_rays.push_back(path);
  }
  std::vector<RayHit> candidate_hits(candidate_rays.size());
  if (!candidate_rays.empty()) in.caster->intersect(candidate_rays, candidate_hits);
  std::vector<uint8_t> moved(pending.size(), 0);
  for (size_t c = 0; c < candidates.size(); ++c) {
    const Candidate& cand = candidates[c];
    const RayHit* probe_hits = &candidate_hits[c * kCandidateRays];
    const RayHit& path = probe_hits[kProbes];
    const bool crossed = path.hit() && !path.front && !geometry.double_sided[path.triangle];
    if (moved[cand.pending] || !crossed || firstBackHit(geometry, probe_hits) >= 0) continue;
    TexelSample& s = pending[cand.pending];
    s.u = float(cand.u);
    s.v = float(cand.v);
    s.position = cand.position;
    moved[cand.pending] = 1;
  }
  return moved;
}

/// A band's samples, and the texels it found wholly inside or behind
/// geometry (their samples dropped), in (y, x) order.
struct BandTexels {
  std::vector<TexelSample> samples;
  std::vector<TexelSample> buried;
};

/// Probes every sample for leaks; moves the leaking ones out where it can
/// and buries the rest (a leaking texel with no way out).
BandTexels resolveLeaks(const BandInput& in, std::vector<TexelSample>& pending) {
  const BakeGeometry& geometry = *in.geometry;
  std::vector<Ray> rays;
  rays.reserve(pending.size() * kProbes);
  for (const TexelSample& s : pending) {
    appendProbes(s.position, s.normal, cornerMagnitude(geometry, s.triangle),
                 probeLength(in, s.face), &rays);
  }
  std::vector<RayHit> hits(rays.size());
  in.caster->intersect(rays, hits);
  const LeakCandidates leaks = findLeakCandidates(in, pending, rays, hits);
  const std::vector<uint8_t> moved = moveLeakingSamples(in, leaks.candidates, pending);
  BandTexels result;
  for (size_t i = 0; i < pending.size(); ++i) {
    (!leaks.leaking[i] || moved[i] ? result.samples : result.buried).push_back(pending[i]);
  }
  return result;
}

/// Rasterizes one band, then pulls or drops its leaking samples. Output in (y, x) order.
BandTexels rasterizeBand(const BandInput& in, size_t band) {
  const int w = in.atlas->page_width, h = in.atlas->page_height;
  BandRows rows;
  rows.page = uint32_t(band / size_t(in.bands_per_page));
  rows.y_begin = int(band % size_t(in.bands_per_page)) * kBandRows;
  rows.y_end = std::min(h, rows.y_begin + kBandRows);
  rows.texels = size_t(w) * size_t(rows.y_end - rows.y_begin);
  if ((*in.band_start)[band] == (*in.band_start)[band + 1]) return {};
  std::vector<TexelSample> pending = placeSamples(in, rows, coverBand(in, band, rows));
  if (!(in.settings->leak_probe_texels > 0.0)) return {std::move(pending), {}};
  return resolveLeaks(in, pending);
}

/// The bands' samples in (page, y, x) order, and their buried texels.
TexelSet assembleTexelSet(const LightmapAtlas& atlas, std::vector<BandTexels>& band_texels) {
  const int w = atlas.page_width, h = atlas.page_height;
  TexelSet set;
  set.page_width = w;
  set.page_height = h;
  set.page_count = atlas.page_count;
  set.texel_to_sample.assign(size_t(atlas.page_count) * size_t(w) * size_t(h), kNoSample);
  const auto at = [&](const TexelSample& s) -> int32_t& {
    return set.texel_to_sample[(size_t(s.page) * size_t(h) + s.y) * size_t(w) + s.x];
  };
  size_t total = 0;
  for (const BandTexels& band : band_texels) total += band.samples.size();
  set.samples.reserve(total);
  for (BandTexels& band : band_texels) {  // band order is (page, y) order
    for (const TexelSample& sample : band.samples) {
      at(sample) = int32_t(set.samples.size());
      set.samples.push_back(sample);
    }
    for (const TexelSample& sample : band.buried) at(sample) = kBuriedTexel;
    band = BandTexels{};
  }
  return set;
}

Status validate(const BakeGeometry& geometry, const LightmapAtlas& atlas,
                const RasterSettings& settings) {
  const size_t count = geometry.triangleCount();
  if (geometry.positions.size() != count * 3 || geometry.normals.size() != count ||
      geometry.double_sided.size() != count) {
    return Status(StatusCode::kInvalidInput,
                  "rasterize texels: bake geometry arrays disagree in length");
  }
  if (atlas.page_width < 1 || atlas.page_height < 1 || atlas.page_count < 1) {
    return Status(StatusCode::kInvalidInput,
                  "rasterize texels: atlas has " + std::to_string(atlas.page_count) + " pages of " +
                      std::to_string(atlas.page_width) + "x" + std::to_string(atlas.page_height));
  }
  const size_t faces = atlas.faceCount();
  if (faces < atlas.back_triangles.size() || atlas.frontCount() != count ||
      atlas.triangle_uv.size() != faces * 3 || atlas.triangle_chart.size() != faces) {
    return Status(StatusCode::kInvalidInput,
                  "rasterize texels: atlas covers " + std::to_string(atlas.triangle_page.size()) +
                      " faces with " + std::to_string(atlas.back_triangles.size()) +
                      " backs, bake geometry has " + std::to_string(count) + " triangles");
  }
  for (size_t i = 0; i < atlas.back_triangles.size(); ++i) {
    const uint32_t t = atlas.back_triangles[i];
    if (t >= count || !geometry.double_sided[t] || (i > 0 && t <= atlas.back_triangles[i - 1])) {
      return Status(StatusCode::kInvalidInput, "rasterize texels: back face " + std::to_string(i) +
                                                   " names triangle " + std::to_string(t) +
                                                   ", not a double-sided triangle after the last");
    }
  }
  for (size_t f = 0; f < faces; ++f) {
    if (atlas.triangle_page[f] >= uint32_t(atlas.page_count)) {
      return Status(StatusCode::kInvalidInput, "rasterize texels: face " + std::to_string(f) +
                                                   " is on page " +
                                                   std::to_string(atlas.triangle_page[f]) + " of " +
                                                   std::to_string(atlas.page_count));
    }
    for (int k = 0; k < 3; ++k) {
      const Vec2& uv = atlas.triangle_uv[f * 3 + size_t(k)];
      if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) {
        return Status(StatusCode::kInvalidInput, "rasterize texels: face " + std::to_string(f) +
                                                     " corner " + std::to_string(k) +
                                                     " has a non-finite UV");
      }
    }
  }
  if (!(settings.leak_probe_texels >= 0.0) || !std::isfinite(settings.leak_probe_texels)) {
    return Status(StatusCode::kInvalidInput, "rasterize texels: leak_probe_texels " +
                                                 std::to_string(settings.leak_probe_texels) +
                                                 " must be finite and >= 0");
  }
  return Status::okStatus();
}

}  // namespace

Expected<TexelSet> rasterizeTexels(const BakeGeometry& geometry, const LightmapAtlas& atlas,
                                   const RayCaster& caster, const RasterSettings& settings) {
  if (Status s = validate(geometry, atlas, settings); !s.ok()) return s;
  const int w = atlas.page_width, h = atlas.page_height;
  const int bands_per_page = (h + kBandRows - 1) / kBandRows;
  const size_t bands = size_t(atlas.page_count) * size_t(bands_per_page);

  // Bin faces into the bands their UV rows overlap (counting sort, in
  // face order, so each band's list is ascending).
  std::vector<uint32_t> band_start(bands + 1, 0);
  auto bandRange = [&](size_t f, size_t* b0, size_t* b1) {
    const UvTriangle tri = uvTriangle(atlas, f);
    if (tri.twice_signed_area == 0.0) return false;
    const double y0 = std::min({tri.c[0].y, tri.c[1].y, tri.c[2].y}),
                 y1 = std::max({tri.c[0].y, tri.c[1].y, tri.c[2].y});
    const double x0 = std::min({tri.c[0].x, tri.c[1].x, tri.c[2].x}),
                 x1 = std::max({tri.c[0].x, tri.c[1].x, tri.c[2].x});
    if (y1 <= 0.0 || y0 >= h || x1 <= 0.0 || x0 >= w) return false;  // off the page
    int lo, hi;
    texelSpan(y0, y1, h, &lo, &hi);
    const size_t base = size_t(atlas.triangle_page[f]) * size_t(bands_per_page);
    *b0 = base + size_t(lo / kBandRows);
    *b1 = base + size_t(hi / kBandRows) + 1;
    return true;
  };
  for (size_t f = 0; f < atlas.faceCount(); ++f) {
    size_t b0, b1;
    if (!bandRange(f, &b0, &b1)) continue;
    for (size_t b = b0; b < b1; ++b) ++band_start[b + 1];
  }
  for (size_t b = 0; b < bands; ++b) band_start[b + 1] += band_start[b];
  std::vector<uint32_t> band_faces(band_start[bands]);
  {
    std::vector<uint32_t> fill(band_start.begin(), band_start.end() - 1);
    for (size_t f = 0; f < atlas.faceCount(); ++f) {
      size_t b0, b1;
      if (!bandRange(f, &b0, &b1)) continue;
      for (size_t b = b0; b < b1; ++b) band_faces[fill[b]++] = uint32_t(f);
    }
  }

  BandInput input{&geometry, &atlas, &caster, &settings, &band_start, &band_faces, bands_per_page};
  std::vector<BandTexels> band_texels(bands);
  parallelFor(bands, 1, resolveThreads(settings.threads), [&](size_t begin, size_t end) {
    for (size_t b = begin; b < end; ++b) band_texels[b] = rasterizeBand(input, b);
  });
  return assembleTexelSet(atlas, band_texels);
}

std::array<Vec3, 4> texelFootprint(const BakeGeometry& geometry, const LightmapAtlas& atlas,
                                   const TexelSample& s) {
  const UvTriangle tri = uvTriangle(atlas, s.face);
  std::array<Vec3, 4> corners;
  for (int k = 0; k < 4; ++k) {
    double u, v;
    barycentric(tri, {double(s.x + (k & 1)), double(s.y + (k >> 1))}, &u, &v);
    clampBarycentric(&u, &v);
    corners[size_t(k)] = worldPoint(geometry, s.triangle, u, v);
  }
  return corners;
}

size_t buryTexels(TexelSet& texels, const std::function<bool(const TexelSample&)>& buried) {
  const size_t page = size_t(texels.page_width) * size_t(texels.page_height);
  std::vector<TexelSample> kept;
  kept.reserve(texels.samples.size());
  for (const TexelSample& s : texels.samples) {
    int32_t& slot = texels.texel_to_sample[s.page * page + size_t(s.y) * texels.page_width + s.x];
    if (buried(s)) {
      slot = kBuriedTexel;
      continue;
    }
    slot = int32_t(kept.size());
    kept.push_back(s);
  }
  const size_t count = texels.samples.size() - kept.size();
  texels.samples = std::move(kept);
  return count;
}

}  // namespace svit::baker
