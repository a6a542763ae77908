// The "pay for what is used" audit: GL storage is measured right, a static
// level holds nothing but its lightmaps, and a dynamic level accounts for
// the maps, deltas and view pass it made, and nothing it did not.

#include <gtest/gtest.h>

#include <epoxy/gl.h>

#include <string>
#include <vector>

#include "gl/gl_handle.h"
#include "gl/gl_memory.h"
#include "runtime/gl_test_context.h"
#include "runtime/runtime_test_util.h"
#include "svit/runtime.h"
#include "svit/scene_renderer.h"

namespace svit {
namespace {

using test::bakedLevel;

const ResourceUse& find(const std::vector<ResourceUse>& uses, const std::string& name) {
  for (const ResourceUse& use : uses) {
    if (use.name == name) return use;
  }
  static const ResourceUse missing;
  ADD_FAILURE() << "no resource line '" << name << "'";
  return missing;
}

TEST(ResourceAudit, GlStorageIsMeasuredFromGl) {
  test::GlTestContext gl;
  SVIT_REQUIRE_GL(gl);
  GLuint buffer = 0, texture = 0, array = 0, cube = 0, renderbuffer = 0;
  glCreateBuffers(1, &buffer);
  glNamedBufferData(buffer, 1234, nullptr, GL_STATIC_DRAW);
  glCreateTextures(GL_TEXTURE_2D, 1, &texture);
  glTextureStorage2D(texture, 2, GL_RGB32F, 100, 50);  // 100x50 + 50x25, 12 bytes each
  glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &array);
  glTextureStorage3D(array, 1, GL_RG32UI, 64, 64, 6);
  glCreateTextures(GL_TEXTURE_CUBE_MAP, 1, &cube);
  glTextureStorage2D(cube, 1, GL_DEPTH_COMPONENT32F, 16, 16);
  glCreateRenderbuffers(1, &renderbuffer);
  glNamedRenderbufferStorage(renderbuffer, GL_DEPTH_COMPONENT32F, 30, 20);
  ASSERT_EQ(glGetError(), GLenum(GL_NO_ERROR));

  EXPECT_EQ(gl::glObjectBytes(gl::glBufferObject(buffer)), 1234u);
  EXPECT_EQ(gl::glObjectBytes(gl::glTextureObject(texture)), (100u * 50u + 50u * 25u) * 12u);
  EXPECT_EQ(gl::glObjectBytes(gl::glTextureObject(array)), 64u * 64u * 6u * 8u);
  EXPECT_EQ(gl::glObjectBytes(gl::glTextureObject(cube)), 6u * 16u * 16u * 4u);
  EXPECT_EQ(gl::glObjectBytes(gl::glRenderbufferObject(renderbuffer)), 30u * 20u * 4u);
  const std::vector<gl::GlObject> set = {gl::glBufferObject(buffer), gl::glTextureObject(0),
                                         gl::glTextureObject(array)};
  const gl::GlFootprint footprint = gl::glFootprint(set);
  EXPECT_EQ(footprint.objects, 2u);
  EXPECT_EQ(footprint.bytes, 1234u + 64u * 64u * 6u * 8u);

  gl::deleteGlName(gl::GlKind::kBuffer, buffer);
  for (GLuint t : {texture, array, cube}) gl::deleteGlName(gl::GlKind::kTexture, t);
  gl::deleteGlName(gl::GlKind::kRenderbuffer, renderbuffer);
}

TEST(ResourceAudit, StaticLevelHoldsOnlyItsLightmaps) {
  test::GlTestContext gl;
  SVIT_REQUIRE_GL(gl);
  const test::BakedLevel& level = bakedLevel("cornell_static", test::cornellGltf());
  Expected<std::unique_ptr<Runtime>> created = Runtime::create(level.scene, level.bake, level.dir);
  ASSERT_TRUE(created.ok()) << created.status().message();
  Runtime& runtime = **created;
  for (int frame = 0; frame < 3; ++frame) runtime.update(16);

  uint64_t page_bytes = 0;
  for (const BakeLightmapPage& page : level.bake.pages)
    page_bytes += uint64_t(page.width) * page.height * 12u;
  std::vector<ResourceUse> uses = runtime.resources();
  for (const ResourceUse& use : uses) {
    EXPECT_FALSE(use.reason.empty()) << use.name;
    if (use.name == "lightmap pages (host copy)") {
      EXPECT_TRUE(use.allocated);
      EXPECT_EQ(use.cpu_bytes, page_bytes);
    } else {
      EXPECT_FALSE(use.allocated) << use.name << ": " << use.reason;
      EXPECT_EQ(use.gpu_bytes + use.cpu_bytes, 0u) << use.name;
    }
  }
  EXPECT_NE(
      find(uses, "index maps, geometry and reduction buffers").reason.find("no dynamic objects"),
      std::string::npos);

  // The host asks for the textures: exactly one GL copy of the pages.
  runtime.shadingResources();
  const std::vector<ResourceUse> shaded = runtime.resources();
  const ResourceUse& textures = find(shaded, "lightmap textures");
  EXPECT_TRUE(textures.allocated);
  EXPECT_EQ(textures.gl_objects, level.bake.pages.size());
  EXPECT_EQ(textures.gpu_bytes, page_bytes);

  // Drawn without a runtime: its own lightmaps, no deltas, no probes, no
  // shadow maps (no runtime lights, no dynamic objects).
  SceneRendererSettings settings;
  settings.width = 64;
  settings.height = 48;
  Expected<std::unique_ptr<SceneRenderer>> renderer =
      SceneRenderer::create(level.scene, level.bake, level.dir, nullptr, settings);
  ASSERT_TRUE(renderer.ok()) << renderer.status().message();
  ASSERT_TRUE((*renderer)->render(Camera{{0, 1, 3.4f}, {0, 1, 0}}, ShadingView::kBakedOnly).ok());
  const std::vector<ResourceUse> drawn = (*renderer)->resources();
  EXPECT_EQ(find(drawn, "lightmap textures").gpu_bytes, page_bytes);
  EXPECT_FALSE(find(drawn, "probe grid textures").allocated);
  EXPECT_FALSE(find(drawn, "light shadow maps").allocated);
  EXPECT_FALSE(find(drawn, "dynamic object vertex buffer").allocated);
  // RGBA8 colour, RGBA32F radiance, 32-bit depth.
  EXPECT_EQ(find(drawn, "offscreen target (colour + radiance + depth)").gpu_bytes,
            64u * 48u * (4u + 16u + 4u));
}

TEST(ResourceAudit, DynamicLevelAccountsForWhatItMade) {
  test::GlTestContext gl;
  SVIT_REQUIRE_GL(gl);
  const test::BakedLevel& level = bakedLevel("cornell", test::cornellLevel());
  RuntimeSettings settings;
  settings.map_resolution = 128;
  Expected<std::unique_ptr<Runtime>> created =
      Runtime::create(level.scene, level.bake, level.dir, settings);
  ASSERT_TRUE(created.ok()) << created.status().message();
  Runtime& runtime = **created;

  // Before any update: patches and the box, but no maps and no deltas yet.
  std::vector<ResourceUse> uses = runtime.resources();
  EXPECT_TRUE(find(uses, "runtime patches (receivers, sub-triangles, map triangles)").allocated);
  EXPECT_GT(find(uses, "runtime patches (receivers, sub-triangles, map triangles)").cpu_bytes, 0u);
  EXPECT_TRUE(find(uses, "dynamic objects (triangles, receivers)").allocated);
  EXPECT_FALSE(find(uses, "index maps, geometry and reduction buffers").allocated);
  EXPECT_FALSE(find(uses, "patch delta buffer").allocated);

  const FrameStats stats = runtime.update(0);
  ASSERT_TRUE(stats.error.empty()) << stats.error;
  uses = runtime.resources();
  const ResourceUse& maps = find(uses, "index maps, geometry and reduction buffers");
  EXPECT_TRUE(maps.allocated);
  // At least one id (RG32UI) + depth (32F) layer at 128^2, plus the buffers.
  EXPECT_GT(maps.gpu_bytes, 128u * 128u * 12u);
  const ResourceUse& deltas = find(uses, "patch delta buffer");
  EXPECT_TRUE(deltas.allocated);
  EXPECT_EQ(deltas.gpu_bytes, uint64_t(runtime.patchDeltas().size()) * 16u);
  EXPECT_GT(find(uses, "emitter caches (point samples, form factors)").cpu_bytes, 0u);
  // No camera given: the view pass was never made.
  EXPECT_FALSE(find(uses, "camera id pass (importance)").allocated);

  RuntimeView view;
  view.position = {0, 1, 3.4f};
  view.look_at = {0, 1, 0};
  view.aspect = 2;
  ASSERT_TRUE(runtime.setView(view).ok());
  // The first update settled everything: the box moves, so this one has
  // work and ranks it for the view (an idle update makes no view pass).
  Mat4 moved;
  moved.m[12] = 0.05f;
  ASSERT_TRUE(runtime.setObjectTransform(runtime.objects().at(0), moved).ok());
  runtime.update(0);
  const std::vector<ResourceUse> viewed = runtime.resources();
  const ResourceUse& pass = find(viewed, "camera id pass (importance)");
  EXPECT_TRUE(pass.allocated);
  EXPECT_EQ(pass.gpu_bytes,
            uint64_t(settings.view_pass_width) * uint64_t(settings.view_pass_width / 2) * 12u);

  // A renderer over the runtime borrows the runtime's lightmaps and draws
  // the box with the probe grid.
  SceneRendererSettings renderer_settings;
  renderer_settings.width = 64;
  renderer_settings.height = 48;
  Expected<std::unique_ptr<SceneRenderer>> renderer =
      SceneRenderer::create(level.scene, level.bake, level.dir, &runtime, renderer_settings);
  ASSERT_TRUE(renderer.ok()) << renderer.status().message();
  ASSERT_TRUE((*renderer)->render(Camera{{0, 1, 3.4f}, {0, 1, 0}}, ShadingView::kRuntime).ok());
  const std::vector<ResourceUse> drawn = (*renderer)->resources();
  EXPECT_FALSE(find(drawn, "lightmap textures").allocated);
  EXPECT_NE(find(drawn, "lightmap textures").reason.find("borrowed"), std::string::npos);
  EXPECT_TRUE(find(drawn, "probe grid textures").allocated);
  EXPECT_TRUE(find(drawn, "dynamic object vertex buffer").allocated);
  EXPECT_TRUE(find(runtime.resources(), "delta surface buffers (per-pixel lookup)").allocated);
}

}  // namespace
}  // namespace svit
