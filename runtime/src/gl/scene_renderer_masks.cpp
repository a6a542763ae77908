#include "scene_renderer_masks.h"

#include <epoxy/gl.h>

#include "gl_program.h"

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

}  // namespace svit::gl
