// Lightmap page assembly. Seam stitching follows the usual lightmapper
// practice (e.g. "Lightmap seams", Sloan & Hwu's least-squares seam fix,
// done here as a few Gauss-Seidel rounds): the texels nearest to matching
// points on the two sides of a seam are pulled to their common average.

#include "svit/baker/lightmap_pages.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <unordered_map>

#include "atlas/texel_neighbours.h"
#include "util/parallel_for.h"
#include "util/random.h"

namespace svit::baker {
namespace {

// Seams between triangles whose normals differ by more than 30 degrees are
// creases, not UV cuts through a smooth surface.
constexpr float kSmoothSeamCos = 0.8660254f;

size_t texelIndex(int width, int x, int y) { return size_t(y) * size_t(width) + size_t(x); }

uint64_t positionKey(const Vec3& p) {
  uint32_t bits[3];
  std::memcpy(bits, &p, sizeof bits);
  return hashIds(bits[0], bits[1], bits[2]);
}

}  // namespace

std::vector<SeamPoint> findSeamPoints(const BakeGeometry& geometry, const LightmapAtlas& atlas) {
  // Edges keyed by their welded end positions; an edge whose two faces
  // (triangle sides) map it to different UVs (or pages) is a seam.
  struct EdgeUse {
    uint32_t face;
    int k;  // edge from corner k to k+1
    uint64_t a_key, b_key;
  };
  std::map<std::pair<uint64_t, uint64_t>, std::vector<EdgeUse>> edges;  // ordered: deterministic
  for (uint32_t f = 0; f < atlas.faceCount(); ++f) {
    const uint32_t t = atlas.faceTriangle(f);
    for (int k = 0; k < 3; ++k) {
      const uint64_t a = positionKey(geometry.corner(t, k)),
                     b = positionKey(geometry.corner(t, (k + 1) % 3));
      edges[{std::min(a, b), std::max(a, b)}].push_back({f, k, a, b});
    }
  }
  // A back's normal points away from its triangle's.
  const auto normal = [&](uint32_t f) {
    const Vec3& n = geometry.normals[atlas.faceTriangle(f)];
    return atlas.isBack(f) ? Vec3{-n.x, -n.y, -n.z} : n;
  };
  std::vector<SeamPoint> points;
  const double texels = double(std::max(atlas.page_width, atlas.page_height));
  for (const auto& [key, uses] : edges) {
    (void)key;
    for (size_t i = 0; i + 1 < uses.size(); ++i) {
      for (size_t j = i + 1; j < uses.size(); ++j) {
        const EdgeUse& e = uses[i];
        const EdgeUse& f = uses[j];
        // Across a crease (or between the two sides of a thin wall) the
        // irradiance really is discontinuous: only smooth seams are stitched.
        const Vec3 ne = normal(e.face), nf = normal(f.face);
        if (ne.x * nf.x + ne.y * nf.y + ne.z * nf.z < kSmoothSeamCos) continue;
        Vec2 a0 = atlas.triangle_uv[e.face * 3 + size_t(e.k)],
             a1 = atlas.triangle_uv[e.face * 3 + size_t((e.k + 1) % 3)];
        Vec2 b0 = atlas.triangle_uv[f.face * 3 + size_t(f.k)],
             b1 = atlas.triangle_uv[f.face * 3 + size_t((f.k + 1) % 3)];
        if (f.a_key != e.a_key) std::swap(b0, b1);  // run both the same way along the edge
        const uint32_t pa = atlas.triangle_page[e.face], pb = atlas.triangle_page[f.face];
        const bool same = pa == pb && a0.x == b0.x && a0.y == b0.y && a1.x == b1.x && a1.y == b1.y;
        if (same) continue;
        const double length =
            std::max(std::hypot(a1.x - a0.x, a1.y - a0.y), std::hypot(b1.x - b0.x, b1.y - b0.y));
        const int samples = std::max(2, int(std::ceil(length * texels * 2.0)));
        for (int s = 0; s < samples; ++s) {
          const float t = (float(s) + 0.5f) / float(samples);
          points.push_back({pa,
                            pb,
                            {a0.x + t * (a1.x - a0.x), a0.y + t * (a1.y - a0.y)},
                            {b0.x + t * (b1.x - b0.x), b0.y + t * (b1.y - b0.y)}});
        }
      }
    }
  }
  return points;
}

namespace {

LightmapPages blankPages(const TexelSet& texels) {
  const int w = texels.page_width, h = texels.page_height;
  LightmapPages pages;
  pages.images.resize(size_t(texels.page_count));
  pages.valid.resize(size_t(texels.page_count));
  for (int p = 0; p < texels.page_count; ++p) {
    pages.images[size_t(p)].width = w;
    pages.images[size_t(p)].height = h;
    pages.images[size_t(p)].rgb.assign(size_t(w) * size_t(h) * 3, 0.0f);
    pages.valid[size_t(p)].assign(size_t(w) * size_t(h), 0);
  }
  return pages;
}

// How much of neighbour j the filter mixes into texel i: noise (guide
// luminances within a few standard errors) yes, an edge of the light no.
double rangeWeight(const FilterGuide& guide, size_t i, size_t j, double k) {
  const double d = double(guide.luminance[j]) - double(guide.luminance[i]);
  const double variance =
      double(guide.sigma[i]) * guide.sigma[i] + double(guide.sigma[j]) * guide.sigma[j];
  if (!(variance > 0)) return d == 0 ? 1.0 : 0.0;
  return std::exp(-d * d / (2.0 * k * k * variance));
}

// Texel i's indirect light, filtered: its chart neighbours within `r`
// texels, weighted by distance, normal and the guide.
Rgb filteredTexel(const LightmapAtlas& atlas, const TexelSet& texels,
                  const std::vector<TexelIrradiance>& lighting, const PageSettings& settings,
                  const FilterGuide& guide, size_t i, int r) {
  double sum[3] = {0, 0, 0}, weight_sum = 0;
  forEachChartNeighbour(atlas, texels, i, r, [&](size_t j, int dx, int dy, double c) {
    const double spatial = std::exp(-double(dx * dx + dy * dy) / (2.0 * r * r));
    const double weight = spatial * std::pow(c, settings.filter_normal_power) *
                          rangeWeight(guide, i, j, settings.filter_noise_sigmas);
    const Rgb& v = lighting[j].indirect;
    sum[0] += weight * v.r;
    sum[1] += weight * v.g;
    sum[2] += weight * v.b;
    weight_sum += weight;
  });
  if (!(weight_sum > 0)) return lighting[i].indirect;
  return {float(sum[0] / weight_sum), float(sum[1] / weight_sum), float(sum[2] / weight_sum)};
}

}  // namespace

// Cross-bilateral on normal, chart and the guide's noise: it never blurs
// across a chart border, a crease or an edge of the light that is not noise.
std::vector<Rgb> filterIndirect(const LightmapAtlas& atlas, const TexelSet& texels,
                                const std::vector<TexelIrradiance>& lighting,
                                const PageSettings& settings) {
  std::vector<Rgb> indirect(lighting.size());
  for (size_t i = 0; i < lighting.size(); ++i) indirect[i] = lighting[i].indirect;
  const FilterGuide* guide = settings.guide.get();
  if (!settings.edge_aware_filter || guide == nullptr ||
      guide->sigma.size() != texels.samples.size())
    return indirect;
  const int r = settings.filter_radius_texels;
  parallelFor(texels.samples.size(), 4096, resolveThreads(settings.threads),
              [&](size_t begin, size_t end) {
                for (size_t i = begin; i < end; ++i)
                  indirect[i] = filteredTexel(atlas, texels, lighting, settings, *guide, i, r);
              });
  return indirect;
}

namespace {

void writeSamples(const TexelSet& texels, const std::vector<TexelIrradiance>& lighting,
                  const std::vector<Rgb>& indirect, LightmapPages& pages) {
  const int w = texels.page_width;
  // Buried texels stay black and count as filled, so dilation leaves them be.
  const size_t page_texels = size_t(w) * size_t(texels.page_height);
  for (size_t i = 0; i < texels.texel_to_sample.size(); ++i) {
    if (texels.texel_to_sample[i] == kBuriedTexel)
      pages.valid[i / page_texels][i % page_texels] = 3;
  }
  for (size_t i = 0; i < texels.samples.size(); ++i) {
    const TexelSample& s = texels.samples[i];
    float* p = &pages.images[s.page].rgb[texelIndex(w, int(s.x), int(s.y)) * 3];
    p[0] = lighting[i].direct.r + indirect[i].r;
    p[1] = lighting[i].direct.g + indirect[i].g;
    p[2] = lighting[i].direct.b + indirect[i].b;
    pages.valid[s.page][texelIndex(w, int(s.x), int(s.y))] = 1;
  }
}

// Dilation: each round fills empty texels next to filled ones with the
// mean of their filled 8-neighbours (marked valid 2).
void dilatePage(int rounds, LightmapImage& image, std::vector<uint8_t>& valid) {
  const int w = image.width, h = image.height;
  for (int round = 0; round < rounds; ++round) {
    std::vector<std::pair<size_t, Rgb>> filled;
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        if (valid[texelIndex(w, x, y)]) continue;
        double sum[3] = {0, 0, 0};
        int count = 0;
        for (int dy = -1; dy <= 1; ++dy) {
          for (int dx = -1; dx <= 1; ++dx) {
            const int nx = x + dx, ny = y + dy;
            if (nx < 0 || ny < 0 || nx >= w || ny >= h || !valid[texelIndex(w, nx, ny)]) continue;
            const Rgb v = image.texel(nx, ny);
            sum[0] += v.r;
            sum[1] += v.g;
            sum[2] += v.b;
            ++count;
          }
        }
        if (count > 0)
          filled.push_back({texelIndex(w, x, y),
                            {float(sum[0] / count), float(sum[1] / count), float(sum[2] / count)}});
      }
    }
    for (const auto& [index, value] : filled) {
      image.rgb[index * 3] = value.r;
      image.rgb[index * 3 + 1] = value.g;
      image.rgb[index * 3 + 2] = value.b;
      valid[index] = 2;
    }
  }
}

// Seams: pull the texels nearest to matching edge points to their average.
void stitchSeams(const BakeGeometry& geometry, const LightmapAtlas& atlas, const TexelSet& texels,
                 int iterations, LightmapPages& pages) {
  const int w = texels.page_width, h = texels.page_height;
  const std::vector<SeamPoint> seam = findSeamPoints(geometry, atlas);
  auto nearest = [&](uint32_t page, Vec2 uv) -> float* {
    const int x = std::clamp(int(uv.x * float(w)), 0, w - 1),
              y = std::clamp(int(uv.y * float(h)), 0, h - 1);
    const uint8_t valid = pages.valid[page][texelIndex(w, x, y)];
    if (valid == 0 || valid == 3) return nullptr;  // a buried texel stays black
    return &pages.images[page].rgb[texelIndex(w, x, y) * 3];
  };
  for (int iteration = 0; iteration < iterations; ++iteration) {
    for (const SeamPoint& point : seam) {
      float* a = nearest(point.page_a, point.uv_a);
      float* b = nearest(point.page_b, point.uv_b);
      if (!a || !b || a == b) continue;
      for (int c = 0; c < 3; ++c) {
        const float mean = 0.5f * (a[c] + b[c]);
        a[c] = mean;
        b[c] = mean;
      }
    }
  }
}

}  // namespace

LightmapPages buildLightmapPages(const BakeGeometry& geometry, const LightmapAtlas& atlas,
                                 const TexelSet& texels,
                                 const std::vector<TexelIrradiance>& lighting,
                                 const PageSettings& settings) {
  LightmapPages pages = blankPages(texels);
  writeSamples(texels, lighting, filterIndirect(atlas, texels, lighting, settings), pages);
  for (int p = 0; p < texels.page_count; ++p) {
    dilatePage(settings.dilation_texels, pages.images[size_t(p)], pages.valid[size_t(p)]);
  }
  stitchSeams(geometry, atlas, texels, settings.seam_iterations, pages);
  return pages;
}

}  // namespace svit::baker
