#include "scene_renderer_materials.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <string>
#include <utility>

#include "gl/gl_program.h"
#include "scene_renderer_bindings.h"

namespace svit::gl {
namespace {

GLint glWrap(WrapMode mode) {
  switch (mode) {
    case WrapMode::kClampToEdge: return GL_CLAMP_TO_EDGE;
    case WrapMode::kMirroredRepeat: return GL_MIRRORED_REPEAT;
    case WrapMode::kRepeat: break;
  }
  return GL_REPEAT;
}

int mipLevels(int width, int height) {
  int levels = 1;
  while ((std::max(width, height) >> levels) > 0) ++levels;
  return levels;
}

bool usable(const Scene& scene, const TextureRef& ref) {
  return ref.texture >= 0 && size_t(ref.texture) < scene.textures.size();
}

void setTextureUniforms(const TextureRef& ref, bool present, int texture_location,
                        int transform_location, int rotation_location) {
  glUniform2i(texture_location, present ? 1 : 0, ref.texcoord);
  glUniform4f(transform_location, ref.scale.x, ref.scale.y, ref.offset.x, ref.offset.y);
  glUniform1f(rotation_location, ref.rotation_rad);
}

}  // namespace

Expected<MaterialTextures> MaterialTextures::create(const Scene& scene) {
  MaterialTextures out;
  out.textures_.resize(scene.textures.size());
  std::vector<uint8_t> used(scene.textures.size(), 0);
  for (const Material& m : scene.materials) {
    if (usable(scene, m.base_color_texture)) used[size_t(m.base_color_texture.texture)] = 1;
    if (usable(scene, m.emissive_texture)) used[size_t(m.emissive_texture.texture)] = 1;
  }
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
  std::vector<uint8_t> rgba;
  for (size_t i = 0; i < scene.textures.size(); ++i) {
    const Texture& t = scene.textures[i];
    if (!used[i] || t.width <= 0 || t.height <= 0) continue;
    const size_t texels = size_t(t.width) * size_t(t.height);
    if (t.channels < 1 || t.channels > 4 || t.texels.size() != texels * size_t(t.channels)) {
      return Status(StatusCode::kInvalidInput,
                    "texture '" + t.name + "': " + std::to_string(t.texels.size()) + " bytes for " +
                        std::to_string(t.width) + "x" + std::to_string(t.height) + "x" +
                        std::to_string(t.channels));
    }
    // Expand to RGBA: grey replicates, alpha 1 where absent (as
    // texture_sampling.cpp reads them for the baker).
    rgba.resize(texels * 4);
    for (size_t p = 0; p < texels; ++p) {
      const uint8_t* s = &t.texels[p * size_t(t.channels)];
      uint8_t* d = &rgba[p * 4];
      const bool grey = t.channels <= 2;
      d[0] = s[0];
      d[1] = grey ? s[0] : s[1];
      d[2] = grey ? s[0] : s[2];
      d[3] = t.channels == 2 ? s[1] : t.channels == 4 ? s[3] : 255;
    }
    out.textures_[i] = createGlTexture(GL_TEXTURE_2D);
    const GLuint texture = out.textures_[i].id();
    glTextureStorage2D(texture, mipLevels(t.width, t.height), GL_SRGB8_ALPHA8, t.width, t.height);
    // glTF's first row is v = 0, GL's first row is t = 0: UVs address it as is.
    glTextureSubImage2D(texture, 0, 0, 0, t.width, t.height, GL_RGBA, GL_UNSIGNED_BYTE,
                        rgba.data());
    glGenerateTextureMipmap(texture);
    glTextureParameteri(texture, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTextureParameteri(texture, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(texture, GL_TEXTURE_WRAP_S, glWrap(t.wrap_s));
    glTextureParameteri(texture, GL_TEXTURE_WRAP_T, glWrap(t.wrap_t));
  }
  const uint8_t white[4] = {255, 255, 255, 255};
  out.white_ = createGlTexture(GL_TEXTURE_2D);
  glTextureStorage2D(out.white_.id(), 1, GL_SRGB8_ALPHA8, 1, 1);
  glTextureSubImage2D(out.white_.id(), 0, 0, 0, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, white);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  Status error = checkGlError("uploading material textures");
  if (!error.ok()) return error;
  return out;
}

MaterialTextures::MaterialTextures(MaterialTextures&& other) noexcept = default;
MaterialTextures& MaterialTextures::operator=(MaterialTextures&& other) noexcept = default;
MaterialTextures::~MaterialTextures() = default;

void MaterialTextures::bind(const Material& m) const {
  namespace b = render_binding;
  auto textureOf = [&](const TextureRef& ref) -> uint32_t {
    return ref.texture >= 0 && size_t(ref.texture) < textures_.size()
               ? textures_[size_t(ref.texture)].id()
               : 0;
  };
  const uint32_t base = textureOf(m.base_color_texture), emissive = textureOf(m.emissive_texture);
  glBindTextureUnit(b::kBaseColorUnit, base != 0 ? base : white_.id());
  glBindTextureUnit(b::kEmissiveUnit, emissive != 0 ? emissive : white_.id());
  glUniform4f(b::kBaseColor, m.base_color.r, m.base_color.g, m.base_color.b, m.base_alpha);
  glUniform3f(b::kEmissive, m.emissive_luminance.r, m.emissive_luminance.g, m.emissive_luminance.b);
  setTextureUniforms(m.base_color_texture, base != 0, b::kBaseTexture, b::kBaseTransform,
                     b::kBaseRotation);
  setTextureUniforms(m.emissive_texture, emissive != 0, b::kEmissiveTexture, b::kEmissiveTransform,
                     b::kEmissiveRotation);
  glUniform2i(b::kMaterialFlags, m.double_sided ? 1 : 0, m.alpha_mode == AlphaMode::kMask ? 1 : 0);
  glUniform1f(b::kAlphaCutoff, m.alpha_cutoff);
}

std::vector<GlObject> MaterialTextures::glObjects() const {
  std::vector<GlObject> out = {glTextureObject(white_.id())};
  for (const GlTexture& t : textures_) out.push_back(glTextureObject(t.id()));
  return out;
}

size_t MaterialTextures::skippedCount() const {
  size_t skipped = 0;
  for (const GlTexture& t : textures_) skipped += !t ? 1 : 0;
  return skipped;
}

}  // namespace svit::gl
