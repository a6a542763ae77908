// Per-vertex interpolation of patch deltas: welded vertices take the
// area-weighted mean of the patches around them, computed on the GPU by
// delta_to_vertices.comp. Label `gl` (xvfb-run).

#include <gtest/gtest.h>

#include <epoxy/gl.h>

#include <vector>

#include <glm/glm.hpp>

#include "gl_test_context.h"
#include "scene_renderer_delta_interpolation.h"
#include "scene_renderer_static_mesh.h"

namespace svit {
namespace {

// Two triangles of a quad, with areas 1 and 3 m2 and one patch each: a
// shared corner takes 1/4 of the first patch and 3/4 of the second.
TEST(SceneRendererDeltas, SharedVerticesTakeTheAreaWeightedMeanOnTheGpu) {
  Scene scene;
  scene.source_path = "two_patches";
  scene.materials.push_back(Material{});
  Mesh mesh;
  // a=(0,0,0) b=(2,0,0) c=(0,0,-1) d=(2,0,-3): abc area 1, bdc area 3 (front up).
  mesh.positions = {{0, 0, 0}, {2, 0, 0}, {0, 0, -1}, {2, 0, -3}};
  mesh.normals = {{0, 1, 0}, {0, 1, 0}, {0, 1, 0}, {0, 1, 0}};
  mesh.indices = {0, 1, 2, 1, 3, 2};
  mesh.triangle_material = {0, 0};
  mesh.triangle_albedo = {{0.5f, 0.5f, 0.5f}, {0.5f, 0.5f, 0.5f}};
  mesh.triangle_emission = {{}, {}};
  mesh.triangle_source = {{0, 0}, {0, 1}};
  scene.meshes.push_back(mesh);
  Node node;
  node.mesh = 0;
  scene.nodes.push_back(node);
  Instance instance;
  instance.node = 0;
  instance.mesh = 0;
  scene.instances.push_back(instance);
  BakeData bake;
  bake.pages.push_back({4, 4, "lightmap-0.exr", 0});
  bake.triangle_uvs.push_back({0, 0, 0, {{0, 0}, {1, 0}, {0, 1}}});
  bake.triangle_uvs.push_back({0, 1, 0, {{1, 0}, {1, 1}, {0, 1}}});
  bake.patches.resize(2);
  bake.patches[0].first_element = 0, bake.patches[0].element_count = 2;
  bake.patches[1].first_element = 2, bake.patches[1].element_count = 2;
  bake.patch_elements = {0, 1, 2, 3};  // triangle t's sides -> patch t
  Expected<gl::StaticMesh> built = gl::buildStaticMesh(scene, bake);
  ASSERT_TRUE(built.ok()) << built.status().message();
  const gl::DeltaInterpolation& d = built->deltas;
  EXPECT_EQ(d.vertex_count, 4u);  // single-sided: front vertices only
  for (uint32_t v = 0; v < d.vertex_count; ++v) {
    float sum = 0;
    for (uint32_t i = d.offsets[v]; i < d.offsets[v + 1]; ++i) sum += d.weights[i];
    EXPECT_NEAR(sum, 1.0f, 1e-6f);
  }

  test::GlTestContext context;
  SVIT_REQUIRE_GL(context);
  Expected<gl::VertexDeltaInterpolator> interpolator = gl::VertexDeltaInterpolator::create(d);
  ASSERT_TRUE(interpolator.ok()) << interpolator.status().message();
  const float patch_deltas[8] = {4, 8, -4, 0, 0, 4, 8, 0};  // patch 0: (4, 8, -4); patch 1: (0, 4, 8)
  GLuint buffer = 0;
  glCreateBuffers(1, &buffer);
  glNamedBufferStorage(buffer, sizeof patch_deltas, patch_deltas, 0);
  interpolator->update(buffer);
  std::vector<float> out(size_t(d.vertex_count) * 4);
  glGetNamedBufferSubData(interpolator->vertexDeltaBuffer(), 0, GLsizeiptr(out.size() * sizeof(float)), out.data());
  glDeleteBuffers(1, &buffer);
  // Find each corner's welded vertex through the vertices (mesh order is
  // kept within the batch: triangle 0 then 1).
  ASSERT_EQ(built->vertices.size(), 6u);
  auto deltaOf = [&](size_t corner) {
    const uint32_t v = built->vertices[corner].delta_vertex[0];
    return glm::vec3(out[v * 4], out[v * 4 + 1], out[v * 4 + 2]);
  };
  const glm::vec3 only0 = deltaOf(0), shared_b = deltaOf(1), shared_c = deltaOf(2), only1 = deltaOf(4);
  EXPECT_NEAR(only0.x, 4, 1e-5f);
  EXPECT_NEAR(only0.y, 8, 1e-5f);
  EXPECT_NEAR(only0.z, -4, 1e-5f);
  EXPECT_NEAR(only1.x, 0, 1e-5f);
  EXPECT_NEAR(only1.y, 4, 1e-5f);
  EXPECT_NEAR(only1.z, 8, 1e-5f);
  for (const glm::vec3& shared : {shared_b, shared_c}) {
    EXPECT_NEAR(shared.x, 0.25f * 4 + 0.75f * 0, 1e-5f);
    EXPECT_NEAR(shared.y, 0.25f * 8 + 0.75f * 4, 1e-5f);
    EXPECT_NEAR(shared.z, 0.25f * -4 + 0.75f * 8, 1e-5f);
  }
}

}  // namespace
}  // namespace svit
