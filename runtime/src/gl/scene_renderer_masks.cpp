#include "scene_renderer_masks.h"

#include <epoxy/gl.h>

#include <cmath>

#include "gl_program.h"
#include "numeric.h"
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

Expected<double> maskedExposureRatio(const Scene& scene, const BakeData& bake,
                                     const std::string& bake_dir) {
  if (bake.masks.lights.empty()) return 1.0;
  Expected<BakedSurfaces> surfaces = BakedSurfaces::build(scene, bake);
  if (!surfaces.ok()) return surfaces.status();
  Expected<MaskedLightField> masked = MaskedLightField::create(scene, bake);
  if (!masked.ok()) return masked.status();
  Expected<std::vector<LightmapImage>> pages = readLightmapPages(bake, bake_dir);
  if (!pages.ok()) return pages.status();
  double log_with = 0, log_without = 0, area = 0;
  for (size_t t = 0; t < surfaces->triangleCount(); ++t) {
    const BakeTriangleUv& uv = bake.triangle_uvs[t];
    const Vec2 centre{(uv.uv[0].x + uv.uv[1].x + uv.uv[2].x) / 3,
                      (uv.uv[0].y + uv.uv[1].y + uv.uv[2].y) / 3};
    Vec3 p{0, 0, 0};
    for (int k = 0; k < 3; ++k) {
      const Vec3& c = surfaces->corner(t, k);
      p = {p.x + c.x / 3, p.y + c.y / 3, p.z + c.z / 3};
    }
    const double lightmap = luminanceOf((*pages)[uv.page].sampleBilinear(centre));
    const double direct =
        luminanceOf(masked->bakedIrradiance(p, surfaces->normal(t), uv.page, centre));
    if (!(lightmap > 0) || !(lightmap + direct > 0)) continue;
    const double a = surfaces->area(t);
    log_with += a * std::log(lightmap + direct);
    log_without += a * std::log(lightmap);
    area += a;
  }
  return area > 0 ? std::exp((log_with - log_without) / area) : 1.0;
}

}  // namespace svit::gl
