// Lightmap pages as EXR: texels and the "comments" attribute (why a page is
// black) round-trip through writeLightmapExr and readLightmapExr.

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "svit/lightmap_image.h"

namespace svit {
namespace {

LightmapImage twoByOne() {
  LightmapImage image;
  image.width = 2;
  image.height = 1;
  image.rgb = {1.5f, 2.5f, 3.5f, 1e5f, 0.0f, 0.25f};
  return image;
}

std::string tempPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("svit_lightmap_image_test_" + name)).string();
}

TEST(LightmapImage, CommentsRoundTripWithTheTexels) {
  LightmapImage image = twoByOne();
  image.comments = "svit: black: the level has no light source to bake (report.json)";
  const std::string path = tempPath("comments.exr");
  ASSERT_TRUE(writeLightmapExr(image, path).ok());
  Expected<LightmapImage> read = readLightmapExr(path);
  ASSERT_TRUE(read.ok()) << read.status().message();
  EXPECT_EQ(read->comments, image.comments);
  EXPECT_EQ(read->rgb, image.rgb);
}

TEST(LightmapImage, NoCommentsWrittenNoneRead) {
  const std::string path = tempPath("plain.exr");
  ASSERT_TRUE(writeLightmapExr(twoByOne(), path).ok());
  Expected<LightmapImage> read = readLightmapExr(path);
  ASSERT_TRUE(read.ok()) << read.status().message();
  EXPECT_TRUE(read->comments.empty());
  EXPECT_EQ(read->rgb, twoByOne().rgb);
}

}  // namespace
}  // namespace svit
