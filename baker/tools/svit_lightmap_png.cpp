// svit-lightmap-png OUT [-o PNG] [--exposure E]: a PNG view of a bake's
// lightmap pages (default OUT/lightmaps.png). Exit 0 ok, 1 bad input, 2 bad usage.

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>

#include "svit/bake_file.h"
#include "svit/baker/lightmap_preview.h"
#include "svit/lightmap_image.h"

int main(int argc, char** argv) {
  std::string out_dir, png;
  double exposure = 0;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "-o") && i + 1 < argc) {
      png = argv[++i];
    } else if (!std::strcmp(argv[i], "--exposure") && i + 1 < argc) {
      exposure = std::atof(argv[++i]);
    } else if (argv[i][0] != '-' && out_dir.empty()) {
      out_dir = argv[i];
    } else {
      std::fprintf(stderr, "usage: svit-lightmap-png OUT [-o PNG] [--exposure E]\n");
      return 2;
    }
  }
  if (out_dir.empty()) {
    std::fprintf(stderr, "usage: svit-lightmap-png OUT [-o PNG] [--exposure E]\n");
    return 2;
  }
  if (png.empty()) png = (std::filesystem::path(out_dir) / "lightmaps.png").string();
  svit::Expected<svit::BakeData> bake =
      svit::readBakeFile((std::filesystem::path(out_dir) / "bake.svit").string());
  if (!bake.ok()) {
    std::fprintf(stderr, "svit-lightmap-png: %s\n", bake.status().message().c_str());
    return 1;
  }
  std::vector<svit::LightmapImage> pages;
  for (const svit::BakeLightmapPage& page : bake->pages) {
    svit::Expected<svit::LightmapImage> image =
        svit::readLightmapExr((std::filesystem::path(out_dir) / page.file).string());
    if (!image.ok()) {
      std::fprintf(stderr, "svit-lightmap-png: %s\n", image.status().message().c_str());
      return 1;
    }
    pages.push_back(std::move(image).value());
  }
  if (svit::Status s = svit::baker::writeLightmapPreviewPng(pages, png, exposure); !s.ok()) {
    std::fprintf(stderr, "svit-lightmap-png: %s\n", s.message().c_str());
    return 1;
  }
  std::printf("wrote %s\n", png.c_str());
  return 0;
}
