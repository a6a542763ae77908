#pragma once
// The picture metric: a frame the runtime shows against the
// baked view of a level in which the dynamic object is static at the same
// pose, both read back as linear radiance from the renderer's float
// target at the same camera. Static surfaces: RMS of the luminance
// difference over their pixels, relative to the reference's mean there.
// The dynamic object's own pixels: mean luminance against the reference's
// over the same pixels, and their relative RMS. Used by the gl tests and by
// tests/bench/picture_bench.cpp alike.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "svit/scene_renderer.h"

namespace svit::test {

/// One frame as the metric reads it.
struct LinearFrame {
  int width = 0, height = 0;
  std::vector<float> rgb;        ///< linear radiance, cd/m2, 3 per pixel, rows top first
  std::vector<uint8_t> surface;  ///< per pixel: SurfaceKind (SceneRenderer::readSurfaceKinds)
};

inline LinearFrame readLinearFrame(const SceneRenderer& renderer) {
  return {renderer.width(), renderer.height(), renderer.readRadiance(),
          renderer.readSurfaceKinds()};
}

struct PictureError {
  double static_rms = 0;      ///< of the luminance difference over static pixels, cd/m2
  double static_rel_rms = 0;  ///< static_rms relative to the reference's mean there
  double static_reference_mean = 0;
  uint32_t static_pixels = 0;
  double dynamic_mean = 0;            ///< the shown frame's, over the dynamic object's pixels
  double dynamic_reference_mean = 0;  ///< the reference's over the same pixels
  double dynamic_rel_rms = 0;
  uint32_t dynamic_pixels = 0;
  /// dynamic_mean / dynamic_reference_mean - 1 (0 without dynamic pixels).
  double dynamicMeanError() const {
    return dynamic_reference_mean > 0 ? dynamic_mean / dynamic_reference_mean - 1 : 0;
  }
};

inline double rec709Luminance(const float* rgb) {
  return 0.2126 * double(rgb[0]) + 0.7152 * double(rgb[1]) + 0.0722 * double(rgb[2]);
}

/// `shown` against `reference` (same size and camera). A pixel is static
/// where both frames show a static surface, dynamic where `shown` shows a
/// dynamic object (the reference has it static there).
inline PictureError comparePictures(const LinearFrame& shown, const LinearFrame& reference) {
  PictureError out;
  double static_sq = 0, static_ref = 0, dynamic_sq = 0, dynamic_sum = 0, dynamic_ref = 0;
  const size_t pixels = size_t(shown.width) * size_t(shown.height);
  for (size_t i = 0; i < pixels && i < reference.surface.size(); ++i) {
    const double a = rec709Luminance(&shown.rgb[i * 3]), b = rec709Luminance(&reference.rgb[i * 3]);
    if (shown.surface[i] == uint8_t(SurfaceKind::kStatic) &&
        reference.surface[i] == uint8_t(SurfaceKind::kStatic)) {
      static_sq += (a - b) * (a - b);
      static_ref += b;
      ++out.static_pixels;
    } else if (shown.surface[i] == uint8_t(SurfaceKind::kDynamic) && reference.surface[i] != 0) {
      dynamic_sq += (a - b) * (a - b);
      dynamic_sum += a;
      dynamic_ref += b;
      ++out.dynamic_pixels;
    }
  }
  if (out.static_pixels > 0) {
    out.static_reference_mean = static_ref / out.static_pixels;
    out.static_rms = std::sqrt(static_sq / out.static_pixels);
    out.static_rel_rms = out.static_rms / std::max(out.static_reference_mean, 1e-30);
  }
  if (out.dynamic_pixels > 0) {
    out.dynamic_mean = dynamic_sum / out.dynamic_pixels;
    out.dynamic_reference_mean = dynamic_ref / out.dynamic_pixels;
    out.dynamic_rel_rms =
        std::sqrt(dynamic_sq / out.dynamic_pixels) / std::max(out.dynamic_reference_mean, 1e-30);
  }
  return out;
}

/// Mean luminance over the pixels of `kind`.
inline double meanLuminance(const LinearFrame& frame, SurfaceKind kind) {
  double sum = 0;
  size_t count = 0;
  for (size_t i = 0; i < frame.surface.size(); ++i) {
    if (frame.surface[i] != uint8_t(kind)) continue;
    sum += rec709Luminance(&frame.rgb[i * 3]);
    ++count;
  }
  return count > 0 ? sum / double(count) : 0;
}

}  // namespace svit::test
