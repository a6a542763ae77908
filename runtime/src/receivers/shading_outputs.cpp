#include "shading_outputs.h"

#include <epoxy/gl.h>

#include <algorithm>

#include "delta_atlas.h"

namespace svit::gl {
namespace {

glm::dvec3 dvec(const Rgb& c) { return {c.r, c.g, c.b}; }

double scaleOf(const DisplayInput& in, uint32_t receiver) {
  return receiver < in.light_scale->size() ? (*in.light_scale)[receiver] : 1.0;
}

GlTexture createPageTexture(GLenum format, int width, int height) {
  GlTexture texture = createGlTexture(GL_TEXTURE_2D);
  glTextureStorage2D(texture.id(), 1, format, width, height);
  glTextureParameteri(texture.id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTextureParameteri(texture.id(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTextureParameteri(texture.id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(texture.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  return texture;
}

template <typename T>
uint64_t vectorBytes(const std::vector<T>& v) {
  return uint64_t(v.capacity()) * sizeof(T);
}

}  // namespace

void ShadingOutputs::resize(size_t receivers) {
  delta_total.resize(receivers, glm::dvec3(0.0));
  runtime_direct.resize(receivers, glm::dvec3(0.0));
  masked_direct.resize(receivers, glm::dvec3(0.0));
  display.resize(receivers, Rgb{});
}

const std::vector<glm::dvec3>& ShadingOutputs::vertexDeltas(const RuntimePatches& patches) const {
  if (vertex_deltas_stale_) {
    std::vector<glm::dvec3> patch_part = delta_total;
    for (size_t r = 0; r < masked_direct.size(); ++r) patch_part[r] -= masked_direct[r];
    vertex_deltas_ = vertexValues(patches, patch_part);
    vertex_deltas_stale_ = false;
  }
  return vertex_deltas_;
}

std::vector<float> ShadingOutputs::packReceivers(const DisplayInput& in) {
  const size_t n = delta_total.size();
  std::vector<float> packed(n * 4, 0.0f);
  for (size_t r = 0; r < n; ++r) {
    const glm::dvec3 target = delta_total[r] - runtime_direct[r];
    Rgb& d = display[r];
    const float blend = in.temporal_blend;
    d = {d.r + blend * (float(target.x) - d.r), d.g + blend * (float(target.y) - d.g),
         d.b + blend * (float(target.z) - d.b)};
    packed[r * 4] = d.r;
    packed[r * 4 + 1] = d.g;
    packed[r * 4 + 2] = d.b;
    packed[r * 4 + 3] = r < in.static_receivers ? float(scaleOf(in, uint32_t(r)) - 1.0) : 0.0f;
  }
  // A dynamic receiver's w says whether its object is lit: shading keeps
  // the probes' light for one that is not (Runtime::Impl::updateObjectsLit).
  for (const DynamicObject& object : *in.objects) {
    const size_t end = std::min(n, size_t(object.first_receiver) + object.albedo.size());
    for (size_t r = object.first_receiver; r < end; ++r)
      packed[r * 4 + 3] = object.lit ? 1.0f : 0.0f;
  }
  return packed;
}

uint32_t ShadingOutputs::uploadPatchBuffer(const std::vector<float>& packed, size_t receivers) {
  uint32_t created = 0;
  if (delta_buffer_receivers_ < receivers) {
    // Grows only when objects are added; a steady scene never allocates.
    delta_buffer_.reset();
    delta_buffer_ = createGlBuffer();
    glNamedBufferStorage(delta_buffer_.id(), GLsizeiptr(receivers * 4 * sizeof(float)), nullptr,
                         GL_DYNAMIC_STORAGE_BIT);
    delta_buffer_receivers_ = uint32_t(receivers);
    ++created;
  }
  glNamedBufferSubData(delta_buffer_.id(), 0, GLsizeiptr(receivers * 4 * sizeof(float)),
                       packed.data());
  return created;
}

uint32_t ShadingOutputs::uploadDeltaTextures(const DisplayInput& in,
                                             const std::vector<glm::dvec3>& shown,
                                             const std::vector<glm::dvec3>& scales) {
  std::vector<std::pair<int, int>> sizes;
  for (const LightmapImage& page : *in.pages) sizes.push_back({page.width, page.height});
  const std::vector<DeltaPage> atlas = rasteriseDeltas(*in.patches, shown, scales, sizes);
  uint32_t created = 0;
  if (delta_textures_.empty()) {
    for (const DeltaPage& page : atlas)
      delta_textures_.push_back(createPageTexture(GL_RGBA32F, page.width, page.height));
    created += uint32_t(atlas.size());
  }
  for (size_t p = 0; p < atlas.size(); ++p) {
    glTextureSubImage2D(delta_textures_[p].id(), 0, 0, 0, atlas[p].width, atlas[p].height, GL_RGBA,
                        GL_FLOAT, atlas[p].rgba.data());
  }
  return created;
}

uint32_t ShadingOutputs::upload(const DisplayInput& in) {
  const std::vector<float> packed = packReceivers(in);
  uint32_t created = uploadPatchBuffer(packed, delta_total.size());
  // The static deltas and light scales at the welded vertices of the
  // runtime patches, as shading interpolates them per pixel.
  std::vector<glm::dvec3> shown(in.static_receivers), scale(in.static_receivers);
  for (uint32_t r = 0; r < in.static_receivers; ++r) {
    shown[r] = dvec(display[r]);
    scale[r] = glm::dvec3(scaleOf(in, r) - 1.0);
  }
  const std::vector<glm::dvec3> shown_at_vertices = vertexValues(*in.patches, shown);
  // Empty while every baked emitter is as baked (a factor of 1 everywhere).
  vertex_scales_ =
      in.light_scale->empty() ? std::vector<glm::dvec3>{} : vertexValues(*in.patches, scale);
  if (!delta_surface_.allocated()) {
    delta_surface_ = DeltaSurfaceBuffers::create(*in.patches);
    created += 3;
  }
  delta_surface_.upload(shown_at_vertices, vertex_scales_);
  if (in.delta_textures) created += uploadDeltaTextures(in, shown_at_vertices, vertex_scales_);
  return created;
}

std::vector<uint32_t> ShadingOutputs::lightmapTextures(
    const std::vector<LightmapImage>& pages) const {
  if (lightmap_textures_.empty()) {
    for (const LightmapImage& page : pages) {
      GlTexture texture = createPageTexture(GL_RGB32F, page.width, page.height);
      glTextureSubImage2D(texture.id(), 0, 0, 0, page.width, page.height, GL_RGB, GL_FLOAT,
                          page.rgb.data());
      lightmap_textures_.push_back(std::move(texture));
    }
  }
  return ids(lightmap_textures_);
}

uint64_t ShadingOutputs::hostBytes() const {
  return vectorBytes(delta_total) + vectorBytes(runtime_direct) + vectorBytes(masked_direct) +
         vectorBytes(display) + vectorBytes(vertex_deltas_);
}

std::vector<uint32_t> ShadingOutputs::ids(const std::vector<GlTexture>& textures) {
  std::vector<uint32_t> out;
  for (const GlTexture& t : textures) out.push_back(t.id());
  return out;
}

std::vector<GlObject> ShadingOutputs::textureObjects(const std::vector<GlTexture>& textures) {
  std::vector<GlObject> out;
  for (const GlTexture& t : textures) out.push_back(glTextureObject(t.id()));
  return out;
}

}  // namespace svit::gl
