// Sharded bakes (sharded_bake.h): the merged OUT is the whole bake's, byte
// for byte, for N = 1, 3 and 7 shards run in any order, on the Cornell box
// (with its dynamic box, so the runtime sections are merged too) and the
// generated house; a shard rerun writes the same bytes; every missing,
// foreign, truncated or damaged shard is an error naming it that leaves OUT
// as it was; and a radiosity snapshot restores the solver bit for bit.

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numeric>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "svit/baker/bake.h"
#include "svit/baker/bake_geometry.h"
#include "svit/baker/radiosity.h"
#include "svit/baker/ray_caster.h"
#include "svit/baker/sharded_bake.h"
#include "svit/level.h"

namespace svit::baker {
namespace {

namespace fs = std::filesystem;

const std::string kCornellLevel =
    std::string(SVIT_SOURCE_DIR) + "/samples/levels/cornell/level.json";
const std::string kHouseLevel = std::string(SVIT_SOURCE_DIR) + "/samples/levels/house/level.json";

std::vector<char> fileBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<char>((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// A fresh directory under the test's temporary directory.
fs::path scratch(const std::string& name) {
  const fs::path dir = fs::path(testing::TempDir()) / ("svit_sharded_" + name);
  fs::remove_all(dir);
  return dir;
}

BakeOptions smallBake(const std::string& level, const fs::path& out) {
  BakeOptions options;
  options.level_path = level;
  options.out_dir = out.string();
  options.seed = 11;
  options.quality = 0.2;
  options.passes = 2;
  options.texels_per_m = 10;
  return options;
}

// Every file of a bake but report.json (timings), which must be byte-identical.
void expectSameBake(const fs::path& a, const fs::path& b) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(a)) names.push_back(entry.path().filename());
  std::sort(names.begin(), names.end());
  ASSERT_GE(names.size(), 3u);
  for (const std::string& name : names) {
    if (name == "report.json") continue;
    EXPECT_TRUE(fileBytes(a / name) == fileBytes(b / name)) << name << " differs";
  }
}

void plan(const BakeOptions& options, uint32_t shards) {
  Expected<ShardPlanResult> planned = planShardedBake(options, shards, {}, nullptr);
  ASSERT_TRUE(planned.ok()) << planned.status().message();
  EXPECT_EQ(planned->shards, shards);
}

void runShards(const fs::path& work, std::vector<uint32_t> order) {
  for (uint32_t shard : order) {
    Expected<ShardRunResult> run = runBakeShard(work.string(), shard, 0, {}, nullptr);
    ASSERT_TRUE(run.ok()) << run.status().message();
  }
}

Status merge(const fs::path& work, const fs::path& out) {
  Expected<BakeResult> merged = mergeShardedBake(work.string(), out.string(), 0, {}, nullptr);
  return merged.ok() ? Status() : merged.status();
}

void expectMergedEqualsWhole(const std::string& level, const std::string& name) {
  const fs::path whole = scratch(name + "_whole");
  ASSERT_TRUE(bakeLevel(smallBake(level, whole), {}, nullptr).ok());
  for (uint32_t shards : {1u, 3u, 7u}) {
    SCOPED_TRACE(std::to_string(shards) + " shards");
    const fs::path work = scratch(name + "_work" + std::to_string(shards));
    const fs::path out = scratch(name + "_out" + std::to_string(shards));
    plan(smallBake(level, work), shards);
    std::vector<uint32_t> order(shards);
    std::iota(order.rbegin(), order.rend(), 0u);  // last shard first
    runShards(work, order);
    ASSERT_TRUE(merge(work, out).ok());
    expectSameBake(whole, out);
  }
}

TEST(ShardedBake, MergeOfCornellBoxIsTheWholeBakeByteForByte) {
  expectMergedEqualsWhole(kCornellLevel, "cornell");
}

TEST(ShardedBake, MergeOfHouseIsTheWholeBakeByteForByte) {
  expectMergedEqualsWhole(kHouseLevel, "house");
}

nlohmann::json lightingPoints(const fs::path& out, size_t passes) {
  std::ifstream in(out / "report.json");
  const nlohmann::json series = nlohmann::json::parse(in)["error_vs_time"];
  return nlohmann::json(std::vector<nlohmann::json>(series.end() - long(passes), series.end()));
}

// The merge's error estimate (lightmap_error.h): the last pass's split-half
// is the whole bake's exactly (the same sums); the passes before it, texel
// spreads scaled by the split-half's ratio (the whole bake's by the ratio
// at pass 2, the merge's at pass 4), agree within a factor 1.5.
TEST(ShardedBake, MergedErrorEstimateIsTheWholeBakes) {
  const fs::path whole = scratch("estimate_whole"), work = scratch("estimate_work"),
                 out = scratch("estimate_out");
  BakeOptions options = smallBake(kCornellLevel, whole);
  options.passes = 4;
  ASSERT_TRUE(bakeLevel(options, {}, nullptr).ok());
  options.out_dir = work.string();
  plan(options, 3);
  runShards(work, {0, 1, 2});
  ASSERT_TRUE(merge(work, out).ok());
  const nlohmann::json a = lightingPoints(whole, 4), b = lightingPoints(out, 4);
  EXPECT_EQ(b[3]["estimate"], "split_half_pages");
  EXPECT_EQ(b[3]["est_rel_error"].get<double>(), a[3]["est_rel_error"].get<double>());
  for (int pass : {1, 2}) {
    EXPECT_EQ(b[pass]["estimate"], "scaled_texel_spread") << pass;
    const double ratio =
        b[pass]["est_rel_error"].get<double>() / a[pass]["est_rel_error"].get<double>();
    EXPECT_GT(ratio, 1 / 1.5) << pass;
    EXPECT_LT(ratio, 1.5) << pass;
  }
}

// The running test's name: CTest runs tests in parallel, so each keeps its
// own scratch directories.
std::string testName() { return testing::UnitTest::GetInstance()->current_test_info()->name(); }

// A planned Cornell box with three shards lit, and a merged OUT.
struct PlannedCornell {
  fs::path work, out;
  PlannedCornell()
      : work(scratch("errors_work_" + testName())), out(scratch("errors_out_" + testName())) {
    plan(smallBake(kCornellLevel, work), 3);
    runShards(work, {0, 1, 2});
    EXPECT_TRUE(merge(work, out).ok());
  }
  fs::path shardFile(uint32_t shard) const {
    return work / ("shard-" + std::to_string(shard) + ".bin");
  }
  // Merging now fails with a message naming `file` and saying `what`, and
  // leaves OUT byte for byte as it was.
  void expectMergeRefused(const fs::path& file, const std::string& what) const {
    const std::vector<char> before = fileBytes(out / "bake.svit");
    const Status status = merge(work, out);
    EXPECT_FALSE(status.ok());
    EXPECT_NE(status.message().find(file.string()), std::string::npos) << status.message();
    EXPECT_NE(status.message().find(what), std::string::npos) << status.message();
    EXPECT_TRUE(fileBytes(out / "bake.svit") == before);
  }
};

TEST(ShardedBake, RerunShardWritesTheSameBytes) {
  const PlannedCornell planned;
  const std::vector<char> first = fileBytes(planned.shardFile(1));
  runShards(planned.work, {1});
  EXPECT_TRUE(fileBytes(planned.shardFile(1)) == first);
}

TEST(ShardedBake, MissingShardIsNamed) {
  const PlannedCornell planned;
  fs::remove(planned.shardFile(2));
  planned.expectMergeRefused(planned.shardFile(2), "missing");
}

TEST(ShardedBake, TruncatedShardIsNamed) {
  const PlannedCornell planned;
  const fs::path file = planned.shardFile(1);
  fs::resize_file(file, fs::file_size(file) - 100);
  planned.expectMergeRefused(file, "truncated");
}

TEST(ShardedBake, DamagedShardIsNamed) {
  const PlannedCornell planned;
  const fs::path file = planned.shardFile(0);
  std::vector<char> bytes = fileBytes(file);
  bytes[bytes.size() - 7] ^= 0x40;
  std::ofstream(file, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
  planned.expectMergeRefused(file, "damaged");
}

TEST(ShardedBake, ShardOfAnotherPlanIsNamed) {
  const PlannedCornell planned;
  // The same level planned with another seed: its shard 1 is foreign here.
  const fs::path other = scratch("errors_other");
  BakeOptions options = smallBake(kCornellLevel, other);
  options.seed = 12;
  plan(options, 3);
  runShards(other, {1});
  fs::copy_file(other / "shard-1.bin", planned.shardFile(1), fs::copy_options::overwrite_existing);
  planned.expectMergeRefused(planned.shardFile(1), "from another plan");
}

TEST(ShardedBake, ShardOutOfRangeIsRefused) {
  const PlannedCornell planned;
  Expected<ShardRunResult> run = runBakeShard(planned.work.string(), 3, 0, {}, nullptr);
  ASSERT_FALSE(run.ok());
  EXPECT_NE(run.status().message().find("shard 3 out of range"), std::string::npos);
  EXPECT_FALSE(fs::exists(planned.shardFile(3)));
}

TEST(ShardedBake, PlanRefusesTimeBudgetReferenceAndForeignWork) {
  const fs::path work = scratch("refusals");
  BakeOptions timed = smallBake(kCornellLevel, work);
  timed.passes = 0;
  timed.time_budget_s = 10;
  Expected<ShardPlanResult> planned = planShardedBake(timed, 2, {}, nullptr);
  ASSERT_FALSE(planned.ok());
  EXPECT_NE(planned.status().message().find("--time"), std::string::npos);
  EXPECT_FALSE(planShardedBake(smallBake(kCornellLevel, work), 0, {}, nullptr).ok());
  // WORK holding something that is not a plan is not replaced.
  fs::create_directories(work);
  std::ofstream(work / "notes.txt") << "mine";
  planned = planShardedBake(smallBake(kCornellLevel, work), 2, {}, nullptr);
  ASSERT_FALSE(planned.ok());
  EXPECT_NE(planned.status().message().find("not replaced"), std::string::npos);
  EXPECT_TRUE(fs::exists(work / "notes.txt"));
}

TEST(ShardedBake, WholeBakeRefusesPassesWithTimeBudget) {
  BakeOptions options = smallBake(kCornellLevel, scratch("passes_time"));
  options.time_budget_s = 5;
  const Status status = validateBakeOptions(options);
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.message().find("--passes and --time"), std::string::npos);
}

// The restored solver answers every query as the original does, and
// continues shooting the same way.
TEST(RadiositySnapshot, RestoredSolverIsTheOriginalBitForBit) {
  Scene scene = std::move(loadLevel(SVIT_CORNELL_GLTF)).value();
  BakeGeometry geometry = std::move(flattenStaticGeometry(scene)).value();
  std::unique_ptr<RayCaster> caster = std::move(makeEmbreeCaster(geometry)).value();
  std::unique_ptr<RadiositySolver> solver =
      std::move(RadiositySolver::create(scene, geometry, *caster, RadiositySettings{})).value();
  StopRule three;
  three.max_passes = 3;
  ASSERT_TRUE(solver->improve(three).ok());
  Expected<std::unique_ptr<RadiositySolver>> restored =
      RadiositySolver::restore(scene, geometry, *caster, 1, solver->snapshot());
  ASSERT_TRUE(restored.ok()) << restored.status().message();
  const auto same = [&](const RadiositySolver& a, const RadiositySolver& b) {
    const std::vector<Rgb> ra = a.triangleRadiosity(), rb = b.triangleRadiosity();
    ASSERT_EQ(ra.size(), rb.size());
    for (size_t t = 0; t < ra.size(); ++t) {
      EXPECT_EQ(ra[t].r, rb[t].r);
      EXPECT_EQ(ra[t].g, rb[t].g);
      const Rgb ea = a.irradianceAt(uint32_t(t), true, 0.2, 0.3, InterpolationMode::kVertex);
      const Rgb eb = b.irradianceAt(uint32_t(t), true, 0.2, 0.3, InterpolationMode::kVertex);
      EXPECT_EQ(ea.b, eb.b);
    }
    EXPECT_EQ(a.stats().leaves, b.stats().leaves);
  };
  same(*solver, **restored);
  StopRule five;
  five.max_passes = 5;
  ASSERT_TRUE(solver->improve(five).ok());
  ASSERT_TRUE((*restored)->improve(five).ok());
  same(*solver, **restored);
  EXPECT_GT((*restored)->stats().subdivisions, 0u);
}

TEST(RadiositySnapshot, SnapshotOfOtherGeometryOrTruncatedIsRefused) {
  Scene scene = std::move(loadLevel(SVIT_CORNELL_GLTF)).value();
  BakeGeometry geometry = std::move(flattenStaticGeometry(scene)).value();
  std::unique_ptr<RayCaster> caster = std::move(makeEmbreeCaster(geometry)).value();
  std::unique_ptr<RadiositySolver> solver =
      std::move(RadiositySolver::create(scene, geometry, *caster, RadiositySettings{})).value();
  StopRule two;
  two.max_passes = 2;
  ASSERT_TRUE(solver->improve(two).ok());
  std::vector<uint8_t> bytes = solver->snapshot();
  bytes.resize(bytes.size() - 1);
  EXPECT_FALSE(RadiositySolver::restore(scene, geometry, *caster, 1, bytes).ok());
  Scene house = std::move(loadLevel(kHouseLevel)).value();
  BakeGeometry house_geometry = std::move(flattenStaticGeometry(house)).value();
  std::unique_ptr<RayCaster> house_caster = std::move(makeEmbreeCaster(house_geometry)).value();
  Expected<std::unique_ptr<RadiositySolver>> foreign =
      RadiositySolver::restore(house, house_geometry, *house_caster, 1, solver->snapshot());
  ASSERT_FALSE(foreign.ok());
  EXPECT_NE(foreign.status().message().find("another level"), std::string::npos);
}

}  // namespace
}  // namespace svit::baker
