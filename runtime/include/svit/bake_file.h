#pragma once
// bake.svit: what the baker hands the runtime. A versioned, checksummed
// binary of tagged sections; the lightmap texels themselves live in the EXR
// pages beside it (lightmap-<page>.exr), named and hashed here. Runtime
// sections (patches, clusters, emitters, proxies, probes) are written only
// for levels that have dynamic objects or runtime lights.

#include <cstdint>
#include <string>
#include <vector>

#include "svit/math_types.h"
#include "svit/scene.h"
#include "svit/status.h"

namespace svit {

/// Format version written by this build; readers reject any other.
inline constexpr uint32_t kBakeFileVersion = 1;

/// One lightmap atlas page: irradiance in lux, linear RGB, fp32 EXR.
struct BakeLightmapPage {
  uint32_t width = 0, height = 0;
  std::string file;         ///< relative to the bake directory, e.g. "lightmap-0.exr"
  uint64_t texel_hash = 0;  ///< FNV-1a 64 of the page's float RGB texels, row-major
};

/// Lightmap coordinates of one static triangle (the baker's triangle order:
/// static instances in scene order, then mesh triangle order).
struct BakeTriangleUv {
  uint32_t instance = 0;       ///< index into Scene::instances
  uint32_t mesh_triangle = 0;  ///< triangle within that instance's mesh
  uint32_t page = 0;
  Vec2 uv[3];  ///< page coordinates in [0, 1], v down the rows
};

/// The lightmap of a double-sided triangle's back, when it has one of its
/// own (a lightmap per side).
/// BakeBackUv::page of a back that no baked light reaches (the outside of
/// a closed room or of the Cornell box, where exporters made every wall
/// double-sided): it has no texels, and reads black wherever the level's
/// lightmaps and shadow masks are read; runtime lights still light it.
inline constexpr uint32_t kUnlitBackPage = 0xffffffffu;

/// The back of a double-sided triangle: its own lightmap, or kUnlitBackPage.
struct BakeBackUv {
  uint32_t triangle = 0;  ///< BakeData::triangle_uvs index
  uint32_t page = 0;      ///< BakeData::pages index, or kUnlitBackPage
  Vec2 uv[3];             ///< page coordinates in [0, 1], v down the rows, corners as the front's
};

/// A patch: a cluster-tree node of bounded area and similar normal, the unit
/// the runtime tracks radiosity deltas for.
struct BakePatch {
  Vec3 centroid;
  Vec3 normal;  ///< unit, area-weighted
  float area_m2 = 0;
  Rgb albedo;                  ///< area-weighted mean
  Rgb emission;                ///< exitance of its own emission, lm/m2
  Rgb radiosity;               ///< static baseline exitance, lm/m2 (emission + albedo * irradiance)
  uint32_t first_element = 0;  ///< into BakeData::patch_elements
  uint32_t element_count = 0;
};

/// Node of a cluster tree over patches (roots: parent -1).
struct BakeClusterNode {
  int32_t parent = -1;
  int32_t child[2] = {-1, -1};
  int32_t patch = -1;  ///< leaf: the patch; interior: -1
  Aabb bounds;
  float area_m2 = 0;
};

/// A static emitter's baseline form factors: which patches it lights, how much.
struct BakeEmitter {
  enum class Kind : uint32_t { kLight = 0, kPatch = 1, kSun = 2, kSky = 3 };
  Kind kind = Kind::kLight;
  uint32_t index = 0;             ///< Scene::lights index (kLight) or patch (kPatch)
  Rgb flux;                       ///< lm per channel
  std::vector<uint32_t> patches;  ///< lit patches, ascending
  std::vector<float> factors;     ///< share of the emitter's flux each receives, same length
};

/// A baked light (point, spot, directional, the sun, or a lamp's emissive
/// patch as an area light) whose direct light the lightmap leaves out: the
/// runtime shades it per pixel as its unshadowed irradiance x this mask
/// (its visibility from the static level, per lightmap texel) x its dimmer
/// x the dynamic objects' shadow.
struct BakeMaskedLight {
  uint32_t emitter = 0;  ///< BakeData::emitters index (a kLight, the kSun or a kPatch)
  uint32_t channel = 0;  ///< mask channel: layer channel / 4, component channel % 4
  uint32_t owner = 0;    ///< its id in that channel's texels, 1..255 (0 marks no light)
};

/// Shadow masks (section SMSK; only for levels with dynamic objects): the
/// static visibility of the masked lights per lightmap texel, in the
/// lightmap's atlas, dilated and seamed as the lightmap is. A texel's
/// channel holds (owner << 8) | visibility (0..255 for 0..1) of the one
/// light of that channel that reaches it, owner 0 where none does; lights
/// that share a channel never reach the same texel, so any number of
/// lights may overlap (each overlap costs a channel, not a cap).
struct BakeShadowMasks {
  std::vector<BakeMaskedLight> lights;
  uint32_t channels = 0;
  /// per lightmap page: layers() x height x width x 4 values, layer
  /// slowest, then rows, then texels, then the 4 channels of a layer
  std::vector<std::vector<uint16_t>> pages;
  uint32_t layers() const { return (channels + 3) / 4; }
};

/// Simplified static geometry the runtime renders index maps from.
struct BakeProxyMesh {
  std::vector<Vec3> positions;       ///< world, metres
  std::vector<uint32_t> indices;     ///< 3 per face
  std::vector<uint32_t> face_patch;  ///< per face: the patch it stands for
};

/// L1 spherical-harmonic irradiance probes on a regular grid for dynamic objects.
struct BakeProbeGrid {
  Vec3 origin;   ///< centre of probe (0, 0, 0), metres
  Vec3 spacing;  ///< metres
  uint32_t dims[3] = {0, 0, 0};
  std::vector<float> sh;  ///< per probe (x fastest): 4 coefficients x RGB = 12 floats
};

struct BakeData {
  uint32_t version = kBakeFileVersion;
  uint64_t level_hash = 0;  ///< hashLevel() of the level baked
  uint64_t seed = 0;
  std::vector<BakeLightmapPage> pages;
  std::vector<BakeTriangleUv> triangle_uvs;
  /// Backs of double-sided triangles with a lightmap of their own, by
  /// ascending triangle (section BUVS, written when not empty).
  std::vector<BakeBackUv> back_uvs;
  /// Runtime sections; all empty (and not written) for static-only levels.
  bool has_runtime_sections = false;
  std::vector<BakePatch> patches;
  std::vector<uint32_t> patch_elements;  ///< triangle * 2 + side (0 front, 1 back)
  std::vector<BakeClusterNode> clusters;
  std::vector<BakeEmitter> emitters;
  BakeProxyMesh proxy;
  BakeProbeGrid probes;
  /// Empty (and not written) when the bake masks no light.
  BakeShadowMasks masks;
};

/// The back lightmap of `triangle`, or null when its back shares the
/// front's texels (one-sided, or a bake without per-side lightmaps).
const BakeBackUv* findBackUv(const BakeData& data, uint32_t triangle);

/// Writes `data` to `path` via `path`.tmp and a rename, so a failure or a
/// kill leaves any previous file intact. Errors: I/O, inconsistent data
/// (e.g. factors and patches of different lengths, indices out of range).
Status writeBakeFile(const BakeData& data, const std::string& path);

/// One section of a bake file as writeBakeFile lays it out: its tag
/// ("HEAD", "PAGE", ...) and payload bytes.
struct BakeSectionSize {
  std::string tag;
  uint64_t bytes = 0;
};

/// The sections writeBakeFile writes for `data`, in file order, with their
/// payload sizes (what report.json's audit lists). `data` must be valid.
std::vector<BakeSectionSize> bakeSectionSizes(const BakeData& data);

/// Reads and validates a bake file. Errors name the file and what is wrong:
/// missing file, bad magic, other version ("version 7, this build reads 1"),
/// truncated section, checksum mismatch, out-of-range indices.
Expected<BakeData> readBakeFile(const std::string& path);

/// 64-bit hash of what a bake depends on: static and dynamic geometry,
/// materials (factors and texture texels), lights, sun and sky.
/// Deterministic across runs and platforms.
uint64_t hashLevel(const Scene& scene);

/// FNV-1a 64 of a byte range (the checksum used by bake files).
uint64_t fnv1a64(const void* data, size_t bytes, uint64_t seed = 0xcbf29ce484222325ull);

}  // namespace svit
