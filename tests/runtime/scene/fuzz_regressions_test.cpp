// Inputs the libFuzzer targets of tests/fuzz found (docs/fuzzing.md), kept
// in tests/data/fuzz_regressions/ and named after the defect. Each must
// give a clean result: a failed Status of the expected code whose message
// names the file and the element, or a scene that keeps every promise of
// svit/scene.h (tests/fuzz/scene_contract.h, the fuzzers' own oracle).
// The memory errors themselves (heap overread, leak) show only under the
// sanitizers: rerun a file with its fuzz target to check those
// (build/fuzz/tests/fuzz/fuzz_glb tests/data/fuzz_regressions/<file>).

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <unistd.h>

#include "fuzz/scene_contract.h"
#include "scene_test_util.h"
#include "svit/level.h"
#include "svit/lightmap_image.h"
#include "svit/scene_summary.h"

namespace svit {
namespace {

using test::describe;
using test::messageHas;

std::string regressionPath(const std::string& name) {
  return test::dataPath("fuzz_regressions/" + name);
}

std::string readText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// A fresh directory for files a test writes, removed when it goes.
class TempDir {
 public:
  explicit TempDir(const std::string& tag)
      : dir_(std::filesystem::temp_directory_path() /
             ("svit_fuzz_regressions_" + tag + "_" + std::to_string(::getpid()))) {
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  ~TempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(dir_, ignored);
  }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }

 private:
  std::filesystem::path dir_;
};

// `text` with its only occurrence of `from` replaced by `to`, written to
// `name` in `dir`; returns the file's path.
std::string writeVariant(const TempDir& dir, const std::string& text, const std::string& from,
                         const std::string& to, const std::string& name) {
  const size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  EXPECT_EQ(text.find(from, at + 1), std::string::npos) << from << " occurs twice";
  std::string variant = text;
  if (at != std::string::npos) variant.replace(at, from.size(), to);
  const std::string path = dir.path(name);
  std::ofstream(path, std::ios::binary) << variant;
  return path;
}

// Loads a level that must load; checks the contract and what svit-info does with it.
void expectCleanLoad(const std::string& name) {
  const std::string path = regressionPath(name);
  Expected<Scene> scene = loadLevel(path);
  ASSERT_TRUE(scene.ok()) << describe(scene.status());
  EXPECT_EQ(fuzz::sceneContractViolation(*scene), "");
  const std::string json = summaryToJson(path, summarize(*scene));
  EXPECT_FALSE(json.empty());
}

// fuzz_glb: NORMAL (0, 1, -5.9e20) is finite, but its squared length
// overflows a float, so normalising in float gave (0, 0, -0).
TEST(FuzzRegressions, HugeNormalIsNormalisedInDouble) {
  expectCleanLoad("huge_normal_normalises_to_zero.glb");
  Expected<Scene> scene = loadLevel(regressionPath("huge_normal_normalises_to_zero.glb"));
  ASSERT_TRUE(scene.ok()) << describe(scene.status());
  // Vertex 2 of the quad's mesh holds it: (0, 1, -5.9e20) / |n| = (0, ~1.7e-21, -1).
  const Vec3& n = scene->meshes.at(0).normals.at(2);
  EXPECT_NEAR(n.z, -1.0f, 1e-6f);
  EXPECT_NEAR(n.y, 0.0f, 1e-6f);
}

// fuzz_gltf: an embedded PNG with a corrupt chunk type made stb_image's
// reason carry raw bytes into a warning, and summaryToJson (svit-info
// --json) threw nlohmann's invalid-UTF-8 error out of the library.
TEST(FuzzRegressions, UndecodableImageWarningIsPrintableAndSummarises) {
  expectCleanLoad("png_chunk_type_not_utf8.gltf");
  Expected<Scene> scene = loadLevel(regressionPath("png_chunk_type_not_utf8.gltf"));
  ASSERT_TRUE(scene.ok()) << describe(scene.status());
  EXPECT_TRUE(test::someWarningHas(
      scene->warnings, {"image 'checker' cannot be decoded", "the factor is used alone"}));
  for (const std::string& warning : scene->warnings) {
    for (char c : warning)
      EXPECT_TRUE(c >= 0x20 && c <= 0x7e) << "unprintable byte in: " << warning;
  }
  // Whatever a name holds, the JSON summary is written (bad bytes replaced).
  SceneSummary summary = summarize(*scene);
  summary.warnings.push_back(std::string("not UTF-8: \x85\xff"));
  EXPECT_NE(summaryToJson("level\xc3.gltf", summary).find("\"warnings\""), std::string::npos);
}

// fuzz_glb: image 0 lives in bufferView 6, bytes [136, 211) of a 174-byte
// buffer. tinygltf 2.7 hands such a view to the image callback unchecked,
// which read 37 bytes past the buffer (ASan heap-buffer-overflow).
TEST(FuzzRegressions, ImageBufferViewOutOfBoundsIsAnError) {
  const std::string path = regressionPath("image_buffer_view_out_of_bounds.glb");
  Expected<Scene> scene = loadLevel(path);
  ASSERT_FALSE(scene.ok());
  EXPECT_EQ(scene.status().code(), StatusCode::kInvalidInput) << describe(scene.status());
  EXPECT_TRUE(messageHas(scene.status(), {path, "image 0", "bufferView 6", "[136, 211)",
                                          "out of bounds", "174 bytes"}));
  // The same with the view starting past the buffer's end (bytes [504, 579)
  // of 348): tinygltf computed &data[504] for the callback.
  const std::string past = regressionPath("image_buffer_view_offset_past_buffer.glb");
  Expected<Scene> past_scene = loadLevel(past);
  ASSERT_FALSE(past_scene.ok());
  EXPECT_TRUE(messageHas(past_scene.status(),
                         {past, "image 0", "bufferView 6", "[504, 579)", "348 bytes"}));
  // Without textures the image bytes are never read: whatever else the file
  // has wrong (an animation accessor out of bounds too), it is not the image.
  LoadOptions no_textures;
  no_textures.load_textures = false;
  Expected<Scene> untextured = loadLevel(path, no_textures);
  ASSERT_FALSE(untextured.ok());
  EXPECT_FALSE(test::containsNoCase(untextured.status().message(), "image 0"))
      << describe(untextured.status());
}

// fuzz_gltf, fuzz_glb: accessor 3 (TEXCOORD_1, no bufferView, one sparse
// value) gives its sparse indices componentType 2561 (.gltf) or 5103 (.glb):
// 0-byte elements, and a division by zero in the bounds check (UBSan).
TEST(FuzzRegressions, SparseIndicesOfUnknownTypeAreAnError) {
  for (const char* name : {"sparse_indices_unknown_type.gltf", "sparse_indices_unknown_type.glb"}) {
    SCOPED_TRACE(name);
    const std::string path = regressionPath(name);
    Expected<Scene> scene = loadLevel(path);
    ASSERT_FALSE(scene.ok());
    EXPECT_EQ(scene.status().code(), StatusCode::kInvalidInput) << describe(scene.status());
    EXPECT_TRUE(messageHas(scene.status(),
                           {path, "TEXCOORD_1", "accessor 3", "sparse indices componentType",
                            "is not unsigned byte, short or int"}));
  }
}

// Found reading the fix above: signed byte indices (5120) were read as 4
// bytes each, and a count of 2^40 without a bufferView was allocated
// before anything checked it.
TEST(FuzzRegressions, SparseIndicesOfSignedTypeAndHugeUnbackedCountAreErrors) {
  const TempDir dir("sparse");
  const std::string text = readText(regressionPath("sparse_indices_unknown_type.gltf"));
  const std::string signed_path =
      writeVariant(dir, text, "\"componentType\": 2561", "\"componentType\": 5120",
                   "signed_sparse_indices.gltf");
  Expected<Scene> signed_indices = loadLevel(signed_path);
  ASSERT_FALSE(signed_indices.ok());
  EXPECT_TRUE(
      messageHas(signed_indices.status(), {"accessor 3", "sparse indices componentType 5120"}));

  const std::string accessor_3 = "\"count\": 4,\n      \"type\": \"VEC2\",\n      \"sparse\"";
  const std::string huge_path = writeVariant(
      dir, text, accessor_3, "\"count\": 1099511627776, \"type\": \"VEC2\", \"sparse\"",
      "huge_unbacked_count.gltf");
  Expected<Scene> huge = loadLevel(huge_path);
  ASSERT_FALSE(huge.ok());
  EXPECT_EQ(huge.status().code(), StatusCode::kInvalidInput) << describe(huge.status());
  EXPECT_TRUE(messageHas(
      huge.status(), {"accessor 3", "count 1099511627776 without a bufferView exceeds 16777216"}));
}

// fuzz_glb: material 'Glow' uses its emissive texture through TEXCOORD_2;
// the texture was dropped with a warning but texcoord 2 was left beside
// texture -1 (TextureRef promises a UV set of 0 or 1).
TEST(FuzzRegressions, UnsupportedTexcoordSetDropsTheTextureAndTheSet) {
  expectCleanLoad("unsupported_texcoord_set_kept.glb");
  Expected<Scene> scene = loadLevel(regressionPath("unsupported_texcoord_set_kept.glb"));
  ASSERT_TRUE(scene.ok()) << describe(scene.status());
  EXPECT_TRUE(test::someWarningHas(
      scene->warnings, {"material 'Glow'", "TEXCOORD_2 is not supported", "texture ignored"}));
  const Material& glow = scene->materials.at(1);
  EXPECT_EQ(glow.name, "Glow");
  EXPECT_EQ(glow.emissive_texture.texture, -1);
  EXPECT_EQ(glow.emissive_texture.texcoord, 0);
}

// fuzz_level_json's oracle (every error names the file loaded): an
// `exclude` that leaves no triangles failed with a message naming only the
// glTF ("good_quad.gltf: empty scene"), not the level file that did it.
TEST(FuzzRegressions, LevelThatExcludesEverythingNamesTheLevelFile) {
  const std::string path = regressionPath("exclude_everything.level.json");
  Expected<Scene> scene = loadLevel(path);
  ASSERT_FALSE(scene.ok());
  EXPECT_EQ(scene.status().code(), StatusCode::kInvalidInput) << describe(scene.status());
  EXPECT_TRUE(
      messageHas(scene.status(), {path, "good_quad.gltf", "empty scene: no triangles to light"}));
}

// fuzz_lightmap_exr: a page whose G plane holds a non-finite float was
// accepted and would have spread NaN through every lookup near it.
TEST(FuzzRegressions, NonFiniteLightmapTexelIsAnError) {
  const std::string path = regressionPath("non_finite_texel.exr");
  Expected<LightmapImage> image = readLightmapExr(path);
  ASSERT_FALSE(image.ok());
  EXPECT_EQ(image.status().code(), StatusCode::kInvalidInput) << describe(image.status());
  EXPECT_TRUE(messageHas(image.status(), {path, "texel (0, 8) channel G", "not finite"}));
}

// fuzz_lightmap_exr: a corrupt ZIP chunk fails the decode; tinyexr 1.0.1
// then leaked the channel planes it had allocated (LeakSanitizer). The
// error is what a normal build can check.
TEST(FuzzRegressions, CorruptLightmapChunkIsAnError) {
  const std::string path = regressionPath("corrupt_chunk_leaks_planes.exr");
  Expected<LightmapImage> image = readLightmapExr(path);
  ASSERT_FALSE(image.ok());
  EXPECT_EQ(image.status().code(), StatusCode::kInvalidInput) << describe(image.status());
  EXPECT_TRUE(messageHas(image.status(), {path, "not a readable EXR"}));
}

// fuzz_lightmap_exr: a chunkCount attribute of 825,193,984 for a 9-line
// image made tinyexr allocate a 6.6 GB offset table (libFuzzer OOM).
TEST(FuzzRegressions, ChunkCountBeyondTheFileIsAnError) {
  const std::string path = regressionPath("huge_chunk_count.exr");
  Expected<LightmapImage> image = readLightmapExr(path);
  ASSERT_FALSE(image.ok());
  EXPECT_EQ(image.status().code(), StatusCode::kInvalidInput) << describe(image.status());
  EXPECT_TRUE(
      messageHas(image.status(), {path, "chunkCount 825193984", "9 scanlines", "882 bytes"}));
}

// fuzz_lightmap_exr: a PIZ-compressed chunk too short for its Huffman
// table header; tinyexr 1.0.1's hufUncompress reads past it (ASan heap
// overread). svit-bake writes ZIP; PIZ is refused by name.
TEST(FuzzRegressions, PizCompressedPageIsRefused) {
  const std::string path = regressionPath("piz_huffman_overread.exr");
  Expected<LightmapImage> image = readLightmapExr(path);
  ASSERT_FALSE(image.ok());
  EXPECT_EQ(image.status().code(), StatusCode::kUnsupported) << describe(image.status());
  EXPECT_TRUE(messageHas(image.status(), {path, "compression 4", "PIZ is not read"}));
}

// readLightmapExr's size guards must not refuse real pages: an all-black
// page of the baker's largest default size (2048^2, 50 MB as floats)
// compresses about 930:1 and reads back.
TEST(FuzzRegressions, AllBlackFullSizePageStillReads) {
  const TempDir dir("exr");
  const std::string path = dir.path("lightmap-0.exr");
  LightmapImage black;
  black.width = black.height = 2048;
  black.rgb.assign(size_t(2048) * 2048 * 3, 0.0f);
  ASSERT_TRUE(writeLightmapExr(black, path).ok());
  Expected<LightmapImage> image = readLightmapExr(path);
  ASSERT_TRUE(image.ok()) << describe(image.status());
  EXPECT_EQ(image->rgb, black.rgb);
}

// fuzz_lightmap_exr (with assertions on, as Debian's libtinyexr has them): a
// header attribute 'type' naming no known part type hits assert(false) in
// tinyexr's ConvertHeader and aborts the process. The second file has two
// 'type' attributes, a bad one first and an empty one after it.
TEST(FuzzRegressions, UnknownPartTypeIsRejectedBeforeTinyexrAsserts) {
  for (const char* name : {"unknown_part_type_asserts.exr", "duplicate_part_type_asserts.exr"}) {
    SCOPED_TRACE(name);
    const std::string path = regressionPath(name);
    Expected<LightmapImage> image = readLightmapExr(path);
    ASSERT_FALSE(image.ok());
    EXPECT_EQ(image.status().code(), StatusCode::kUnsupported) << describe(image.status());
    EXPECT_TRUE(
        messageHas(image.status(), {path, "part type", "lightmap pages are scanline images"}));
  }
}

}  // namespace
}  // namespace svit
