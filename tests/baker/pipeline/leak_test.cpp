// Leaks (issue 22 item 5): every generated level of leak_levels.h is baked
// as a user would (svit-bake's bakeLevel on the written glTF, with --sun /
// --sky) and probed as svit-probe does; its dark probes must read below
// 1e-4 of its lit ones, and its edge probes (within a texel of where a lit
// surface runs into sealed space) below half of them.

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "leak_levels.h"
#include "svit/baker/bake.h"
#include "svit/baker/probe.h"
#include "svit/level.h"

namespace svit::baker {
namespace {

namespace fs = std::filesystem;

/// What a sealed space may read, as a fraction of the lit probes' mean.
constexpr double kDarkBound = 1e-4;
/// What it may read within a texel of where a lit surface runs into it
/// (5 cm under a crate's edge, 2 cm inside a wall the floor runs under):
/// the texel straddling the boundary keeps the light of its lit sample, as
/// black would show on the lit side, and bilinear filtering spreads that
/// light up to a texel into the sealed side.
constexpr double kEdgeBound = 0.5;

struct LeakFigures {
  double lit_lux = 0;         ///< mean of the lit probes
  double darkest_share = 0;   ///< the brightest dark probe over lit_lux
  size_t brightest_dark = 0;  ///< its index
  double edge_share = 0;      ///< the brightest edge probe over lit_lux
  double bake_s = 0;
  size_t texels = 0;
  size_t buried_texels = 0;  ///< black on purpose: under geometry or unreached
  double guard_s = 0;        ///< the light-reach flood's share of bake_s
};

fs::path scratch(const std::string& name) {
  std::string safe = name;
  std::replace(safe.begin(), safe.end(), ' ', '_');
  const fs::path dir = fs::path(testing::TempDir()) / ("svit_leak_" + safe);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

double meanLux(const std::vector<ProbeResult>& results) {
  double sum = 0;
  for (const ProbeResult& r : results) sum += double(luminance(r.irradiance));
  return results.empty() ? 0 : sum / double(results.size());
}

/// `points` as svit-probe's POINTS file, so the bake beside it can be
/// probed again by hand or by another build (tests/bench/leak_compare.sh).
void writePoints(const fs::path& path, const std::vector<ProbePoint>& points) {
  std::ofstream out(path);
  for (const ProbePoint& p : points)
    out << p.position.x << ' ' << p.position.y << ' ' << p.position.z << ' ' << p.normal.x << ' '
        << p.normal.y << ' ' << p.normal.z << '\n';
}

/// Bakes the level and probes it; a failure is an assertion.
LeakFigures bakeAndProbe(const test::LeakLevel& level) {
  const fs::path dir = scratch(level.name);
  const std::string gltf = (dir / "level.gltf").string();
  const Status written = writeGltf(level.scene, gltf);
  EXPECT_TRUE(written.ok()) << written.message();
  writePoints(dir / "dark.txt", level.dark);
  writePoints(dir / "lit.txt", level.lit);
  writePoints(dir / "edge.txt", level.edge);
  const BakeOptions options = test::leakBakeOptions(level, gltf, (dir / "out").string());
  Expected<BakeResult> baked = bakeLevel(options, {}, nullptr);
  EXPECT_TRUE(baked.ok()) << baked.status().message();
  if (!baked.ok()) return {};
  Expected<std::vector<ProbeResult>> lit = probeBake(options.out_dir, level.lit);
  Expected<std::vector<ProbeResult>> dark = probeBake(options.out_dir, level.dark);
  EXPECT_TRUE(lit.ok() && dark.ok()) << (lit.ok() ? dark.status() : lit.status()).message();
  if (!lit.ok() || !dark.ok()) return {};
  LeakFigures figures;
  figures.lit_lux = meanLux(*lit);
  for (size_t i = 0; i < dark->size(); ++i) {
    const double share = double(luminance((*dark)[i].irradiance)) / figures.lit_lux;
    if (share >= figures.darkest_share) {
      figures.darkest_share = share;
      figures.brightest_dark = i;
    }
    std::printf("  %s dark %zu: %.4g lux (%.3g of lit) at triangle %u, %.3f m away\n",
                level.name.c_str(), i, double(luminance((*dark)[i].irradiance)), share,
                (*dark)[i].triangle, (*dark)[i].distance_m);
  }
  if (!level.edge.empty()) {
    Expected<std::vector<ProbeResult>> edge = probeBake(options.out_dir, level.edge);
    EXPECT_TRUE(edge.ok()) << edge.status().message();
    for (const ProbeResult& r : edge.ok() ? *edge : std::vector<ProbeResult>{})
      figures.edge_share =
          std::max(figures.edge_share, double(luminance(r.irradiance)) / figures.lit_lux);
  }
  figures.bake_s = baked->seconds;
  figures.texels = baked->covered_texels;
  const nlohmann::json report = nlohmann::json::parse(std::ifstream(dir / "out" / "report.json"));
  figures.buried_texels = report["lightmap"]["buried_texels"].get<size_t>();
  figures.guard_s = report["radiosity"]["leak_guard"]["seconds"].get<double>();
  std::printf(
      "%s: lit %.4g lux, brightest dark probe %zu at %.3g of it, 2 cm from a wall %.3g; %zu "
      "texels (%zu buried), %.2f s (leak guard %.3f s)\n",
      level.name.c_str(), figures.lit_lux, figures.brightest_dark, figures.darkest_share,
      figures.edge_share, figures.texels, figures.buried_texels, figures.bake_s, figures.guard_s);
  return figures;
}

class Leaks : public testing::TestWithParam<size_t> {};

TEST_P(Leaks, SealedSpacesAndFloorsUnderWallsAreDark) {
  const test::LeakLevel level = test::leakLevels()[GetParam()];
  const LeakFigures figures = bakeAndProbe(level);
  ASSERT_GT(figures.lit_lux, 0.0) << level.name;
  EXPECT_LT(figures.darkest_share, kDarkBound)
      << level.name << ": dark probe " << figures.brightest_dark << " reads "
      << figures.darkest_share << " of the lit probes' " << figures.lit_lux << " lux";
  EXPECT_LT(figures.edge_share, kEdgeBound)
      << level.name << ": within a texel of where the floor runs under a wall or a crate, it reads "
      << figures.edge_share << " of the lit probes' " << figures.lit_lux << " lux";
}

INSTANTIATE_TEST_SUITE_P(Levels, Leaks, testing::Range(size_t(0), test::leakLevels().size()),
                         [](const testing::TestParamInfo<size_t>& param) {
                           std::string name = test::leakLevels()[param.param].name;
                           std::string id;
                           for (char c : name) id += std::isalnum(uint8_t(c)) ? c : '_';
                           return id;
                         });

}  // namespace
}  // namespace svit::baker
