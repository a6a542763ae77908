// svit-probe OUT POINTS [--json]: baked irradiance (lux) at points, read from
// the lightmap as a game would. Exit 0 ok, 1 bad input, 2 bad usage.

#include <cstdio>
#include <cstring>
#include <string>

#include "svit/baker/probe.h"

namespace {

void usage(FILE* out) {
  std::fprintf(
      out,
      "usage: svit-probe OUT POINTS [--json]\n"
      "  OUT     a bake directory written by svit-bake\n"
      "  POINTS  a file of lines 'x y z nx ny nz' (metres; the normal picks the surface side)\n"
      "  --json  print a JSON array instead of 'r g b' lines\n");
}

}  // namespace

int main(int argc, char** argv) {
  std::string out_dir, points_path;
  bool json = false;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--json")) {
      json = true;
    } else if (!std::strcmp(argv[i], "--help") || !std::strcmp(argv[i], "-h")) {
      usage(stdout);
      return 0;
    } else if (argv[i][0] == '-') {
      std::fprintf(stderr, "svit-probe: unknown option '%s'\n", argv[i]);
      usage(stderr);
      return 2;
    } else if (out_dir.empty()) {
      out_dir = argv[i];
    } else if (points_path.empty()) {
      points_path = argv[i];
    } else {
      std::fprintf(stderr, "svit-probe: unexpected argument '%s'\n", argv[i]);
      usage(stderr);
      return 2;
    }
  }
  if (out_dir.empty() || points_path.empty()) {
    usage(stderr);
    return 2;
  }
  svit::Expected<std::vector<svit::baker::ProbePoint>> points =
      svit::baker::readProbePoints(points_path);
  if (!points.ok()) {
    std::fprintf(stderr, "svit-probe: %s\n", points.status().message().c_str());
    return 1;
  }
  svit::Expected<std::vector<svit::baker::ProbeResult>> results =
      svit::baker::probeBake(out_dir, *points);
  if (!results.ok()) {
    std::fprintf(stderr, "svit-probe: %s\n", results.status().message().c_str());
    return 1;
  }
  if (json) std::printf("[\n");
  for (size_t i = 0; i < results->size(); ++i) {
    const svit::baker::ProbeResult& r = (*results)[i];
    if (json) {
      std::printf(
          "  {\"irradiance_lux\": [%.9g, %.9g, %.9g], \"surface_point\": [%.9g, %.9g, %.9g], "
          "\"distance_m\": %.9g}%s\n",
          r.irradiance.r, r.irradiance.g, r.irradiance.b, r.surface_point.x, r.surface_point.y,
          r.surface_point.z, r.distance_m, i + 1 < results->size() ? "," : "");
    } else {
      std::printf("%.9g %.9g %.9g\n", r.irradiance.r, r.irradiance.g, r.irradiance.b);
    }
  }
  if (json) std::printf("]\n");
  return 0;
}
