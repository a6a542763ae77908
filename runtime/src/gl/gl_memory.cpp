#include "gl_memory.h"

#include <epoxy/gl.h>

#include <utility>

namespace svit::gl {
namespace {

/// Bits per texel of a texture level or a renderbuffer, from the sizes GL
/// reports per component (works for every uncompressed internal format).
template <typename Query>
uint64_t bitsPerTexel(Query query) {
  const GLenum components[] = {GL_TEXTURE_RED_SIZE,   GL_TEXTURE_GREEN_SIZE,
                               GL_TEXTURE_BLUE_SIZE,  GL_TEXTURE_ALPHA_SIZE,
                               GL_TEXTURE_DEPTH_SIZE, GL_TEXTURE_STENCIL_SIZE};
  uint64_t bits = 0;
  for (GLenum c : components) bits += uint64_t(query(c));
  return bits;
}

uint64_t textureBytes(GLuint texture) {
  GLint target = 0, levels = 0;
  glGetTextureParameteriv(texture, GL_TEXTURE_TARGET, &target);
  glGetTextureParameteriv(texture, GL_TEXTURE_IMMUTABLE_LEVELS, &levels);
  // Cube maps report one face per level; every other target reports its
  // layers as depth.
  const uint64_t faces = target == GL_TEXTURE_CUBE_MAP ? 6 : 1;
  uint64_t bytes = 0;
  for (GLint level = 0; level < (levels > 0 ? levels : 1); ++level) {
    auto query = [&](GLenum pname) {
      GLint v = 0;
      glGetTextureLevelParameteriv(texture, level, pname, &v);
      return v;
    };
    const uint64_t texels = uint64_t(query(GL_TEXTURE_WIDTH)) * uint64_t(query(GL_TEXTURE_HEIGHT)) *
                            uint64_t(query(GL_TEXTURE_DEPTH)) * faces;
    if (query(GL_TEXTURE_COMPRESSED) == GL_TRUE) {
      bytes += uint64_t(query(GL_TEXTURE_COMPRESSED_IMAGE_SIZE)) * faces;
    } else {
      bytes += texels * bitsPerTexel(query) / 8;
    }
  }
  return bytes;
}

uint64_t renderbufferBytes(GLuint renderbuffer) {
  auto query = [&](GLenum pname) {
    GLint v = 0;
    glGetNamedRenderbufferParameteriv(renderbuffer, pname, &v);
    return v;
  };
  const GLenum components[] = {GL_RENDERBUFFER_RED_SIZE,   GL_RENDERBUFFER_GREEN_SIZE,
                               GL_RENDERBUFFER_BLUE_SIZE,  GL_RENDERBUFFER_ALPHA_SIZE,
                               GL_RENDERBUFFER_DEPTH_SIZE, GL_RENDERBUFFER_STENCIL_SIZE};
  uint64_t bits = 0;
  for (GLenum c : components) bits += uint64_t(query(c));
  const GLint samples = query(GL_RENDERBUFFER_SAMPLES);
  return uint64_t(query(GL_RENDERBUFFER_WIDTH)) * uint64_t(query(GL_RENDERBUFFER_HEIGHT)) * bits /
         8 * uint64_t(samples > 0 ? samples : 1);
}

}  // namespace

uint64_t glObjectBytes(const GlObject& object) {
  if (object.name == 0) return 0;
  switch (object.kind) {
    case GlObject::Kind::kBuffer: {
      GLint64 size = 0;
      glGetNamedBufferParameteri64v(object.name, GL_BUFFER_SIZE, &size);
      return size > 0 ? uint64_t(size) : 0;
    }
    case GlObject::Kind::kTexture: return textureBytes(object.name);
    case GlObject::Kind::kRenderbuffer: return renderbufferBytes(object.name);
  }
  return 0;
}

GlFootprint glFootprint(std::span<const GlObject> objects) {
  GlFootprint out;
  for (const GlObject& o : objects) {
    if (o.name == 0) continue;
    ++out.objects;
    out.bytes += glObjectBytes(o);
  }
  return out;
}

ResourceUse measuredUse(std::string name, const std::vector<GlObject>& objects) {
  const GlFootprint footprint = glFootprint(objects);
  ResourceUse use;
  use.name = std::move(name);
  use.allocated = footprint.objects > 0;
  use.gl_objects = footprint.objects;
  use.gpu_bytes = footprint.bytes;
  return use;
}

}  // namespace svit::gl
