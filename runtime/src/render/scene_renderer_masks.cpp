#include "scene_renderer_masks.h"

#include <epoxy/gl.h>

#include <cmath>

#include "gl/gl_program.h"
#include "scene/numeric.h"
#include "scene_renderer_bindings.h"
#include "svit/baked_surfaces.h"
#include "svit/masked_lights.h"

namespace svit::gl {

Expected<ShadowMaskTextures> ShadowMaskTextures::create(const BakeData& bake) {
  ShadowMaskTextures out;
  const BakeShadowMasks& masks = bake.masks;
  if (masks.lights.empty()) return out;
  const GLsizei layers = GLsizei(masks.layers());
  for (size_t p = 0; p < bake.pages.size(); ++p) {
    const GLsizei width = GLsizei(bake.pages[p].width), height = GLsizei(bake.pages[p].height);
    GlTexture texture = createGlTexture(GL_TEXTURE_2D_ARRAY);
    glTextureStorage3D(texture.id(), 1, GL_RGBA16UI, width, height, layers);
    glTextureParameteri(texture.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(texture.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage3D(texture.id(), 0, 0, 0, 0, width, height, layers, GL_RGBA_INTEGER,
                        GL_UNSIGNED_SHORT, masks.pages[p].data());
    out.textures_.push_back(std::move(texture));
  }
  Status error = checkGlError("shadow mask textures");
  if (!error.ok()) return error;
  return out;
}

std::vector<GlObject> ShadowMaskTextures::glObjects() const {
  std::vector<GlObject> out;
  for (const GlTexture& t : textures_) out.push_back(glTextureObject(t.id()));
  return out;
}

namespace {

double exposureRatio(const BakeData& bake, const BakedSurfaces& surfaces,
                     const MaskedLightField& masked, const std::vector<LightmapImage>& pages) {
  double log_with = 0, log_without = 0, area = 0;
  for (size_t t = 0; t < surfaces.triangleCount(); ++t) {
    const BakeTriangleUv& uv = bake.triangle_uvs[t];
    const Vec2 centre{(uv.uv[0].x + uv.uv[1].x + uv.uv[2].x) / 3,
                      (uv.uv[0].y + uv.uv[1].y + uv.uv[2].y) / 3};
    Vec3 p{0, 0, 0};
    for (int k = 0; k < 3; ++k) {
      const Vec3& c = surfaces.corner(t, k);
      p = {p.x + c.x / 3, p.y + c.y / 3, p.z + c.z / 3};
    }
    const double lightmap = luminanceOf(pages[uv.page].sampleBilinear(centre));
    const double direct =
        luminanceOf(masked.bakedIrradiance(p, surfaces.normal(t), uv.page, centre));
    if (!(lightmap > 0) || !(lightmap + direct > 0)) continue;
    const double a = surfaces.area(t);
    log_with += a * std::log(lightmap + direct);
    log_without += a * std::log(lightmap);
    area += a;
  }
  return area > 0 ? std::exp((log_with - log_without) / area) : 1.0;
}

}  // namespace

Expected<MaskedShading> prepareMaskedShading(const Scene& scene, const BakeData& bake,
                                             const std::string& bake_dir) {
  MaskedShading out;
  if (bake.masks.lights.empty()) return out;
  Expected<BakedSurfaces> surfaces = BakedSurfaces::build(scene, bake);
  if (!surfaces.ok()) return surfaces.status();
  Expected<MaskedLightField> masked = MaskedLightField::create(scene, bake, *surfaces);
  if (!masked.ok()) return masked.status();
  Expected<std::vector<LightmapImage>> pages = readLightmapPages(bake, bake_dir);
  if (!pages.ok()) return pages.status();
  out.exposure_ratio = exposureRatio(bake, *surfaces, *masked, *pages);
  out.field = std::move(masked).value();
  return out;
}

AreaLightBuffer AreaLightBuffer::create(const MaskedLightField& field) {
  AreaLightBuffer out;
  std::vector<float> data;
  const auto push = [&](float x, float y, float z, float w) {
    data.insert(data.end(), {x, y, z, w});
  };
  for (size_t k = 0; k < field.lightCount(); ++k) {
    out.offsets_.push_back(uint32_t(data.size() / 4));
    if (!field.isArea(k)) continue;
    const std::vector<MaskedAreaElement>& elements = field.areaElements(k);
    push(float(elements.size()), 0, 0, 0);
    for (const MaskedAreaElement& e : elements) {
      for (const Vec3& c : e.corner) push(c.x, c.y, c.z, 1);
      push(e.luminance.r, e.luminance.g, e.luminance.b, 0);
    }
  }
  if (data.empty()) return out;
  out.buffer_ = createGlBuffer();
  glNamedBufferStorage(out.buffer_.id(), GLsizeiptr(data.size() * sizeof(float)), data.data(), 0);
  return out;
}

void AreaLightBuffer::bind() const {
  if (buffer_.id() != 0)
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, render_binding::kAreaLights, buffer_.id());
}

std::vector<GlObject> AreaLightBuffer::glObjects() const {
  if (buffer_.id() == 0) return {};
  return {glBufferObject(buffer_.id())};
}

}  // namespace svit::gl
