// A lightmap per side, as a player sees it: the generated level of two
// rooms split by a double-sided partition, a lamp in one (the leak tests'
// level, tests/baker/pipeline/leak_levels.cpp), baked and rendered from each room
// looking at the partition. Its lit side shows the lamp's light; its dark
// side, which faces the sealed room, has no texels (kUnlitBackPage) and is
// drawn black (with one lightmap for both sides it showed the lit side's
// light). Label `gl` (xvfb-run).

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "baker/pipeline/leak_levels.h"
#include "runtime/gl_test_context.h"
#include "svit/baker/bake.h"
#include "svit/level.h"
#include "svit/scene_renderer.h"

namespace svit {
namespace {

namespace fs = std::filesystem;

struct PartitionViews {
  double lit = 0, dark = 0;  ///< mean linear radiance of the partition, cd/m2
  size_t back_faces = 0;     ///< double-sided triangles with a back lightmap
  size_t unlit_backs = 0;    ///< of them, backs no light reaches (kUnlitBackPage)
};

/// Mean radiance of the middle quarter of the frame (the partition fills it).
double middleMean(const std::vector<float>& rgba, int width, int height) {
  double sum = 0;
  int count = 0;
  for (int y = height * 3 / 8; y < height * 5 / 8; ++y) {
    for (int x = width * 3 / 8; x < width * 5 / 8; ++x) {
      const float* p = &rgba[(size_t(y) * size_t(width) + size_t(x)) * 4];
      sum += 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
      ++count;
    }
  }
  return sum / count;
}

PartitionViews renderPartition() {
  PartitionViews views;
  test::LeakLevel level;
  for (test::LeakLevel& l : test::leakLevels()) {
    if (l.name == "double-sided partition") level = std::move(l);
  }
  const fs::path dir = fs::path(testing::TempDir()) / "svit_scene_renderer_sides";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string gltf = (dir / "level.gltf").string();
  EXPECT_TRUE(writeGltf(level.scene, gltf).ok());
  const baker::BakeOptions options = test::leakBakeOptions(level, gltf, (dir / "out").string());
  EXPECT_TRUE(baker::bakeLevel(options, {}, nullptr).ok());
  Expected<BakeData> bake = readBakeFile(options.out_dir + "/bake.svit");
  Expected<Scene> scene = loadLevel(gltf);
  EXPECT_TRUE(bake.ok() && scene.ok());
  if (!bake.ok() || !scene.ok()) return views;
  views.back_faces = bake->back_uvs.size();
  for (const BakeBackUv& back : bake->back_uvs) views.unlit_backs += back.page == kUnlitBackPage;
  test::GlTestContext context;
  EXPECT_TRUE(context.ok());
  if (!context.ok()) return views;
  SceneRendererSettings settings;
  settings.width = 160, settings.height = 90;
  auto renderer = SceneRenderer::create(*scene, *bake, options.out_dir, nullptr, settings);
  EXPECT_TRUE(renderer.ok()) << renderer.status().message();
  if (!renderer.ok()) return views;
  // The partition stands at x = 0 (z in [-1.5, 1.5], y in [0, 2.5]); the
  // lamp's room is x < 0. From 1.8 m away a 0.6 rad view sees only it.
  for (const float side : {-1.0f, 1.0f}) {
    Camera camera;
    camera.position = {side * 1.8f, 1.25f, 0.0f};
    camera.look_at = {0.0f, 1.25f, 0.0f};
    camera.yfov_rad = 0.6f;
    EXPECT_TRUE((*renderer)->render(camera, ShadingView::kBakedOnly).ok());
    (side < 0 ? views.lit : views.dark) =
        middleMean((*renderer)->readRadiance(), settings.width, settings.height);
    const fs::path png = fs::temp_directory_path() / (side < 0 ? "svit_partition_lit_side.png"
                                                               : "svit_partition_dark_side.png");
    EXPECT_TRUE((*renderer)->writePng(png.string()).ok());
  }
  return views;
}

TEST(SceneRendererSides, EachSideOfADoubleSidedPartitionShowsItsOwnRoomsLight) {
  const PartitionViews views = renderPartition();
  std::printf(
      "double-sided partition: lit side %.4g cd/m2, dark side %.4g cd/m2 (%zu backs, %zu unlit)\n",
      views.lit, views.dark, views.back_faces, views.unlit_backs);
  EXPECT_EQ(views.back_faces, 2u) << "the partition's two triangles";
  EXPECT_EQ(views.unlit_backs, 2u) << "its back faces the sealed room: no texels, drawn black";
  EXPECT_GT(views.lit, 0.5) << "the lamp-lit side (100 cd at 1.5 m, albedo 0.5: ~7 cd/m2)";
  EXPECT_LT(views.dark, 1e-4 * views.lit) << "the dark room's side reads " << views.dark
                                          << " cd/m2 against the lit side's " << views.lit;
}

}  // namespace
}  // namespace svit
