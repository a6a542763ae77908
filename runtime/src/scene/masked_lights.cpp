#include "svit/masked_lights.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "glm_interop.h"
#include "polygon_irradiance.h"

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

glm::dvec3 dvec(const Vec3& v) { return {v.x, v.y, v.z}; }

Rgb triangleEmission(const Scene& scene, const BakeData& bake, uint32_t triangle) {
  const BakeTriangleUv& t = bake.triangle_uvs[triangle];
  const Mesh& mesh = scene.meshes[size_t(scene.instances[t.instance].mesh)];
  return t.mesh_triangle < mesh.triangle_emission.size() ? mesh.triangle_emission[t.mesh_triangle]
                                                         : Rgb{};
}

// The emissive sides among a patch's elements (triangle * 2 + side), wound
// to face their emitting side.
std::vector<MaskedAreaElement> areaElementsOf(const Scene& scene, const BakeData& bake,
                                              const BakedSurfaces& surfaces,
                                              const BakePatch& patch) {
  std::vector<MaskedAreaElement> out;
  for (uint32_t i = 0; i < patch.element_count; ++i) {
    const uint32_t element = bake.patch_elements[patch.first_element + i];
    const uint32_t t = element / 2;
    const Rgb l = triangleEmission(scene, bake, t);
    if (!(l.r > 0 || l.g > 0 || l.b > 0)) continue;
    const bool back = element % 2 == 1;
    MaskedAreaElement e;
    e.corner[0] = surfaces.corner(t, 0);
    e.corner[1] = surfaces.corner(t, back ? 2 : 1);
    e.corner[2] = surfaces.corner(t, back ? 1 : 2);
    const Vec3& n = surfaces.normal(t);
    e.normal = back ? Vec3{-n.x, -n.y, -n.z} : n;
    e.area_m2 = surfaces.area(t);
    e.luminance = l;
    out.push_back(e);
  }
  return out;
}

// An area light as a point light at its elements' area-weighted centre
// (what towardLight and distanceToLight aim at).
Light areaAsLight(const std::vector<MaskedAreaElement>& elements, uint32_t patch) {
  glm::dvec3 centre(0.0);
  double area = 0;
  for (const MaskedAreaElement& e : elements) {
    centre += (dvec(e.corner[0]) + dvec(e.corner[1]) + dvec(e.corner[2])) * (e.area_m2 / 3.0);
    area += e.area_m2;
  }
  Light l;
  l.name = "emissive patch " + std::to_string(patch);
  l.position = fromGlm(glm::vec3(area > 0 ? centre / area : centre));
  l.intensity = 0;  // its light is its elements'
  return l;
}

}  // namespace

Expected<MaskedLightField> MaskedLightField::create(const Scene& scene, const BakeData& bake,
                                                    const BakedSurfaces& surfaces) {
  MaskedLightField field;
  if (bake.masks.lights.empty()) return field;
  field.masks_ = std::make_shared<const BakeShadowMasks>(bake.masks);
  for (const BakeLightmapPage& page : bake.pages) {
    field.page_width_.push_back(page.width);
    field.page_height_.push_back(page.height);
  }
  for (const BakeMaskedLight& m : bake.masks.lights) {
    const BakeEmitter& e = bake.emitters[m.emitter];  // validated: in range, a light or the sun
    std::vector<MaskedAreaElement> area;
    if (e.kind == BakeEmitter::Kind::kPatch) {
      // validated: the patch is in range
      if (surfaces.triangleCount() == bake.triangle_uvs.size())
        area = areaElementsOf(scene, bake, surfaces, bake.patches[e.index]);
      if (area.empty()) {
        return Status(StatusCode::kInvalidInput,
                      "bake.svit: section SMSK masks emitter " + std::to_string(m.emitter) +
                          ", patch " + std::to_string(e.index) +
                          ", which has no emissive triangle in the level");
      }
      field.lights_.push_back(areaAsLight(area, e.index));
    } else if (e.kind == BakeEmitter::Kind::kSun) {
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
    field.areas_.push_back(std::move(area));
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

uint32_t MaskedLightField::areaSampleCount(size_t k, const Vec3& at) const {
  double solid_angle = 0;
  for (const MaskedAreaElement& e : areas_[k]) {
    const glm::dvec3 centre = (dvec(e.corner[0]) + dvec(e.corner[1]) + dvec(e.corner[2])) / 3.0;
    const glm::dvec3 v = dvec(at) - centre;
    const double d2 = std::max(glm::dot(v, v), 1e-12);
    solid_angle += e.area_m2 * std::abs(glm::dot(dvec(e.normal), v)) / (d2 * std::sqrt(d2));
  }
  const double samples =
      std::ceil(std::min(solid_angle, 2.0 * 3.14159265358979) / kAreaSampleSolidAngleSr);
  return uint32_t(std::clamp(samples, 1.0, double(kMaxAreaSamples)));
}

std::vector<MaskedAreaSample> MaskedLightField::areaSamples(size_t k, uint32_t count) const {
  const std::vector<MaskedAreaElement>& elements = areas_[k];
  std::vector<double> cdf;
  double total = 0;
  for (const MaskedAreaElement& e : elements) cdf.push_back(total += e.area_m2);
  std::vector<MaskedAreaSample> out;
  for (uint32_t s = 0; s < count && total > 0; ++s) {
    const double pick = (double(s) + 0.5) / double(count) * total;
    const size_t i = std::min(elements.size() - 1,
                              size_t(std::lower_bound(cdf.begin(), cdf.end(), pick) - cdf.begin()));
    const double low = i > 0 ? cdf[i - 1] : 0.0;
    const double r1 = std::clamp((pick - low) / std::max(cdf[i] - low, 1e-30), 0.0, 1.0);
    const double r2 = std::fmod(double(s) * 0.6180339887498949 + 0.5, 1.0);  // rank-1 lattice
    const double root = std::sqrt(r1);  // uniform on the triangle
    const MaskedAreaElement& e = elements[i];
    const glm::dvec3 point = dvec(e.corner[0]) * (1.0 - root) +
                             dvec(e.corner[1]) * (root * (1.0 - r2)) +
                             dvec(e.corner[2]) * (root * r2);
    out.push_back({fromGlm(glm::vec3(point)), e.normal});
  }
  return out;
}

namespace {

// An area light: each element in front of whose emitting side `p` lies
// gives its luminance x the cosine-weighted solid angle it subtends.
Rgb areaIrradiance(const std::vector<MaskedAreaElement>& elements, const Vec3& p, const Vec3& n) {
  glm::dvec3 e(0.0);
  for (const MaskedAreaElement& element : elements) {
    if (!(glm::dot(dvec(p) - dvec(element.corner[0]), dvec(element.normal)) > 0)) continue;
    const double f =
        triangleCosineSolidAngle(dvec(element.corner[0]), dvec(element.corner[1]),
                                 dvec(element.corner[2]), dvec(p), glm::normalize(dvec(n)));
    e += glm::dvec3(element.luminance.r, element.luminance.g, element.luminance.b) * f;
  }
  return {float(e.x), float(e.y), float(e.z)};
}

}  // namespace

Rgb MaskedLightField::unshadowed(size_t k, const Vec3& p, const Vec3& n) const {
  if (isArea(k)) return areaIrradiance(areas_[k], p, n);
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
