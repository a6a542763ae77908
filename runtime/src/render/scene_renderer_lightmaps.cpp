#include "scene_renderer_lightmaps.h"

#include <epoxy/gl.h>

#include <cmath>
#include <filesystem>
#include <utility>

#include "gl/gl_program.h"
#include "scene/numeric.h"
#include "svit/lightmap_image.h"

namespace svit::gl {
namespace {

// Running log-average of texel luminance (lux) over lit texels.
struct LogMean {
  double log_sum = 0;
  size_t lit = 0;
  void add(const std::vector<float>& rgb) {
    for (size_t i = 0; i + 2 < rgb.size(); i += 3) {
      const double y = luminanceOf(Rgb{rgb[i], rgb[i + 1], rgb[i + 2]});
      if (y > 0 && std::isfinite(y)) {
        log_sum += std::log(y);
        ++lit;
      }
    }
  }
  double value() const { return lit > 0 ? std::exp(log_sum / double(lit)) : 0.0; }
};

}  // namespace

Expected<LightmapTextures> LightmapTextures::borrow(const BakeData& bake,
                                                    const std::vector<uint32_t>& textures) {
  if (textures.size() != bake.pages.size()) {
    return Status(StatusCode::kInvalidInput,
                  "runtime lightmap textures: " + std::to_string(textures.size()) + " for " +
                      std::to_string(bake.pages.size()) + " bake pages");
  }
  LightmapTextures out;
  out.owned_ = false;
  out.textures_ = textures;
  LogMean mean;
  std::vector<float> rgb;
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  for (size_t i = 0; i < textures.size(); ++i) {
    const BakeLightmapPage& page = bake.pages[i];
    rgb.resize(size_t(page.width) * page.height * 3);
    glGetTextureImage(textures[i], 0, GL_RGB, GL_FLOAT, GLsizei(rgb.size() * sizeof(float)),
                      rgb.data());
    mean.add(rgb);
  }
  out.log_mean_lux_ = mean.value();
  Status error = checkGlError("reading the runtime's lightmap textures");
  if (!error.ok()) return error;
  return out;
}

Expected<LightmapTextures> LightmapTextures::create(const BakeData& bake,
                                                    const std::string& bake_dir) {
  LightmapTextures out;
  LogMean mean;
  for (const BakeLightmapPage& page : bake.pages) {
    const std::string path = (std::filesystem::path(bake_dir) / page.file).string();
    if (!std::filesystem::exists(path)) {
      return Status(StatusCode::kNotFound,
                    path + ": lightmap page is missing (bake.svit lists it)");
    }
    Expected<LightmapImage> image = readLightmapExr(path);
    if (!image.ok()) {
      // Name the page even when the reader's message does not.
      const std::string& message = image.status().message();
      return Status(image.status().code(),
                    message.find(page.file) == std::string::npos ? path + ": " + message : message);
    }
    if (uint32_t(image->width) != page.width || uint32_t(image->height) != page.height) {
      return Status(StatusCode::kInvalidInput,
                    path + ": lightmap page is " + std::to_string(image->width) + "x" +
                        std::to_string(image->height) + ", bake.svit says " +
                        std::to_string(page.width) + "x" + std::to_string(page.height));
    }
    mean.add(image->rgb);
    // owned from here: released on error
    out.owned_textures_.push_back(createGlTexture(GL_TEXTURE_2D));
    const GLuint texture = out.owned_textures_.back().id();
    out.textures_.push_back(texture);
    glTextureStorage2D(texture, 1, GL_RGB32F, image->width, image->height);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
    // Row 0 of the EXR is v in [0, 1/height): GL's first row is t = 0, so the
    // bake's UVs address the texture directly.
    glTextureSubImage2D(texture, 0, 0, 0, image->width, image->height, GL_RGB, GL_FLOAT,
                        image->rgb.data());
    glTextureParameteri(texture, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTextureParameteri(texture, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(texture, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(texture, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    Status error = checkGlError(("uploading lightmap " + path).c_str());
    if (!error.ok()) return error;
  }
  out.log_mean_lux_ = mean.value();
  return out;
}

LightmapTextures::LightmapTextures(LightmapTextures&& other) noexcept { *this = std::move(other); }

LightmapTextures& LightmapTextures::operator=(LightmapTextures&& other) noexcept {
  if (this != &other) {
    owned_textures_ = std::exchange(other.owned_textures_, {});
    textures_ = std::exchange(other.textures_, {});
    owned_ = other.owned_;
    log_mean_lux_ = other.log_mean_lux_;
  }
  return *this;
}

LightmapTextures::~LightmapTextures() = default;

std::vector<GlObject> LightmapTextures::glObjects() const {
  std::vector<GlObject> out;
  if (owned_) {
    for (uint32_t t : textures_) out.push_back(glTextureObject(t));
  }
  return out;
}

}  // namespace svit::gl
