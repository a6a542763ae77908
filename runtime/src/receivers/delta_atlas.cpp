#include "delta_atlas.h"

#include <algorithm>
#include <cmath>

namespace svit::gl {

std::vector<DeltaPage> rasteriseDeltas(const RuntimePatches& patches,
                                       const std::vector<glm::dvec3>& vertex_values,
                                       const std::vector<glm::dvec3>& scale_minus_one,
                                       const std::vector<std::pair<int, int>>& page_sizes) {
  std::vector<DeltaPage> pages(page_sizes.size());
  std::vector<std::vector<uint8_t>> written(pages.size());
  for (size_t p = 0; p < pages.size(); ++p) {
    pages[p].width = std::max(1, page_sizes[p].first / 2);
    pages[p].height = std::max(1, page_sizes[p].second / 2);
    pages[p].rgba.assign(size_t(pages[p].width) * size_t(pages[p].height) * 4, 0.0f);
    written[p].assign(size_t(pages[p].width) * size_t(pages[p].height), 0);
  }
  const size_t subs = patches.triangles.triangleCount();
  // Pass 0 covers texel centres inside each sub-triangle; pass 1 fills the
  // gutter (texels within one texel of a triangle, still empty) with the
  // value at the nearest point of the triangle (clamped barycentrics).
  for (int pass = 0; pass < 2; ++pass) {
    for (size_t s = 0; s < subs; ++s) {
      const uint32_t page = patches.triangle_page[s];
      if (page >= pages.size()) continue;
      DeltaPage& out = pages[page];
      glm::dvec2 uv[3];
      glm::dvec4 value[3];
      for (int k = 0; k < 3; ++k) {
        const Vec2& t = patches.triangle_uvs[s * 3 + size_t(k)];
        uv[k] = {t.x * out.width, t.y * out.height};
        const uint32_t vertex = patches.triangle_vertices[s * 3 + size_t(k)];
        const double scale = vertex < scale_minus_one.size() ? scale_minus_one[vertex].x : 0.0;
        value[k] = glm::dvec4(vertex_values[vertex], scale);
      }
      const glm::dvec2 e1 = uv[1] - uv[0], e2 = uv[2] - uv[0];
      const double det = e1.x * e2.y - e1.y * e2.x;
      if (std::abs(det) < 1e-12) continue;
      const double grow = pass == 0 ? 0.0 : 1.0;
      const int x0 = std::max(0, int(std::floor(std::min({uv[0].x, uv[1].x, uv[2].x}) - grow)));
      const int x1 =
          std::min(out.width - 1, int(std::ceil(std::max({uv[0].x, uv[1].x, uv[2].x}) + grow)));
      const int y0 = std::max(0, int(std::floor(std::min({uv[0].y, uv[1].y, uv[2].y}) - grow)));
      const int y1 =
          std::min(out.height - 1, int(std::ceil(std::max({uv[0].y, uv[1].y, uv[2].y}) + grow)));
      for (int y = y0; y <= y1; ++y) {
        for (int x = x0; x <= x1; ++x) {
          const size_t texel = size_t(y) * size_t(out.width) + size_t(x);
          if (written[page][texel] != 0) continue;
          const glm::dvec2 d = glm::dvec2(x + 0.5, y + 0.5) - uv[0];
          double w1 = (d.x * e2.y - d.y * e2.x) / det, w2 = (e1.x * d.y - e1.y * d.x) / det;
          const bool inside = w1 >= 0 && w2 >= 0 && w1 + w2 <= 1;
          if (pass == 0 && !inside) continue;
          if (pass == 1) {
            w1 = std::clamp(w1, 0.0, 1.0);
            w2 = std::clamp(w2, 0.0, 1.0 - w1);
          }
          const glm::dvec4 v = value[0] * (1 - w1 - w2) + value[1] * w1 + value[2] * w2;
          for (int c = 0; c < 4; ++c) out.rgba[texel * 4 + size_t(c)] = float(v[c]);
          written[page][texel] = 1;
        }
      }
    }
  }
  return pages;
}

}  // namespace svit::gl
