#include "svit/masked_lights.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "glm_interop.h"

namespace svit {
namespace {

Light sunAsLight(const Sun& sun) {
  Light l;
  l.name = "sun";
  l.type = LightType::kDirectional;
  l.direction = {-sun.direction_to_sun.x, -sun.direction_to_sun.y, -sun.direction_to_sun.z};
  l.color = sun.color;
  l.intensity = sun.illuminance_lux;
  return l;
}

}  // namespace

Expected<MaskedLightField> MaskedLightField::create(const Scene& scene, const BakeData& bake) {
  MaskedLightField field;
  if (bake.masks.lights.empty()) return field;
  field.masks_ = std::make_shared<const BakeShadowMasks>(bake.masks);
  for (const BakeLightmapPage& page : bake.pages) {
    field.page_width_.push_back(page.width);
    field.page_height_.push_back(page.height);
  }
  for (const BakeMaskedLight& m : bake.masks.lights) {
    const BakeEmitter& e = bake.emitters[m.emitter];  // validated: in range, a light or the sun
    if (e.kind == BakeEmitter::Kind::kSun) {
      field.lights_.push_back(sunAsLight(scene.sun));
    } else if (e.index < scene.lights.size() && !scene.lights[e.index].dynamic) {
      field.lights_.push_back(scene.lights[e.index]);
    } else {
      return Status(StatusCode::kInvalidInput,
                    "bake.svit: section SMSK masks emitter " + std::to_string(m.emitter) +
                        ", light " + std::to_string(e.index) +
                        ", which is not a baked light of "
                        "the level (" +
                        std::to_string(scene.lights.size()) + " lights)");
    }
    field.emitters_.push_back(m.emitter);
  }
  return field;
}

Vec3 MaskedLightField::towardLight(size_t k, const Vec3& p) const {
  const Light& l = lights_[k];
  const glm::vec3 d =
      l.type == LightType::kDirectional ? -toGlm(l.direction) : toGlm(l.position) - toGlm(p);
  const float length = glm::length(d);
  return length > 0 ? fromGlm(d / length) : Vec3{0, 1, 0};
}

float MaskedLightField::distanceToLight(size_t k, const Vec3& p) const {
  const Light& l = lights_[k];
  if (l.type == LightType::kDirectional) return std::numeric_limits<float>::infinity();
  return glm::length(toGlm(l.position) - toGlm(p));
}

Rgb MaskedLightField::unshadowed(size_t k, const Vec3& p, const Vec3& n) const {
  const Light& l = lights_[k];
  const glm::dvec3 colour(l.color.r, l.color.g, l.color.b);
  glm::dvec3 e = colour * double(l.intensity);
  glm::dvec3 toward;
  if (l.type == LightType::kDirectional) {
    toward = -glm::normalize(glm::dvec3(toGlm(l.direction)));
  } else {
    const glm::dvec3 v = glm::dvec3(toGlm(l.position)) - glm::dvec3(toGlm(p));
    const double d2 = std::max(glm::dot(v, v), 1e-12);
    toward = v / std::sqrt(d2);
    e /= d2;
    if (l.type == LightType::kSpot) {
      const double c = glm::dot(glm::normalize(glm::dvec3(toGlm(l.direction))), -toward);
      const double cos_outer = std::cos(double(l.outer_cone_rad)),
                   cos_inner = std::cos(double(l.inner_cone_rad));
      const double t =
          std::clamp((c - cos_outer) / std::max(cos_inner - cos_outer, 1e-6), 0.0, 1.0);
      e *= t * t;
    }
  }
  const double cos_theta = glm::dot(glm::dvec3(toGlm(n)), toward);
  if (!(cos_theta > 0)) return {};
  e *= cos_theta;
  return {float(e.x), float(e.y), float(e.z)};
}

float MaskedLightField::visibility(size_t k, uint32_t page, const Vec2& uv) const {
  if (page >= page_width_.size()) return 0.0f;
  const BakeMaskedLight& m = masks_->lights[k];
  const int width = int(page_width_[page]), height = int(page_height_[page]);
  const std::vector<uint16_t>& values = masks_->pages[page];
  const size_t texels = size_t(width) * size_t(height);
  const size_t layer = m.channel / 4, component = m.channel % 4;
  const auto at = [&](int x, int y) {
    x = std::clamp(x, 0, width - 1);
    y = std::clamp(y, 0, height - 1);
    const uint16_t v =
        values[(layer * texels + size_t(y) * size_t(width) + size_t(x)) * 4 + component];
    return (v >> 8) == m.owner ? float(v & 0xff) / 255.0f : 0.0f;
  };
  // Bilinear, as GL samples a texture: texel centres at (i + 0.5) / size.
  const float fx = uv.x * float(width) - 0.5f, fy = uv.y * float(height) - 0.5f;
  const int x0 = int(std::floor(fx)), y0 = int(std::floor(fy));
  const float ax = fx - float(x0), ay = fy - float(y0);
  return (at(x0, y0) * (1 - ax) + at(x0 + 1, y0) * ax) * (1 - ay) +
         (at(x0, y0 + 1) * (1 - ax) + at(x0 + 1, y0 + 1) * ax) * ay;
}

Rgb MaskedLightField::bakedIrradiance(const Vec3& p, const Vec3& n, uint32_t page,
                                      const Vec2& uv) const {
  Rgb sum{};
  for (size_t k = 0; k < lights_.size(); ++k) {
    const Rgb e = unshadowed(k, p, n);
    if (e.r <= 0 && e.g <= 0 && e.b <= 0) continue;
    const float v = visibility(k, page, uv);
    sum = {sum.r + e.r * v, sum.g + e.g * v, sum.b + e.b * v};
  }
  return sum;
}

}  // namespace svit
