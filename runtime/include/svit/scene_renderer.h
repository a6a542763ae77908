#pragma once
// svit::SceneRenderer — draws a level the way svit means it to be shaded:
// baked lightmaps plus the runtime's interpolated per-patch deltas on static
// geometry, per-pixel runtime lights with soft (multi-tap) shadows, and
// dynamic objects lit per pixel and by the bake's probe grid corrected by
// the runtime's patch irradiance. The GLSL lives in shaders/ (see
// shadingSource()); an engine with its own renderer uses those files and
// Runtime::shadingResources() instead of this class. svit-walk and the tests
// draw with it.
//
// Threading: needs the GL context current at create() on the calling thread.

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "svit/bake_file.h"
#include "svit/math_types.h"
#include "svit/resource_use.h"
#include "svit/scene.h"
#include "svit/status.h"

namespace svit {

class Runtime;

/// What the frame shows.
enum class ShadingView {
  kBakedOnly = 0,   ///< lightmaps alone (what a game without svit's runtime shows)
  kRuntime = 1,     ///< lightmaps + runtime deltas + runtime lights (the product)
  kPatchDelta = 2,  ///< false colour of the per-patch delta (red +, blue -)
};

/// What a pixel shows (SceneRenderer::readSurfaceKinds).
enum class SurfaceKind : uint8_t {
  kNothing = 0,  ///< no geometry: the clear colour
  kStatic = 1,   ///< a static (baked) surface
  kDynamic = 2,  ///< a dynamic object
};

/// A pinhole camera, right-handed, +Y up.
struct Camera {
  Vec3 position{0, 0, 0};
  Vec3 look_at{0, 0, -1};
  Vec3 up{0, 1, 0};
  float yfov_rad = 1.0471975512f;
  float near_m = 0.05f, far_m = 1000.0f;
};

struct SceneRendererSettings {
  int width = 640, height = 360;  ///< offscreen target, pixels
  float exposure = 1.0f;          ///< multiplies radiance before the tone curve
  bool auto_exposure = true;      ///< derive exposure from the bake's mean irradiance
  int shadow_map_size = 512;      ///< runtime lights' shadow maps, texels per face edge
  int shadow_taps = 16;           ///< PCF taps (soft shadows)
};

/// Per-frame draw statistics.
struct RenderStats {
  double shading_ms = 0;  ///< CPU wall time incl. glFinish
  uint32_t draw_calls = 0;
  uint32_t shadow_maps_rendered = 0;
};

class SceneRenderer {
 public:
  /// Uploads the static and dynamic meshes, materials (base colour textures)
  /// and lightmap pages (read from `bake_dir`). `runtime` may be null (baked
  /// only); when given it must outlive the renderer. Errors: no GL 4.5
  /// context, unreadable lightmap page, bake/scene mismatch (triangle count).
  static Expected<std::unique_ptr<SceneRenderer>> create(
      const Scene& scene, const BakeData& bake, const std::string& bake_dir, const Runtime* runtime,
      const SceneRendererSettings& settings = {});
  ~SceneRenderer();

  /// Renders one frame into the offscreen target (or, with
  /// `to_default_framebuffer`, into framebuffer 0 of the current window).
  /// Dynamic objects are drawn where the runtime has them. Framebuffer 0
  /// has no radiance attachment: after such a frame readRadiance() and
  /// writeExr() (like readPixels() and writePng()) still give the previous
  /// offscreen frame, or nothing when there was none.
  Expected<RenderStats> render(const Camera& camera, ShadingView view,
                               bool to_default_framebuffer = false);

  /// Scales what frames show of a baked emitter (BakeData::emitters index),
  /// to match Runtime::setBakedEmitterScale with the same arguments (the
  /// runtime changes the light the emitter casts; the renderer what is seen
  /// of the emitter itself): a lamp's emissive patch (kPatch) has the
  /// emission drawn on its triangles scaled; a baked light or the sun
  /// (kLight, kSun) has its per-pixel direct light on dynamic objects scaled;
  /// the sky (kSky) draws nothing. 1 = as baked (the default), 0 = off.
  /// The runtime and patch-delta views show the scale; kBakedOnly shows the
  /// bake as it is. Errors (nothing changes): `bake_emitter` out of range,
  /// `scale` negative or not finite.
  Status setBakedEmitterScale(uint32_t bake_emitter, float scale);

  /// The GL framebuffer of the offscreen target a host may draw over, a HUD
  /// say, after render() and before readPixels()/writePng(): RGBA8 display
  /// values at colour attachment 0, RGBA32F linear radiance at attachment
  /// 1, depth. render() leaves it drawing to attachment 0 only, so what a
  /// host draws changes the display colour and never the radiance.
  /// Replaced by resize().
  uint32_t offscreenFramebuffer() const;

  /// Reads the last offscreen frame back as 8-bit sRGB RGB, rows top first.
  /// Empty before the first offscreen frame (and after resize()).
  std::vector<uint8_t> readPixels() const;
  /// Writes the last offscreen frame as a PNG. Errors name the path.
  Status writePng(const std::string& path) const;
  /// Reads the last offscreen frame's linear radiance back (cd/m2, linear
  /// Rec.709 RGB, before exposure and the tone curve: what readPixels()
  /// shows is svitDisplay() of it), 3 floats per pixel, rows top first.
  /// The kPatchDelta view stores its false colour there as it is (display
  /// values in 0..1, not radiance). Empty before the first offscreen frame
  /// (and after resize()). Context current.
  std::vector<float> readRadiance() const;
  /// What each pixel of the last offscreen frame shows (SurfaceKind), rows
  /// top first: the picture metric's mask of static surfaces and dynamic
  /// objects. Empty before the first offscreen frame. Context current.
  std::vector<uint8_t> readSurfaceKinds() const;
  /// Writes the last offscreen frame's linear radiance (readRadiance()) as
  /// an OpenEXR file with fp32 R, G, B channels, through `path`.tmp and a
  /// rename (a failure leaves no partial file). Errors name the path: no
  /// offscreen frame yet, a value that is not finite, a directory that
  /// does not exist or cannot be written.
  Status writeExr(const std::string& path) const;
  int width() const;
  int height() const;
  /// Replaces the offscreen target (the last frame is gone). Error (the
  /// size stays): a width or height outside 1..16384.
  Status resize(int width, int height);

  /// What the renderer holds on the GPU now, one line per buffer or
  /// texture set, measured through GL queries; what it left out says why
  /// (Runtime::resources() for the runtime's part). Context current.
  std::vector<ResourceUse> resources() const;

 private:
  struct Impl;
  explicit SceneRenderer(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

/// The GLSL a host engine shades with, by file name in shaders/ (e.g.
/// "lit_static.frag"); empty when unknown.
std::string_view shadingSource(std::string_view file_name);

}  // namespace svit
