// Culling in the runtime's index maps on the generated 2 x 2 house: lit-set
// culling (an emitter's later maps draw only what its static maps showed) and
// occlusion culling (nearest chunks first, then what they do not hide) draw
// less and change no delta beyond rounding. The CPU halves are in
// tests/runtime/indexmaps/index_map_culling_test.cpp and index_map_occlusion_test.cpp.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <utility>
#include <vector>

#include "runtime/gl_test_context.h"
#include "runtime/runtime_house_util.h"
#include "runtime/runtime_test_util.h"
#include "svit/runtime.h"

namespace svit {
namespace {

using test::cachingSettings;
using test::house;
using test::makeRuntime;
using test::nodeIndex;
using test::settle;
using test::translated;

/// Settles a runtime of the house, moves table (0, 0) by 30 cm and brings
/// everything up to date again; the deltas then, and the triangles the
/// maps drew after the move.
struct MoveResult {
  std::vector<Rgb> deltas;
  uint64_t triangles_drawn = 0, triangles_hidden = 0;
  uint32_t samples = 0;
};
MoveResult moveTableAndSettle(bool lit_set_culling, bool occlusion_culling = true) {
  RuntimeSettings settings = cachingSettings();
  settings.lit_set_culling = lit_set_culling;
  settings.occlusion_culling = occlusion_culling;
  std::unique_ptr<Runtime> runtime = makeRuntime(house(), settings);
  if (!runtime) return {};
  settle(*runtime, 0);
  const ObjectId table = runtime->objectForNode(nodeIndex(house().scene, "table_0_0"));
  EXPECT_TRUE(runtime
                  ->setObjectTransform(
                      table, translated(runtime->objectInfo(table)->world_from_object, 0.3f, 0.0f))
                  .ok());
  MoveResult out;
  for (int frame = 0; frame < 16; ++frame) {
    const FrameStats stats = runtime->update(0);
    EXPECT_TRUE(stats.error.empty()) << stats.error;
    out.triangles_drawn += stats.triangles_drawn;
    out.triangles_hidden += stats.triangles_hidden;
    out.samples += stats.samples_rendered;
    if (stats.idle) break;
  }
  out.deltas = runtime->patchDeltas();
  return out;
}

// The largest |delta| of `reference` and the worst |difference| of `other`
// from it, in lux (luminance of the patch deltas).
std::pair<double, double> largestAndWorstDifference(const MoveResult& reference,
                                                    const MoveResult& other) {
  double largest = 0, worst = 0;
  for (size_t i = 0; i < reference.deltas.size(); ++i) {
    largest = std::max(largest, double(std::abs(luminance(reference.deltas[i]))));
    worst = std::max(worst,
                     double(std::abs(luminance(reference.deltas[i]) - luminance(other.deltas[i]))));
  }
  return {largest, worst};
}

TEST(RuntimeCulling, LitSetCullingDrawsLessAndChangesNothing) {
  // An emitter's later maps draw only the static runs its static-level maps
  // showed: the same result (objects only hide surfaces) for less drawing.
  test::GlTestContext gl;
  SVIT_REQUIRE_GL(gl);
  const MoveResult box = moveTableAndSettle(false), lit = moveTableAndSettle(true);
  ASSERT_EQ(box.deltas.size(), lit.deltas.size());
  ASSERT_GT(box.samples, 0u);
  EXPECT_EQ(box.samples, lit.samples);
  const auto [largest, worst] = largestAndWorstDifference(box, lit);
  std::printf(
      "lit set: %llu triangles drawn against %llu by boxes (%u samples); largest delta %.4g lux, "
      "worst "
      "difference %.3g lux\n",
      (unsigned long long)lit.triangles_drawn, (unsigned long long)box.triangles_drawn, lit.samples,
      largest, worst);
  ASSERT_GT(largest, 0.0);
  EXPECT_LE(worst, 1e-4 * largest);
  EXPECT_LT(double(lit.triangles_drawn), 0.9 * double(box.triangles_drawn));
}

TEST(RuntimeCulling, OcclusionCullingDrawsLessAndChangesNothing) {
  // Maps of samples with no lit set (here every sample: lit-set culling is
  // off) draw their nearest chunks first, then only what those do not hide:
  // the same maps (hidden chunks cannot win a texel, nor pass the fallback's
  // vertex tests) for less drawing. Depth ties may resolve in another
  // order, so the bound is a rounding one, not zero.
  test::GlTestContext gl;
  SVIT_REQUIRE_GL(gl);
  const MoveResult all = moveTableAndSettle(false, false), culled = moveTableAndSettle(false, true);
  ASSERT_EQ(all.deltas.size(), culled.deltas.size());
  ASSERT_GT(all.samples, 0u);
  EXPECT_EQ(all.samples, culled.samples);
  EXPECT_EQ(all.triangles_hidden, 0u);
  const auto [largest, worst] = largestAndWorstDifference(all, culled);
  std::printf(
      "occlusion: %llu triangles drawn against %llu (%llu hidden; %u samples); largest delta %.4g "
      "lux, worst "
      "difference %.3g lux\n",
      (unsigned long long)culled.triangles_drawn, (unsigned long long)all.triangles_drawn,
      (unsigned long long)culled.triangles_hidden, culled.samples, largest, worst);
  ASSERT_GT(largest, 0.0);
  EXPECT_LE(worst, 1e-4 * largest);
  // Every sample here already draws only its reach box (its room), so
  // little is left to hide; bench_importance shows the 8 x 8 house.
  EXPECT_GT(culled.triangles_hidden, 0u);
  EXPECT_LT(culled.triangles_drawn, all.triangles_drawn);
}

}  // namespace
}  // namespace svit
