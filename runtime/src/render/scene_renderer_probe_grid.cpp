#include "scene_renderer_probe_grid.h"

#include <epoxy/gl.h>

#include <string>
#include <utility>
#include <vector>

#include "scene_renderer_bindings.h"

namespace svit::gl {

Expected<ProbeGridTextures> ProbeGridTextures::create(const BakeProbeGrid& grid) {
  ProbeGridTextures out;
  const size_t probes = size_t(grid.dims[0]) * grid.dims[1] * grid.dims[2];
  if (probes == 0) return out;
  if (grid.sh.size() < probes * 12) {
    return Status(StatusCode::kInvalidInput, "bake probe grid: " + std::to_string(grid.sh.size()) +
                                                 " SH floats for " + std::to_string(probes) +
                                                 " probes (12 each)");
  }
  out.layout_.origin = grid.origin;
  out.layout_.spacing = grid.spacing;
  for (int a = 0; a < 3; ++a) out.layout_.dims[a] = grid.dims[a];
  std::vector<float> channel(probes * 4);
  for (int c = 0; c < 3; ++c) {
    // sh per probe: coefficient-major, RGB inside (bake_file.h).
    for (size_t p = 0; p < probes; ++p) {
      for (int k = 0; k < 4; ++k)
        channel[p * 4 + size_t(k)] = grid.sh[p * 12 + size_t(k) * 3 + size_t(c)];
    }
    out.textures_[c] = createGlTexture(GL_TEXTURE_3D);
    const GLuint texture = out.textures_[c].id();
    glTextureStorage3D(texture, 1, GL_RGBA32F, GLsizei(grid.dims[0]), GLsizei(grid.dims[1]),
                       GLsizei(grid.dims[2]));
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTextureSubImage3D(texture, 0, 0, 0, 0, GLsizei(grid.dims[0]), GLsizei(grid.dims[1]),
                        GLsizei(grid.dims[2]), GL_RGBA, GL_FLOAT, channel.data());
    glTextureParameteri(texture, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTextureParameteri(texture, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    for (GLenum wrap : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T, GL_TEXTURE_WRAP_R}) {
      glTextureParameteri(texture, wrap, GL_CLAMP_TO_EDGE);
    }
  }
  return out;
}

ProbeGridTextures::ProbeGridTextures(ProbeGridTextures&& other) noexcept = default;
ProbeGridTextures& ProbeGridTextures::operator=(ProbeGridTextures&& other) noexcept = default;
ProbeGridTextures::~ProbeGridTextures() = default;

void ProbeGridTextures::bind() const {
  namespace b = render_binding;
  glUniform1i(b::kUseProbes, empty() ? 0 : 1);
  glUniform3f(b::kProbeOrigin, layout_.origin.x, layout_.origin.y, layout_.origin.z);
  glUniform3f(b::kProbeSpacing, layout_.spacing.x, layout_.spacing.y, layout_.spacing.z);
  glUniform3f(b::kProbeDims, float(layout_.dims[0]), float(layout_.dims[1]),
              float(layout_.dims[2]));
  if (empty()) return;
  glBindTextureUnit(b::kProbeUnitR, textures_[0].id());
  glBindTextureUnit(b::kProbeUnitG, textures_[1].id());
  glBindTextureUnit(b::kProbeUnitB, textures_[2].id());
}

}  // namespace svit::gl
