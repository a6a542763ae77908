// Shadow masks through whole bakes (shadow_masks.h): which lights a level
// gets masks for, how many channels overlapping and disjoint lights take,
// and that the lightmap without the masked lights' direct light plus their
// masks reads (svit-probe) as the bake without masks does.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "svit/bake_file.h"
#include "svit/baker/bake.h"
#include "svit/baker/probe.h"

namespace svit::baker {
namespace {

namespace fs = std::filesystem;

fs::path workDir() { return fs::temp_directory_path() / "svit_shadow_masks_test"; }

// The Cornell box with `lights` (level.json "lights" entries), the tall box dynamic or not.
std::string cornellLevel(const std::string& name, const std::string& lights, bool box_dynamic) {
  fs::create_directories(workDir());
  const fs::path path = workDir() / (name + ".json");
  std::ofstream(path) << R"({"gltf": ")" << SVIT_CORNELL_GLTF << R"(", )"
                      << (box_dynamic ? R"("dynamic": ["tallBox"], )" : "") << R"("lights": [)"
                      << lights << "]}";
  return path.string();
}

// Eight point lamps over the floor, 1.5 m up (above the tall box), on a 4 x
// 2 grid: every one lights most of the floor, so each needs a channel of
// its own.
std::string eightLamps() {
  std::string out;
  for (int i = 0; i < 8; ++i) {
    const double x = -0.6 + 0.4 * (i % 4), z = -0.4 + 0.8 * (i / 4);
    if (i > 0) out += ", ";
    out += R"({"name": "lamp)" + std::to_string(i) +
           R"(", "type": "point", "color": [1, 1, 1], "intensity_cd": 0.3, "position": [)" +
           std::to_string(x) + ", 1.5, " + std::to_string(z) + "]}";
  }
  return out;
}

struct Baked {
  BakeData bake;
  nlohmann::json report;
  std::string dir;
};

Baked bake(const std::string& level, const std::string& name, bool masks) {
  BakeOptions options;
  options.level_path = level;
  options.out_dir = (workDir() / name).string();
  options.passes = 4;
  options.seed = 5;
  options.shadow_masks = masks;
  Expected<BakeResult> result = bakeLevel(options, nullptr, nullptr);
  EXPECT_TRUE(result.ok()) << result.status().message();
  Baked out;
  out.dir = options.out_dir;
  Expected<BakeData> data = readBakeFile(out.dir + "/bake.svit");
  EXPECT_TRUE(data.ok()) << data.status().message();
  if (data.ok()) out.bake = std::move(data).value();
  out.report = nlohmann::json::parse(std::ifstream(out.dir + "/report.json"));
  return out;
}

TEST(ShadowMasks, EightOverlappingLampsTakeAChannelEachAndReadAsTheUnmaskedBake) {
  const std::string level = cornellLevel("eight_lamps", eightLamps(), true);
  const Baked masked = bake(level, "eight_lamps_masked", true);
  const Baked plain = bake(level, "eight_lamps_plain", false);
  // The eight lamps and the ceiling lamp's two patches (area lights): all
  // overlap, so each takes a channel.
  ASSERT_EQ(masked.bake.masks.lights.size(), 10u);
  size_t areas = 0;
  for (const BakeMaskedLight& m : masked.bake.masks.lights)
    areas += masked.bake.emitters[m.emitter].kind == BakeEmitter::Kind::kPatch ? 1 : 0;
  EXPECT_EQ(areas, 2u);
  EXPECT_EQ(masked.bake.masks.channels, 10u);
  EXPECT_EQ(masked.bake.masks.layers(), 3u);
  EXPECT_TRUE(plain.bake.masks.lights.empty());
  const nlohmann::json& report = masked.report["shadow_masks"];
  EXPECT_EQ(report["lights"].size(), 10u);
  EXPECT_GT(report["bytes"].get<double>(), 0);
  std::printf("8 lamps and 2 lamp patches: %u channels, %.0f bytes, %.2f s\n",
              masked.bake.masks.channels, report["bytes"].get<double>(),
              report["seconds"].get<double>());
  // The floor, the back wall and the short box's top, where every lamp reaches.
  std::vector<ProbePoint> points;
  for (double x : {-0.7, -0.3, 0.0, 0.4, 0.7})
    for (double z : {-0.6, 0.0, 0.6}) points.push_back({{float(x), 0.0f, float(z)}, {0, 1, 0}});
  for (double x : {-0.5, 0.5}) points.push_back({{float(x), 1.0f, -1.04f}, {0, 0, 1}});
  Expected<std::vector<ProbeResult>> with = probeBake(masked.dir, points);
  Expected<std::vector<ProbeResult>> without = probeBake(plain.dir, points);
  ASSERT_TRUE(with.ok()) << with.status().message();
  ASSERT_TRUE(without.ok()) << without.status().message();
  for (size_t i = 0; i < points.size(); ++i) {
    const double a = luminance((*with)[i].irradiance), b = luminance((*without)[i].irradiance);
    EXPECT_NEAR(a, b, 0.05 * b + 0.02) << "probe " << i;
  }
}

TEST(ShadowMasks, LightsThatNeverOverlapShareAChannel) {
  // Two narrow spots on the left and the right wall.
  const std::string spots =
      R"({"name": "left", "type": "spot", "position": [0, 1, 0], "direction": [-1, 0, 0],
          "color": [1, 1, 1], "intensity_cd": 2, "inner_cone_rad": 0.1, "outer_cone_rad": 0.2},
         {"name": "right", "type": "spot", "position": [0, 1, 0], "direction": [1, 0, 0],
          "color": [1, 1, 1], "intensity_cd": 2, "inner_cone_rad": 0.1, "outer_cone_rad": 0.2})";
  const Baked masked = bake(cornellLevel("two_spots", spots, true), "two_spots", true);
  std::vector<BakeMaskedLight> spot_masks;  // (the ceiling lamp's patches are masked too)
  for (const BakeMaskedLight& m : masked.bake.masks.lights)
    if (masked.bake.emitters[m.emitter].kind == BakeEmitter::Kind::kLight) spot_masks.push_back(m);
  ASSERT_EQ(spot_masks.size(), 2u);
  EXPECT_EQ(spot_masks[0].channel, spot_masks[1].channel);
  EXPECT_NE(spot_masks[0].owner, spot_masks[1].owner);
}

TEST(ShadowMasks, ALevelWithoutDynamicObjectsStoresNone) {
  const Baked plain = bake(cornellLevel("static_lamps", eightLamps(), false), "static_lamps", true);
  EXPECT_TRUE(plain.bake.masks.lights.empty());
  EXPECT_TRUE(plain.bake.masks.pages.empty());
  bool listed = false;
  for (const nlohmann::json& left : plain.report["sections_left_out"]) {
    if (left["section"] == "shadow_masks") {
      listed = true;
      EXPECT_EQ(left["reason"], "the level has no dynamic objects");
    }
  }
  EXPECT_TRUE(listed);
}

}  // namespace
}  // namespace svit::baker
