// Crops of frames, for tests/bench/filter_crops.sh:
//   bench_frame_compare compare SHOWN.exr REFERENCE.exr X Y W H
//     two linear-radiance frames (svit-walk --frames-format exr) in a
//     rectangle: the RMS of their luminance difference over the reference's
//     mean luminance there, and both means; prints
//     rel_rms=R shown_mean=A reference_mean=B pixels=N
//   bench_frame_compare crop IN.png OUT.png X Y W H SCALE
//     the rectangle of a display frame, each pixel SCALE x SCALE, as a PNG.

#include <stb_image.h>
#include <stb_image_write.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "svit/lightmap_image.h"

namespace {

struct Rect {
  int x = 0, y = 0, w = 0, h = 0;
  bool inside(int width, int height) const { return x + w <= width && y + h <= height; }
};

int fail(const std::string& message) {
  std::fprintf(stderr, "bench_frame_compare: %s\n", message.c_str());
  return 1;
}

bool parseInt(const char* text, int low, int high, int& out) {
  char* end = nullptr;
  const long v = std::strtol(text, &end, 10);
  if (*end != '\0' || v < low || v > high) return false;
  out = int(v);
  return true;
}

bool parseRect(char** argv, Rect& rect) {
  return parseInt(argv[0], 0, 16384, rect.x) && parseInt(argv[1], 0, 16384, rect.y) &&
         parseInt(argv[2], 1, 16384, rect.w) && parseInt(argv[3], 1, 16384, rect.h);
}

int compare(char** argv) {
  const auto shown = svit::readLightmapExr(argv[0]);
  if (!shown.ok()) return fail(shown.status().message());
  const auto reference = svit::readLightmapExr(argv[1]);
  if (!reference.ok()) return fail(reference.status().message());
  if (shown->width != reference->width || shown->height != reference->height)
    return fail(std::string(argv[0]) + " and " + argv[1] + " differ in size");
  Rect rect;
  if (!parseRect(argv + 2, rect)) return fail("bad rectangle X Y W H");
  if (!rect.inside(shown->width, shown->height)) return fail("rectangle outside the frames");
  double squares = 0, shown_sum = 0, reference_sum = 0;
  for (int y = rect.y; y < rect.y + rect.h; ++y) {
    for (int x = rect.x; x < rect.x + rect.w; ++x) {
      const double a = svit::luminance(shown->texel(x, y));
      const double b = svit::luminance(reference->texel(x, y));
      squares += (a - b) * (a - b);
      shown_sum += a;
      reference_sum += b;
    }
  }
  const double n = double(rect.w) * double(rect.h);
  const double reference_mean = reference_sum / n;
  std::printf("rel_rms=%.5f shown_mean=%.6g reference_mean=%.6g pixels=%.0f\n",
              reference_mean > 0 ? std::sqrt(squares / n) / reference_mean : 0.0, shown_sum / n,
              reference_mean, n);
  return 0;
}

int crop(char** argv) {
  Rect rect;
  int scale = 1;
  if (!parseRect(argv + 2, rect) || !parseInt(argv[6], 1, 16, scale))
    return fail("bad rectangle X Y W H or SCALE (1..16)");
  int width = 0, height = 0, channels = 0;
  const std::unique_ptr<stbi_uc, void (*)(void*)> in(
      stbi_load(argv[0], &width, &height, &channels, 3), stbi_image_free);
  if (!in) return fail(std::string(argv[0]) + ": " + stbi_failure_reason());
  if (!rect.inside(width, height)) return fail(std::string(argv[0]) + ": rectangle outside it");
  const int out_w = rect.w * scale, out_h = rect.h * scale;
  std::vector<uint8_t> out(size_t(out_w) * size_t(out_h) * 3);
  for (int y = 0; y < out_h; ++y) {
    for (int x = 0; x < out_w; ++x) {
      const size_t from = (size_t(rect.y + y / scale) * size_t(width) + size_t(rect.x + x / scale));
      for (int c = 0; c < 3; ++c)
        out[(size_t(y) * size_t(out_w) + size_t(x)) * 3 + size_t(c)] =
            in.get()[from * 3 + size_t(c)];
    }
  }
  if (stbi_write_png(argv[1], out_w, out_h, 3, out.data(), out_w * 3) == 0)
    return fail(std::string(argv[1]) + ": cannot write the PNG");
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string verb = argc > 1 ? argv[1] : "";
  if (verb == "compare" && argc == 8) return compare(argv + 2);
  if (verb == "crop" && argc == 9) return crop(argv + 2);
  return fail(
      "usage: bench_frame_compare compare SHOWN.exr REFERENCE.exr X Y W H\n"
      "       bench_frame_compare crop IN.png OUT.png X Y W H SCALE");
}
