// The true error of svit-bake --reference (bake.h BakeOptions::reference_dir):
// this bake's pages against the reference's, so a bake against an identical
// bake of itself reads exactly 0 (raw texel means against its filtered
// pages read the filter as error), and a bake of another seed reads its
// noise, measured after passes 1, 2, 4 and the last.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "svit/baker/bake.h"

namespace svit::baker {
namespace {

namespace fs = std::filesystem;

BakeOptions cornellBake(const std::string& name, uint64_t seed) {
  const fs::path dir = fs::path(testing::TempDir()) / ("svit_reference_" + name);
  fs::remove_all(dir);
  BakeOptions options;
  options.level_path = std::string(SVIT_SOURCE_DIR) + "/samples/levels/cornell/level.json";
  options.out_dir = dir.string();
  options.seed = seed;
  options.quality = 0.2;
  options.passes = 5;
  options.texels_per_m = 10;
  return options;
}

TEST(ReferenceError, PagesAgainstPagesReadZeroForTheSameBakeAndTheNoiseForAnother) {
  const BakeOptions reference = cornellBake("reference", 11);
  ASSERT_TRUE(bakeLevel(reference, {}, nullptr).ok());

  BakeOptions same = cornellBake("same", 11);
  same.reference_dir = reference.out_dir;
  Expected<BakeResult> again = bakeLevel(same, {}, nullptr);
  ASSERT_TRUE(again.ok()) << again.status().message();
  EXPECT_EQ(again->ref_rel_error, 0.0);

  BakeOptions other = cornellBake("other", 12);
  other.reference_dir = reference.out_dir;
  Expected<BakeResult> noisy = bakeLevel(other, {}, nullptr);
  ASSERT_TRUE(noisy.ok()) << noisy.status().message();
  EXPECT_GT(noisy->ref_rel_error, 0.0);
  EXPECT_LT(noisy->ref_rel_error, 0.05);

  // Measured after passes 1, 2, 4 and the last (5), not after pass 3.
  const nlohmann::json report = nlohmann::json::parse(noisy->report_json);
  std::vector<bool> measured;
  for (const auto& point : report["error_vs_time"])
    if (point.contains("ref_rel_error")) measured.push_back(!point["ref_rel_error"].is_null());
  ASSERT_GE(measured.size(), 5u);
  const std::vector<bool> last_five(measured.end() - 5, measured.end());
  EXPECT_EQ(last_five, (std::vector<bool>{true, true, false, true, true}));
}

}  // namespace
}  // namespace svit::baker
