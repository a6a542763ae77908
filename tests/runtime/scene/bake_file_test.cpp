// bake.svit: round trip of every section (bitwise; shadow masks on their
// own bake), static-only files, and every validation path of the reader
// (truncation, corruption, magic, version, huge counts, bad indices) and of
// the writer (bad data refused, previous file untouched, no .tmp left).
//
// The tests that corrupt a file on purpose find sections with their own
// small parser of the documented layout ("SVITBAKE", u32 version, u32
// count, {u32 tag, u64 size, payload}..., u64 FNV-1a 64 of the rest) and,
// where the point is to get past the checksum, recompute it.

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include <unistd.h>

#include "scene_test_util.h"
#include "svit/bake_file.h"
#include "svit/level.h"

namespace svit {
namespace {

namespace fs = std::filesystem;
using test::describe;
using test::messageHas;

// A fresh directory per test, removed afterwards.
class BakeFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("svit_bake_file_test_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ignored;
    fs::remove_all(dir_, ignored);
  }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  fs::path dir_;
};

std::vector<uint8_t> readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void writeBytes(const std::string& path, const std::vector<uint8_t>& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

uint32_t getU32(const std::vector<uint8_t>& b, size_t at) {
  uint32_t v = 0;
  for (int i = 0; i < 4; ++i) v |= uint32_t(b.at(at + size_t(i))) << (8 * i);
  return v;
}
uint64_t getU64(const std::vector<uint8_t>& b, size_t at) {
  return uint64_t(getU32(b, at)) | uint64_t(getU32(b, at + 4)) << 32;
}
void putU32(std::vector<uint8_t>& b, size_t at, uint32_t v) {
  for (int i = 0; i < 4; ++i) b.at(at + size_t(i)) = uint8_t(v >> (8 * i));
}
void putU64(std::vector<uint8_t>& b, size_t at, uint64_t v) {
  putU32(b, at, uint32_t(v));
  putU32(b, at + 4, uint32_t(v >> 32));
}

// Rewrites the trailing checksum so the file gets past the checksum test.
void fixChecksum(std::vector<uint8_t>& b) {
  ASSERT_GE(b.size(), 24u);
  putU64(b, b.size() - 8, fnv1a64(b.data(), b.size() - 8));
}

struct SectionAt {
  std::string tag;
  size_t header = 0;   // offset of the tag
  size_t payload = 0;  // offset of the payload
  uint64_t size = 0;
};

// The section table of a well-formed file, by the documented layout.
std::vector<SectionAt> sectionTable(const std::vector<uint8_t>& b) {
  std::vector<SectionAt> table;
  const uint32_t count = getU32(b, 12);
  size_t at = 16;
  for (uint32_t i = 0; i < count; ++i) {
    SectionAt s;
    s.tag.assign(reinterpret_cast<const char*>(&b.at(at)), 4);
    s.header = at;
    s.size = getU64(b, at + 4);
    s.payload = at + 12;
    table.push_back(s);
    at = s.payload + size_t(s.size);
  }
  return table;
}

SectionAt findSection(const std::vector<uint8_t>& b, const std::string& tag) {
  for (const SectionAt& s : sectionTable(b)) {
    if (s.tag == tag) return s;
  }
  ADD_FAILURE() << "no section " << tag;
  return {};
}

// Values chosen to catch lossy encodings: negative zero, a denormal, the
// largest float, values that are not exact in decimal.
constexpr float kDenormal = 1.0e-40f;
constexpr float kHuge = std::numeric_limits<float>::max();
constexpr float kNan = std::numeric_limits<float>::quiet_NaN();

// A bake with every section filled: 2 pages, 4 triangles, 3 patches over 5
// elements, a 5-node cluster tree, 3 emitters, a 2-face proxy, 2x1x2 probes.
BakeData fullBake() {
  BakeData d;
  d.level_hash = 0x0123456789abcdefull;
  d.seed = 0xfedcba9876543210ull;
  d.pages = {{256, 128, "lightmap-0.exr", 0x1111222233334444ull},
             {64, 64, "lightmap-1.exr", 0xffffffffffffffffull}};
  for (uint32_t t = 0; t < 4; ++t) {
    BakeTriangleUv uv;
    uv.instance = t / 2;
    uv.mesh_triangle = t % 2;
    uv.page = t % 2;
    uv.uv[0] = {0.1f * float(t), -0.0f};
    uv.uv[1] = {1.0f / 3.0f, kDenormal};
    uv.uv[2] = {1.0f, 0.7f + float(t)};
    d.triangle_uvs.push_back(uv);
  }
  // Triangles 1 and 3 are double-sided with back lightmaps of their own.
  d.back_uvs = {{1, 1, {{0.5f, 0.25f}, {0.75f, 0.25f}, {0.5f, kDenormal}}},
                {3, 0, {{0.0f, 1.0f}, {1.0f / 3.0f, 0.5f}, {-0.0f, 0.125f}}}};
  d.has_runtime_sections = true;
  for (uint32_t p = 0; p < 3; ++p) {
    BakePatch patch;
    patch.centroid = {float(p), -0.0f, 1.0f / 7.0f};
    patch.normal = {0, 1, 0};
    patch.area_m2 = 0.25f + float(p);
    patch.albedo = {0.8f, 0.5f, 0.1f};
    patch.emission = {p == 2 ? 1000.0f : 0.0f, kDenormal, 0};
    patch.radiosity = {kHuge, 3.14159265f, 2.0f / 3.0f};
    patch.first_element = p == 0 ? 0 : p + 1;  // [0,2) [2,3) [3,5)
    patch.element_count = p == 0 ? 2 : (p == 1 ? 1 : 2);
    d.patches.push_back(patch);
  }
  d.patch_elements = {0, 1, 2, 5, 7};  // triangle * 2 + side, triangles < 4
  // 0 root (children 1, 2); 1 leaf patch 0; 2 (children 3, 4); 3 leaf patch 1; 4 leaf patch 2.
  d.clusters.resize(5);
  d.clusters[0] = {-1, {1, 2}, -1, {{-1, -1, -1}, {1, 1, 1}}, 3.75f};
  d.clusters[1] = {0, {-1, -1}, 0, {{-1, -1, -1}, {0, 0, 0}}, 0.25f};
  d.clusters[2] = {0, {3, 4}, -1, {{0, 0, 0}, {1, 1, 1}}, 3.5f};
  d.clusters[3] = {2, {-1, -1}, 1, {{0, 0, 0}, {0.5f, 0.5f, 0.5f}}, 1.25f};
  d.clusters[4] = {2, {-1, -1}, 2, {{0.5f, 0.5f, 0.5f}, {1, 1, 1}}, 2.25f};
  BakeEmitter light;
  light.kind = BakeEmitter::Kind::kLight;
  light.index = 0;
  light.flux = {100, 90, 80};
  light.patches = {0, 1, 2};
  light.factors = {0.25f, 0.125f, 1.0f / 3.0f};
  BakeEmitter sun;
  sun.kind = BakeEmitter::Kind::kSun;
  sun.flux = {kHuge, 0, -0.0f};
  BakeEmitter panel;
  panel.kind = BakeEmitter::Kind::kPatch;
  panel.index = 2;
  panel.flux = {785.398f, 785.398f, 785.398f};
  panel.patches = {0, 1};
  panel.factors = {kDenormal, 0.5f};
  d.emitters = {light, sun, panel};
  d.proxy.positions = {{0, 0, 0}, {1, 0, 0}, {1, 0, -1}, {0, 0, -1.0f / 3.0f}};
  d.proxy.indices = {0, 1, 2, 0, 2, 3};
  d.proxy.face_patch = {0, 2};
  d.probes.origin = {-0.5f, 0.25f, kDenormal};
  d.probes.spacing = {0.5f, 1.0f / 3.0f, 2.0f};
  d.probes.dims[0] = 2;
  d.probes.dims[1] = 1;
  d.probes.dims[2] = 2;
  for (int i = 0; i < 4 * 12; ++i) d.probes.sh.push_back(float(i) * 0.1f - 1.0f);
  return d;
}

BakeData staticBake() {
  BakeData d = fullBake();
  d.has_runtime_sections = false;
  d.patches.clear();
  d.patch_elements.clear();
  d.clusters.clear();
  d.emitters.clear();
  d.proxy = {};
  d.probes = {};
  d.back_uvs.clear();
  return d;
}

// Index of a texel's value in a mask page (BakeShadowMasks::pages order:
// layer, row, texel, the 4 channels of the layer).
size_t maskIndex(const BakeLightmapPage& page, uint32_t x, uint32_t y, uint32_t channel) {
  const size_t layer = channel / 4;
  return ((layer * page.height + y) * page.width + x) * 4 + channel % 4;
}

// fullBake() plus shadow masks: 3 more point lights (emitters 3..5) and 5
// masked lights over 2 channels. Channel 0 holds emitters 0, 3, 4 (owners
// 1, 2, 3), lighting the left, middle and right thirds of each page;
// channel 1 the sun (emitter 1, owner 1) over the top half and emitter 5
// (owner 2, a cellar lamp) over the bottom half. Some texels no light of a
// channel reaches (owner 0); channels 2 and 3 of the one layer are unused (0).
BakeData maskedBake() {
  BakeData d = fullBake();
  for (uint32_t light = 1; light <= 3; ++light) {
    BakeEmitter lamp;
    lamp.kind = BakeEmitter::Kind::kLight;
    lamp.index = light;
    lamp.flux = {50, 50, 50};
    lamp.patches = {light - 1};
    lamp.factors = {0.5f};
    d.emitters.push_back(lamp);
  }
  d.masks.lights = {{0, 0, 1}, {1, 1, 1}, {3, 0, 2}, {4, 0, 3}, {5, 1, 2}};
  d.masks.channels = 2;
  for (const BakeLightmapPage& page : d.pages) {
    std::vector<uint16_t> values(size_t(d.masks.layers()) * page.width * page.height * 4, 0);
    for (uint32_t y = 0; y < page.height; ++y) {
      for (uint32_t x = 0; x < page.width; ++x) {
        const uint32_t visibility = (x * 7 + y * 3) & 255;  // 0..255, both ends hit
        const uint32_t third = x * 3 / page.width;          // owner - 1 in channel 0
        const bool dark = (x + y) % 5 == 0;                 // no channel-0 light reaches it
        values[maskIndex(page, x, y, 0)] =
            uint16_t(dark ? visibility : (third + 1) << 8 | visibility);
        const uint32_t half_owner = y < page.height / 2 ? 1 : 2;
        values[maskIndex(page, x, y, 1)] = uint16_t(half_owner << 8 | (255 - visibility));
      }
    }
    d.masks.pages.push_back(std::move(values));
  }
  return d;
}

// An SMSK payload by the documented layout: u32 light count, {u32 emitter,
// u32 channel, u32 owner}..., u32 channels, u32 page count, {u64 value
// count, u16 values}...
std::vector<uint8_t> shadowMaskPayload(const BakeShadowMasks& masks) {
  std::vector<uint8_t> b;
  auto u32 = [&](uint32_t v) {
    for (int i = 0; i < 4; ++i) b.push_back(uint8_t(v >> (8 * i)));
  };
  u32(uint32_t(masks.lights.size()));
  for (const BakeMaskedLight& light : masks.lights) {
    u32(light.emitter);
    u32(light.channel);
    u32(light.owner);
  }
  u32(masks.channels);
  u32(uint32_t(masks.pages.size()));
  for (const std::vector<uint16_t>& page : masks.pages) {
    u32(uint32_t(page.size()));
    u32(uint32_t(uint64_t(page.size()) >> 32));
    for (uint16_t v : page) {
      b.push_back(uint8_t(v));
      b.push_back(uint8_t(v >> 8));
    }
  }
  return b;
}

// Puts `payload` in the file's SMSK section (appended as the last section
// when there is none), fixing the section size, count and checksum.
void replaceShadowMasks(std::vector<uint8_t>& b, const std::vector<uint8_t>& payload) {
  for (const SectionAt& s : sectionTable(b)) {
    if (s.tag != "SMSK") continue;
    b.erase(b.begin() + std::ptrdiff_t(s.payload),
            b.begin() + std::ptrdiff_t(s.payload + size_t(s.size)));
    b.insert(b.begin() + std::ptrdiff_t(s.payload), payload.begin(), payload.end());
    putU64(b, s.header + 4, payload.size());
    fixChecksum(b);
    return;
  }
  std::vector<uint8_t> section = {'S', 'M', 'S', 'K', 0, 0, 0, 0, 0, 0, 0, 0};
  putU64(section, 4, payload.size());
  section.insert(section.end(), payload.begin(), payload.end());
  b.insert(b.end() - 8, section.begin(), section.end());
  putU32(b, 12, getU32(b, 12) + 1);
  fixChecksum(b);
}

uint32_t bits(float v) { return std::bit_cast<uint32_t>(v); }

// Bitwise equality of floats (so -0 vs 0 and denormals count), exact for the rest.
void expectSameFloat(float a, float b, const std::string& what) {
  EXPECT_EQ(bits(a), bits(b)) << what << ": " << a << " vs " << b;
}
void expectSame(const Vec2& a, const Vec2& b, const std::string& what) {
  expectSameFloat(a.x, b.x, what + ".x");
  expectSameFloat(a.y, b.y, what + ".y");
}
void expectSame(const Vec3& a, const Vec3& b, const std::string& what) {
  expectSameFloat(a.x, b.x, what + ".x");
  expectSameFloat(a.y, b.y, what + ".y");
  expectSameFloat(a.z, b.z, what + ".z");
}
void expectSame(const Rgb& a, const Rgb& b, const std::string& what) {
  expectSameFloat(a.r, b.r, what + ".r");
  expectSameFloat(a.g, b.g, what + ".g");
  expectSameFloat(a.b, b.b, what + ".b");
}

void expectSameBake(const BakeData& a, const BakeData& b) {
  EXPECT_EQ(a.version, b.version);
  EXPECT_EQ(a.level_hash, b.level_hash);
  EXPECT_EQ(a.seed, b.seed);
  ASSERT_EQ(a.pages.size(), b.pages.size());
  for (size_t i = 0; i < a.pages.size(); ++i) {
    EXPECT_EQ(a.pages[i].width, b.pages[i].width);
    EXPECT_EQ(a.pages[i].height, b.pages[i].height);
    EXPECT_EQ(a.pages[i].file, b.pages[i].file);
    EXPECT_EQ(a.pages[i].texel_hash, b.pages[i].texel_hash);
  }
  ASSERT_EQ(a.back_uvs.size(), b.back_uvs.size());
  for (size_t i = 0; i < a.back_uvs.size(); ++i) {
    EXPECT_EQ(a.back_uvs[i].triangle, b.back_uvs[i].triangle);
    EXPECT_EQ(a.back_uvs[i].page, b.back_uvs[i].page);
    for (int k = 0; k < 3; ++k) expectSame(a.back_uvs[i].uv[k], b.back_uvs[i].uv[k], "back uv");
  }
  ASSERT_EQ(a.triangle_uvs.size(), b.triangle_uvs.size());
  for (size_t i = 0; i < a.triangle_uvs.size(); ++i) {
    const std::string w = "triangle " + std::to_string(i);
    EXPECT_EQ(a.triangle_uvs[i].instance, b.triangle_uvs[i].instance) << w;
    EXPECT_EQ(a.triangle_uvs[i].mesh_triangle, b.triangle_uvs[i].mesh_triangle) << w;
    EXPECT_EQ(a.triangle_uvs[i].page, b.triangle_uvs[i].page) << w;
    for (int k = 0; k < 3; ++k)
      expectSame(a.triangle_uvs[i].uv[k], b.triangle_uvs[i].uv[k], w + " uv");
  }
  EXPECT_EQ(a.has_runtime_sections, b.has_runtime_sections);
  ASSERT_EQ(a.patches.size(), b.patches.size());
  for (size_t i = 0; i < a.patches.size(); ++i) {
    const std::string w = "patch " + std::to_string(i);
    expectSame(a.patches[i].centroid, b.patches[i].centroid, w + " centroid");
    expectSame(a.patches[i].normal, b.patches[i].normal, w + " normal");
    expectSameFloat(a.patches[i].area_m2, b.patches[i].area_m2, w + " area");
    expectSame(a.patches[i].albedo, b.patches[i].albedo, w + " albedo");
    expectSame(a.patches[i].emission, b.patches[i].emission, w + " emission");
    expectSame(a.patches[i].radiosity, b.patches[i].radiosity, w + " radiosity");
    EXPECT_EQ(a.patches[i].first_element, b.patches[i].first_element) << w;
    EXPECT_EQ(a.patches[i].element_count, b.patches[i].element_count) << w;
  }
  EXPECT_EQ(a.patch_elements, b.patch_elements);
  ASSERT_EQ(a.clusters.size(), b.clusters.size());
  for (size_t i = 0; i < a.clusters.size(); ++i) {
    const std::string w = "cluster " + std::to_string(i);
    EXPECT_EQ(a.clusters[i].parent, b.clusters[i].parent) << w;
    EXPECT_EQ(a.clusters[i].child[0], b.clusters[i].child[0]) << w;
    EXPECT_EQ(a.clusters[i].child[1], b.clusters[i].child[1]) << w;
    EXPECT_EQ(a.clusters[i].patch, b.clusters[i].patch) << w;
    expectSame(a.clusters[i].bounds.min, b.clusters[i].bounds.min, w + " min");
    expectSame(a.clusters[i].bounds.max, b.clusters[i].bounds.max, w + " max");
    expectSameFloat(a.clusters[i].area_m2, b.clusters[i].area_m2, w + " area");
  }
  ASSERT_EQ(a.emitters.size(), b.emitters.size());
  for (size_t i = 0; i < a.emitters.size(); ++i) {
    const std::string w = "emitter " + std::to_string(i);
    EXPECT_EQ(a.emitters[i].kind, b.emitters[i].kind) << w;
    EXPECT_EQ(a.emitters[i].index, b.emitters[i].index) << w;
    expectSame(a.emitters[i].flux, b.emitters[i].flux, w + " flux");
    EXPECT_EQ(a.emitters[i].patches, b.emitters[i].patches) << w;
    ASSERT_EQ(a.emitters[i].factors.size(), b.emitters[i].factors.size()) << w;
    for (size_t k = 0; k < a.emitters[i].factors.size(); ++k) {
      expectSameFloat(a.emitters[i].factors[k], b.emitters[i].factors[k], w + " factor");
    }
  }
  ASSERT_EQ(a.proxy.positions.size(), b.proxy.positions.size());
  for (size_t i = 0; i < a.proxy.positions.size(); ++i)
    expectSame(a.proxy.positions[i], b.proxy.positions[i], "proxy");
  EXPECT_EQ(a.proxy.indices, b.proxy.indices);
  EXPECT_EQ(a.proxy.face_patch, b.proxy.face_patch);
  expectSame(a.probes.origin, b.probes.origin, "probe origin");
  expectSame(a.probes.spacing, b.probes.spacing, "probe spacing");
  for (int k = 0; k < 3; ++k) EXPECT_EQ(a.probes.dims[k], b.probes.dims[k]);
  ASSERT_EQ(a.probes.sh.size(), b.probes.sh.size());
  for (size_t i = 0; i < a.probes.sh.size(); ++i)
    expectSameFloat(a.probes.sh[i], b.probes.sh[i], "sh");
  ASSERT_EQ(a.masks.lights.size(), b.masks.lights.size());
  for (size_t i = 0; i < a.masks.lights.size(); ++i) {
    const std::string w = "masked light " + std::to_string(i);
    EXPECT_EQ(a.masks.lights[i].emitter, b.masks.lights[i].emitter) << w;
    EXPECT_EQ(a.masks.lights[i].channel, b.masks.lights[i].channel) << w;
    EXPECT_EQ(a.masks.lights[i].owner, b.masks.lights[i].owner) << w;
  }
  EXPECT_EQ(a.masks.channels, b.masks.channels);
  ASSERT_EQ(a.masks.pages.size(), b.masks.pages.size());
  for (size_t p = 0; p < a.masks.pages.size(); ++p)
    EXPECT_TRUE(a.masks.pages[p] == b.masks.pages[p]) << "mask page " << p << " differs";
}

TEST_F(BakeFileTest, RoundTripOfEverySectionIsBitwiseEqual) {
  const BakeData written = fullBake();
  const std::string file = path("bake.svit");
  const Status s = writeBakeFile(written, file);
  ASSERT_TRUE(s.ok()) << describe(s);
  EXPECT_FALSE(fs::exists(file + ".tmp"));
  Expected<BakeData> read = readBakeFile(file);
  ASSERT_TRUE(read.ok()) << describe(read.status());
  expectSameBake(written, *read);

  // The layout: magic, version 1, 9 sections in the documented order.
  const std::vector<uint8_t> bytes = readBytes(file);
  ASSERT_GE(bytes.size(), 24u);
  EXPECT_EQ(std::string(reinterpret_cast<const char*>(bytes.data()), 8), "SVITBAKE");
  EXPECT_EQ(getU32(bytes, 8), kBakeFileVersion);
  std::vector<std::string> tags;
  for (const SectionAt& section : sectionTable(bytes)) tags.push_back(section.tag);
  EXPECT_EQ(tags, (std::vector<std::string>{"HEAD", "PAGE", "TUVS", "BUVS", "PTCH", "PELM", "CLST",
                                            "EMIT", "PRXY", "PROB"}));
  EXPECT_EQ(findBackUv(*read, 3)->page, 0u);
  EXPECT_EQ(findBackUv(*read, 2), nullptr);
  EXPECT_EQ(getU64(bytes, bytes.size() - 8), fnv1a64(bytes.data(), bytes.size() - 8));

  // Writing is deterministic: the same data gives the same bytes.
  ASSERT_TRUE(writeBakeFile(*read, path("again.svit")).ok());
  EXPECT_EQ(readBytes(path("again.svit")), bytes);
}

TEST_F(BakeFileTest, ShadowMasksRoundTripBitwiseAsTheLastSection) {
  const BakeData written = maskedBake();
  const std::string file = path("bake.svit");
  const Status s = writeBakeFile(written, file);
  ASSERT_TRUE(s.ok()) << describe(s);
  Expected<BakeData> read = readBakeFile(file);
  ASSERT_TRUE(read.ok()) << describe(read.status());
  expectSameBake(written, *read);

  // SMSK follows the runtime sections, and its payload is the documented layout.
  const std::vector<uint8_t> bytes = readBytes(file);
  std::vector<std::string> tags;
  for (const SectionAt& section : sectionTable(bytes)) tags.push_back(section.tag);
  EXPECT_EQ(tags, (std::vector<std::string>{"HEAD", "PAGE", "TUVS", "BUVS", "PTCH", "PELM", "CLST",
                                            "EMIT", "PRXY", "PROB", "SMSK"}));
  const SectionAt smsk = findSection(bytes, "SMSK");
  const std::vector<uint8_t> want = shadowMaskPayload(written.masks);
  ASSERT_EQ(smsk.size, want.size());
  EXPECT_TRUE(std::equal(want.begin(), want.end(), bytes.begin() + std::ptrdiff_t(smsk.payload)));
  // 4 + 5 x 12 + 4 + 4 + (8 + 256 x 128 x 4 x 2) + (8 + 64 x 64 x 4 x 2) bytes.
  EXPECT_EQ(smsk.size, 72u + 8u + 262144u + 8u + 32768u);
  const std::vector<BakeSectionSize> sizes = bakeSectionSizes(written);
  ASSERT_FALSE(sizes.empty());
  EXPECT_EQ(sizes.back().tag, "SMSK");
  EXPECT_EQ(sizes.back().bytes, smsk.size);

  // Deterministic, and a bake that masks no light writes no SMSK.
  ASSERT_TRUE(writeBakeFile(*read, path("again.svit")).ok());
  EXPECT_EQ(readBytes(path("again.svit")), bytes);
  BakeData unmasked = written;
  unmasked.masks = {};
  ASSERT_TRUE(writeBakeFile(unmasked, path("unmasked.svit")).ok());
  for (const SectionAt& section : sectionTable(readBytes(path("unmasked.svit"))))
    EXPECT_NE(section.tag, "SMSK");
}

TEST_F(BakeFileTest, StaticOnlyBakeWritesNoRuntimeSections) {
  const std::string full = path("full.svit"), stat = path("static.svit");
  ASSERT_TRUE(writeBakeFile(fullBake(), full).ok());
  const BakeData written = staticBake();
  const Status s = writeBakeFile(written, stat);
  ASSERT_TRUE(s.ok()) << describe(s);
  EXPECT_LT(fs::file_size(stat), fs::file_size(full));
  const std::vector<uint8_t> bytes = readBytes(stat);
  std::vector<std::string> tags;
  for (const SectionAt& section : sectionTable(bytes)) tags.push_back(section.tag);
  EXPECT_EQ(tags, (std::vector<std::string>{"HEAD", "PAGE", "TUVS"}));

  Expected<BakeData> read = readBakeFile(stat);
  ASSERT_TRUE(read.ok()) << describe(read.status());
  EXPECT_FALSE(read->has_runtime_sections);
  EXPECT_TRUE(read->patches.empty());
  EXPECT_TRUE(read->patch_elements.empty());
  EXPECT_TRUE(read->clusters.empty());
  EXPECT_TRUE(read->emitters.empty());
  EXPECT_TRUE(read->proxy.positions.empty());
  EXPECT_TRUE(read->proxy.indices.empty());
  EXPECT_TRUE(read->probes.sh.empty());
  expectSameBake(written, *read);
}

TEST_F(BakeFileTest, RuntimeDataWithoutTheFlagIsRefusedNotDropped) {
  BakeData data = fullBake();
  data.has_runtime_sections = false;
  const Status s = writeBakeFile(data, path("bake.svit"));
  EXPECT_EQ(s.code(), StatusCode::kInvalidInput) << describe(s);
  EXPECT_TRUE(messageHas(s, {"bake.svit", "has_runtime_sections", "PTCH"}));
  EXPECT_FALSE(fs::exists(path("bake.svit")));
}

TEST_F(BakeFileTest, TruncatedFileIsRejectedAtEveryCut) {
  const std::string good = path("good.svit");
  ASSERT_TRUE(writeBakeFile(fullBake(), good).ok());
  const std::vector<uint8_t> bytes = readBytes(good);
  const SectionAt ptch = findSection(bytes, "PTCH");
  const SectionAt prob = findSection(bytes, "PROB");
  struct Cut {
    size_t size;
    const char* where;
  };
  const Cut cuts[] = {
      {0, "empty file"},
      {5, "inside the magic"},
      {12, "inside the header"},
      {20, "inside the first section header"},
      {ptch.payload + 30, "inside PTCH"},
      {prob.payload + size_t(prob.size) - 3, "inside the last section"},
      {bytes.size() - 8, "before the checksum"},
      {bytes.size() - 1, "inside the checksum"},
  };
  for (const Cut& cut : cuts) {
    SCOPED_TRACE(cut.where);
    const std::string file = path("cut.svit");
    writeBytes(file, std::vector<uint8_t>(bytes.begin(), bytes.begin() + std::ptrdiff_t(cut.size)));
    Expected<BakeData> read = readBakeFile(file);
    ASSERT_FALSE(read.ok());
    EXPECT_EQ(read.status().code(), StatusCode::kInvalidInput) << describe(read.status());
    EXPECT_TRUE(messageHas(read.status(), {"cut.svit"}));
    EXPECT_TRUE(test::containsNoCase(read.status().message(), "truncated") ||
                test::containsNoCase(read.status().message(), "checksum"))
        << describe(read.status());
  }
  // The cut inside PTCH names the section and the byte counts.
  writeBytes(
      path("cut.svit"),
      std::vector<uint8_t>(bytes.begin(), bytes.begin() + std::ptrdiff_t(ptch.payload + 30)));
  const Status s = readBakeFile(path("cut.svit")).status();
  EXPECT_TRUE(
      messageHas(s, {"truncated: section PTCH needs " + std::to_string(ptch.size) + " bytes"}))
      << describe(s);
}

TEST_F(BakeFileTest, FlippedByteIsChecksumMismatch) {
  const std::string good = path("good.svit");
  ASSERT_TRUE(writeBakeFile(fullBake(), good).ok());
  const std::vector<uint8_t> bytes = readBytes(good);
  const SectionAt tuvs = findSection(bytes, "TUVS");
  const SectionAt prob = findSection(bytes, "PROB");
  for (size_t at : {tuvs.payload + 7, prob.payload + 40, bytes.size() - 1}) {
    SCOPED_TRACE("byte " + std::to_string(at));
    std::vector<uint8_t> bad = bytes;
    bad[at] ^= 0x10;
    writeBytes(path("flipped.svit"), bad);
    const Status s = readBakeFile(path("flipped.svit")).status();
    EXPECT_EQ(s.code(), StatusCode::kInvalidInput) << describe(s);
    EXPECT_TRUE(messageHas(s, {"flipped.svit", "checksum mismatch"}));
  }
}

TEST_F(BakeFileTest, WrongMagicIsRejected) {
  ASSERT_TRUE(writeBakeFile(fullBake(), path("good.svit")).ok());
  std::vector<uint8_t> bytes = readBytes(path("good.svit"));
  std::memcpy(bytes.data(), "GLTFBAKE", 8);
  writeBytes(path("magic.svit"), bytes);
  const Status s = readBakeFile(path("magic.svit")).status();
  EXPECT_EQ(s.code(), StatusCode::kInvalidInput) << describe(s);
  EXPECT_TRUE(messageHas(s, {"magic.svit", "not a bake file", "GLTFBAKE"}));

  // Not even a bake-sized file: a text file.
  writeBytes(path("text.svit"), {'h', 'i', '\n'});
  const Status t = readBakeFile(path("text.svit")).status();
  EXPECT_EQ(t.code(), StatusCode::kInvalidInput) << describe(t);
  EXPECT_TRUE(messageHas(t, {"not a bake file"}));
}

TEST_F(BakeFileTest, OtherVersionIsRejectedEvenWithAGoodChecksum) {
  ASSERT_TRUE(writeBakeFile(fullBake(), path("good.svit")).ok());
  std::vector<uint8_t> bytes = readBytes(path("good.svit"));
  putU32(bytes, 8, 7);
  fixChecksum(bytes);  // so the version check itself is what fails
  writeBytes(path("v7.svit"), bytes);
  const Status s = readBakeFile(path("v7.svit")).status();
  EXPECT_EQ(s.code(), StatusCode::kInvalidInput) << describe(s);
  EXPECT_TRUE(messageHas(s, {"v7.svit: bake file version 7, this build reads version 1"}));

  // And the writer refuses data that claims another version.
  BakeData data = fullBake();
  data.version = 2;
  const Status w = writeBakeFile(data, path("v2.svit"));
  EXPECT_EQ(w.code(), StatusCode::kInvalidInput) << describe(w);
  EXPECT_TRUE(messageHas(w, {"version 2"}));
  EXPECT_FALSE(fs::exists(path("v2.svit")));
}

TEST_F(BakeFileTest, UnknownSectionIsSkipped) {
  ASSERT_TRUE(writeBakeFile(fullBake(), path("good.svit")).ok());
  std::vector<uint8_t> bytes = readBytes(path("good.svit"));
  // Append a section "XTRA" of 5 bytes after the last one (before the checksum).
  const std::vector<uint8_t> extra = {'X', 'T', 'R', 'A', 5, 0, 0, 0, 0, 0, 0, 0, 1, 2, 3, 4, 5};
  bytes.insert(bytes.end() - 8, extra.begin(), extra.end());
  putU32(bytes, 12, getU32(bytes, 12) + 1);
  fixChecksum(bytes);
  writeBytes(path("extra.svit"), bytes);
  Expected<BakeData> read = readBakeFile(path("extra.svit"));
  ASSERT_TRUE(read.ok()) << describe(read.status());
  expectSameBake(fullBake(), *read);
}

TEST_F(BakeFileTest, HugeCountIsAnErrorNotAnAllocation) {
  ASSERT_TRUE(writeBakeFile(fullBake(), path("good.svit")).ok());
  const std::vector<uint8_t> good = readBytes(path("good.svit"));
  for (const char* tag : {"PAGE", "TUVS", "PTCH", "PELM", "CLST", "EMIT", "PRXY"}) {
    SCOPED_TRACE(tag);
    std::vector<uint8_t> bytes = good;
    putU32(bytes, findSection(bytes, tag).payload, 0xffffffffu);  // the element count
    fixChecksum(bytes);
    writeBytes(path("huge.svit"), bytes);
    const Status s = readBakeFile(path("huge.svit")).status();
    EXPECT_EQ(s.code(), StatusCode::kInvalidInput) << describe(s);
    EXPECT_TRUE(messageHas(s, {"truncated: section", tag}));
  }
  // A section size beyond the end of the file.
  std::vector<uint8_t> bytes = good;
  putU64(bytes, findSection(bytes, "CLST").header + 4, 0xffffffffffffull);
  fixChecksum(bytes);
  writeBytes(path("huge.svit"), bytes);
  const Status s = readBakeFile(path("huge.svit")).status();
  EXPECT_EQ(s.code(), StatusCode::kInvalidInput) << describe(s);
  EXPECT_TRUE(messageHas(s, {"truncated: section CLST needs 281474976710655 bytes"}));
}

TEST_F(BakeFileTest, HugeShadowMaskCountIsAnErrorNotAnAllocation) {
  ASSERT_TRUE(writeBakeFile(maskedBake(), path("good.svit")).ok());
  const std::vector<uint8_t> good = readBytes(path("good.svit"));
  const size_t smsk = findSection(good, "SMSK").payload;
  const size_t page_count_at = smsk + 4 + 5 * 12 + 4;
  struct Field {
    const char* what;
    size_t at;
    bool is_u64;
  };
  const Field fields[] = {{"light count", smsk, false},
                          {"page count", page_count_at, false},
                          {"page 0 value count", page_count_at + 4, true},
                          {"page 1 value count", page_count_at + 4 + 8 + 256 * 128 * 4 * 2, true}};
  for (const Field& field : fields) {
    SCOPED_TRACE(field.what);
    std::vector<uint8_t> bytes = good;
    if (field.is_u64) {
      putU64(bytes, field.at, 0x7fffffffffffffffull);
    } else {
      putU32(bytes, field.at, 0xffffffffu);
    }
    fixChecksum(bytes);
    writeBytes(path("huge.svit"), bytes);
    const Status s = readBakeFile(path("huge.svit")).status();
    EXPECT_EQ(s.code(), StatusCode::kInvalidInput) << describe(s);
    EXPECT_TRUE(messageHas(s, {"huge.svit", "truncated: section SMSK"}));
  }
}

TEST_F(BakeFileTest, ReaderValidatesIndicesInTheFile) {
  ASSERT_TRUE(writeBakeFile(fullBake(), path("good.svit")).ok());
  const std::vector<uint8_t> good = readBytes(path("good.svit"));
  {
    // Cluster 0's first child (record: count u32, then parent i32, child0 i32...).
    std::vector<uint8_t> bytes = good;
    putU32(bytes, findSection(bytes, "CLST").payload + 4 + 4, 77);
    fixChecksum(bytes);
    writeBytes(path("bad.svit"), bytes);
    const Status s = readBakeFile(path("bad.svit")).status();
    EXPECT_EQ(s.code(), StatusCode::kInvalidInput) << describe(s);
    EXPECT_TRUE(messageHas(s, {"bad.svit", "CLST", "cluster 0", "77"}));
  }
  {
    // A NaN in the first probe SH float (after origin, spacing, dims, count).
    std::vector<uint8_t> bytes = good;
    putU32(bytes, findSection(bytes, "PROB").payload + 12 + 12 + 12 + 4, 0x7fc00000u);
    fixChecksum(bytes);
    writeBytes(path("bad.svit"), bytes);
    const Status s = readBakeFile(path("bad.svit")).status();
    EXPECT_EQ(s.code(), StatusCode::kInvalidInput) << describe(s);
    EXPECT_TRUE(messageHas(s, {"PROB", "probe 0", "not finite"}));
  }
  {
    // One runtime section renamed: the set is incomplete.
    std::vector<uint8_t> bytes = good;
    std::memcpy(&bytes[findSection(bytes, "EMIT").header], "EMIX", 4);
    fixChecksum(bytes);
    writeBytes(path("bad.svit"), bytes);
    const Status s = readBakeFile(path("bad.svit")).status();
    EXPECT_EQ(s.code(), StatusCode::kInvalidInput) << describe(s);
    EXPECT_TRUE(messageHas(s, {"runtime sections incomplete", "EMIT"}));
  }
  {
    // A required section renamed.
    std::vector<uint8_t> bytes = good;
    std::memcpy(&bytes[findSection(bytes, "TUVS").header], "TUVX", 4);
    fixChecksum(bytes);
    writeBytes(path("bad.svit"), bytes);
    const Status s = readBakeFile(path("bad.svit")).status();
    EXPECT_EQ(s.code(), StatusCode::kInvalidInput) << describe(s);
    EXPECT_TRUE(messageHas(s, {"missing", "TUVS"}));
  }
}

// One broken field per case; the writer must refuse it, name the section
// and the offending index, and leave the previous file byte-identical.
TEST_F(BakeFileTest, WriterRefusesBadDataAndKeepsThePreviousFile) {
  const std::string file = path("bake.svit");
  ASSERT_TRUE(writeBakeFile(fullBake(), file).ok());
  const std::vector<uint8_t> before = readBytes(file);
  struct Case {
    const char* what;
    void (*breakIt)(BakeData&);
    std::vector<std::string> message;
  };
  const Case cases[] = {
      {"patch range past patch_elements",
       [](BakeData& d) { d.patches[1].element_count = 9; },
       {"PTCH", "patch 1", "[2, 11)"}},
      {"patch element past the triangles",
       [](BakeData& d) { d.patch_elements[3] = 9001; },
       {"PELM", "element 3", "9001"}},
      {"cluster child out of range",
       [](BakeData& d) { d.clusters[2].child[1] = 12; },
       {"CLST", "cluster 2", "12"}},
      {"cluster parent out of range",
       [](BakeData& d) { d.clusters[3].parent = 40; },
       {"CLST", "cluster 3", "40"}},
      {"cluster patch out of range",
       [](BakeData& d) { d.clusters[4].patch = 3; },
       {"CLST", "cluster 4", "patch 3"}},
      {"cluster child/parent disagree",
       [](BakeData& d) { d.clusters[4].parent = 0; },
       {"CLST", "cluster 2", "parent 0"}},
      {"emitter patch out of range",
       [](BakeData& d) { d.emitters[0].patches[2] = 3; },
       {"EMIT", "emitter 0", "3 >= patch count 3"}},
      {"emitter patches not ascending",
       [](BakeData& d) {
         d.emitters[2].patches = {1, 0};
       },
       {"EMIT", "emitter 2", "ascending"}},
      {"emitter factors length",
       [](BakeData& d) { d.emitters[2].factors.push_back(0.5f); },
       {"EMIT", "emitter 2", "3 factors for 2 patches"}},
      {"emitting patch out of range",
       [](BakeData& d) { d.emitters[2].index = 5; },
       {"EMIT", "emitter 2", "5"}},
      {"proxy index out of range",
       [](BakeData& d) { d.proxy.indices[4] = 4; },
       {"PRXY", "face 1", "index 4 >= vertex count 4"}},
      {"proxy face patch out of range",
       [](BakeData& d) { d.proxy.face_patch[1] = 7; },
       {"PRXY", "face 1", "patch 7"}},
      {"proxy face count",
       [](BakeData& d) { d.proxy.face_patch.pop_back(); },
       {"PRXY", "1 face patches for 2 faces"}},
      {"triangle uv page out of range",
       [](BakeData& d) { d.triangle_uvs[3].page = 2; },
       {"TUVS", "triangle 3", "page 2 >= page count 2"}},
      {"back uv triangle out of range",
       [](BakeData& d) { d.back_uvs[1].triangle = 4; },
       {"BUVS", "back 1", "triangle 4 >= triangle count 4"}},
      {"back uvs not ascending",
       [](BakeData& d) { d.back_uvs[1].triangle = 1; },
       {"BUVS", "back 1", "does not follow", "1"}},
      {"back uv page out of range",
       [](BakeData& d) { d.back_uvs[0].page = 2; },
       {"BUVS", "back 0", "page 2 >= page count 2"}},
      {"NaN back uv",
       [](BakeData& d) { d.back_uvs[0].uv[1].y = kNan; },
       {"BUVS", "back 0", "uv 1", "not finite"}},
      {"probe sh size", [](BakeData& d) { d.probes.sh.pop_back(); }, {"PROB", "47", "2 x 1 x 2"}},
      {"NaN radiosity",
       [](BakeData& d) { d.patches[2].radiosity.g = kNan; },
       {"PTCH", "patch 2", "radiosity", "not finite"}},
      {"Inf uv",
       [](BakeData& d) { d.triangle_uvs[1].uv[2].x = std::numeric_limits<float>::infinity(); },
       {"TUVS", "triangle 1", "inf"}},
      {"NaN factor",
       [](BakeData& d) { d.emitters[0].factors[1] = kNan; },
       {"EMIT", "emitter 0", "factor 1"}},
      {"NaN proxy vertex",
       [](BakeData& d) { d.proxy.positions[3].z = kNan; },
       {"PRXY", "vertex 3"}},
      {"page file escapes the directory",
       [](BakeData& d) { d.pages[1].file = "../lightmap-1.exr"; },
       {"PAGE", "page 1", "../lightmap-1.exr"}},
      {"empty page", [](BakeData& d) { d.pages[0].height = 0; }, {"PAGE", "page 0", "256 x 0"}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    BakeData data = fullBake();
    c.breakIt(data);
    const Status s = writeBakeFile(data, file);
    EXPECT_EQ(s.code(), StatusCode::kInvalidInput) << describe(s);
    EXPECT_TRUE(messageHas(s, {"bake.svit"}));
    for (const std::string& part : c.message) EXPECT_TRUE(messageHas(s, {part}));
    EXPECT_EQ(readBytes(file), before) << "the previous file changed";
    EXPECT_FALSE(fs::exists(file + ".tmp"));
  }
}

// One broken shadow-mask invariant per case. The writer must refuse it,
// naming SMSK and the offending element, and leave the previous file
// byte-identical; the reader must refuse a good file whose SMSK payload
// (re-encoded from the broken masks, checksum fixed) says the same.
TEST_F(BakeFileTest, BadShadowMasksAreRefusedByWriterAndReader) {
  const std::string file = path("bake.svit");
  ASSERT_TRUE(writeBakeFile(maskedBake(), file).ok());
  const std::vector<uint8_t> before = readBytes(file);
  struct Case {
    const char* what;
    void (*breakIt)(BakeData&);
    std::vector<std::string> message;
  };
  const Case cases[] = {
      {"masks without runtime sections",
       [](BakeData& d) {
         const BakeShadowMasks masks = d.masks;
         d = staticBake();
         d.masks = masks;
       },
       {"SMSK", "has_runtime_sections is false", "masks.lights holds 5"}},
      {"emitter out of range",
       [](BakeData& d) { d.masks.lights[2].emitter = 9; },
       {"section SMSK light 2: emitter 9 is out of range (6 emitters)"}},
      {"emitter is the sky",
       [](BakeData& d) {
         d.emitters[2].kind = BakeEmitter::Kind::kSky;
         d.masks.lights[1].emitter = 2;
       },
       {"SMSK light 1", "emitter 2 is a sky", "not a light, the sun or a lamp's patch"}},
      {"emitter masked twice",
       [](BakeData& d) { d.masks.lights[3].emitter = 0; },
       {"SMSK light 3", "emitter 0 is already masked by light 0"}},
      {"channel out of range",
       [](BakeData& d) { d.masks.lights[4].channel = 2; },
       {"SMSK light 4", "channel 2 >= channel count 2"}},
      {"owner 0", [](BakeData& d) { d.masks.lights[0].owner = 0; }, {"SMSK light 0", "owner 0"}},
      {"owner above 255",
       [](BakeData& d) { d.masks.lights[2].owner = 256; },
       {"SMSK light 2", "owner 256 is not in 1..255"}},
      {"two lights with one (channel, owner)",
       [](BakeData& d) { d.masks.lights[3].owner = 2; },
       {"SMSK light 3", "channel 0 owner 2 is already light 2's"}},
      {"too many channels",
       [](BakeData& d) { d.masks.channels = 300; },
       {"SMSK", "300 channels exceed the limit of 256"}},
      {"mask page missing",
       [](BakeData& d) { d.masks.pages.pop_back(); },
       {"SMSK", "1 mask pages for 2 lightmap pages"}},
      {"mask page short",
       [](BakeData& d) { d.masks.pages[1].pop_back(); },
       {"SMSK page 1", "16383 values", "1 layers of 64 x 64", "= 16384"}},
      {"texel owner unknown",
       [](BakeData& d) { d.masks.pages[1][maskIndex(d.pages[1], 5, 3, 1)] = 7 << 8 | 9; },
       {"SMSK page 1", "texel (5, 3) channel 1", "value 1801 has owner 7"}},
      {"texel owner of another channel's light",
       [](BakeData& d) { d.masks.pages[0][maskIndex(d.pages[0], 200, 100, 1)] = 3 << 8; },
       {"SMSK page 0", "texel (200, 100) channel 1", "owner 3"}},
      {"texel owner in an unused channel",
       [](BakeData& d) { d.masks.pages[0][maskIndex(d.pages[0], 0, 127, 3)] = 1 << 8 | 255; },
       {"SMSK page 0", "layer 0 texel (0, 127) channel 3", "owner 1"}},
      {"no lights but channels",
       [](BakeData& d) {
         d.masks.lights.clear();
         d.masks.pages.clear();
       },
       {"SMSK", "no masked lights but 2 channels"}},
      {"no lights but pages",
       [](BakeData& d) {
         d.masks.lights.clear();
         d.masks.channels = 0;
       },
       {"SMSK", "no masked lights but 2 mask pages"}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    BakeData data = maskedBake();
    c.breakIt(data);
    const Status s = writeBakeFile(data, file);
    EXPECT_EQ(s.code(), StatusCode::kInvalidInput) << describe(s);
    EXPECT_TRUE(messageHas(s, {"bake.svit"}));
    for (const std::string& part : c.message) EXPECT_TRUE(messageHas(s, {part}));
    EXPECT_EQ(readBytes(file), before) << "the previous file changed";
    EXPECT_FALSE(fs::exists(file + ".tmp"));

    // The same data as a file: everything but the masks written, then the
    // broken masks spliced in as SMSK.
    BakeData unmasked = data;
    unmasked.masks = {};
    ASSERT_TRUE(writeBakeFile(unmasked, path("bad.svit")).ok());
    std::vector<uint8_t> bytes = readBytes(path("bad.svit"));
    replaceShadowMasks(bytes, shadowMaskPayload(data.masks));
    writeBytes(path("bad.svit"), bytes);
    const Status r = readBakeFile(path("bad.svit")).status();
    EXPECT_EQ(r.code(), StatusCode::kInvalidInput) << describe(r);
    EXPECT_TRUE(messageHas(r, {"bad.svit"}));
    for (const std::string& part : c.message) EXPECT_TRUE(messageHas(r, {part}));
  }
}

TEST_F(BakeFileTest, DirectoryAsTargetFailsAndLeavesNoTmp) {
  const std::string target = path("a_directory");
  fs::create_directories(target);
  const Status s = writeBakeFile(fullBake(), target);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.code(), StatusCode::kIoError) << describe(s);
  EXPECT_TRUE(messageHas(s, {"a_directory"}));
  EXPECT_FALSE(fs::exists(target + ".tmp"));
  EXPECT_TRUE(fs::is_directory(target));

  // Reading a directory is an I/O error too, not a crash or "not found".
  const Status r = readBakeFile(target).status();
  EXPECT_EQ(r.code(), StatusCode::kIoError) << describe(r);

  // A directory that does not exist: the tmp cannot be created.
  const Status m = writeBakeFile(fullBake(), path("no/such/dir/bake.svit"));
  EXPECT_EQ(m.code(), StatusCode::kIoError) << describe(m);
  EXPECT_TRUE(messageHas(m, {"bake.svit.tmp", "cannot create"}));
}

TEST_F(BakeFileTest, MissingFileIsNotFound) {
  const Status s = readBakeFile(path("never_written.svit")).status();
  EXPECT_EQ(s.code(), StatusCode::kNotFound) << describe(s);
  EXPECT_TRUE(messageHas(s, {"never_written.svit"}));
}

TEST(BakeFileHash, Fnv1a64KnownValues) {
  // Reference values of FNV-1a 64 (Fowler/Noll/Vo test vectors).
  EXPECT_EQ(fnv1a64("", 0), 0xcbf29ce484222325ull);
  EXPECT_EQ(fnv1a64("a", 1), 0xaf63dc4c8601ec8cull);
  EXPECT_EQ(fnv1a64("foobar", 6), 0x85944171f73967e8ull);
  // Chaining through `seed` equals hashing the concatenation.
  EXPECT_EQ(fnv1a64("bar", 3, fnv1a64("foo", 3)), fnv1a64("foobar", 6));
}

}  // namespace
}  // namespace svit
