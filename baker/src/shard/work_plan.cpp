// Payload codecs of a sharded bake's work files (work_plan.h).

#include "work_plan.h"

#include "util/byte_stream.h"

namespace svit::baker {
namespace {

Status notFitting(const std::string& path, const std::string& what) {
  return Status(StatusCode::kInvalidInput, path + ": " + what + " does not fit its file");
}

void putAtlas(ByteWriter& w, const AtlasTexels& a) {
  w.put(a.settings.texels_per_m);
  w.put(int32_t(a.settings.max_page_size));
  w.put(int32_t(a.settings.padding_texels));
  w.put(int32_t(a.atlas.page_width));
  w.put(int32_t(a.atlas.page_height));
  w.put(int32_t(a.atlas.page_count));
  w.put(uint8_t(a.atlas.authored));
  w.putVector(a.atlas.triangle_page);
  w.putVector(a.atlas.triangle_uv);
  w.putVector(a.atlas.triangle_chart);
  w.putVector(a.atlas.back_triangles);
}

void getAtlas(ByteReader& r, AtlasTexels& a) {
  a.settings.texels_per_m = r.get<double>();
  a.settings.max_page_size = r.get<int32_t>();
  a.settings.padding_texels = r.get<int32_t>();
  a.atlas.page_width = r.get<int32_t>();
  a.atlas.page_height = r.get<int32_t>();
  a.atlas.page_count = r.get<int32_t>();
  a.atlas.authored = r.get<uint8_t>() != 0;
  a.atlas.triangle_page = r.getVector<uint32_t>();
  a.atlas.triangle_uv = r.getVector<Vec2>();
  a.atlas.triangle_chart = r.getVector<uint32_t>();
  a.atlas.back_triangles = r.getVector<uint32_t>();
}

// The texel set's lookup points into its samples, and the samples into its pages.
bool texelsFit(const TexelSet& t) {
  if (t.page_width < 0 || t.page_height < 0 || t.page_count < 0) return false;
  const size_t page_texels = size_t(t.page_width) * size_t(t.page_height);
  if (t.texel_to_sample.size() != page_texels * size_t(t.page_count)) return false;
  for (int32_t s : t.texel_to_sample) {
    if (s < kBuriedTexel || (s >= 0 && size_t(s) >= t.samples.size())) return false;
  }
  for (const TexelSample& s : t.samples) {
    if (s.page >= uint32_t(t.page_count) || s.x >= uint32_t(t.page_width) ||
        s.y >= uint32_t(t.page_height))
      return false;
  }
  return true;
}

// Every face's sample names it and its triangle.
bool facesFit(const AtlasTexels& a) {
  const size_t faces = a.atlas.triangle_page.size();
  if (a.atlas.triangle_uv.size() != faces * 3 || a.atlas.triangle_chart.size() != faces ||
      a.atlas.back_triangles.size() > faces)
    return false;
  const std::vector<uint32_t>& backs = a.atlas.back_triangles;
  for (size_t i = 0; i < backs.size(); ++i) {  // ascending: LightmapAtlas::face searches them
    if (backs[i] >= a.atlas.frontCount() || (i > 0 && backs[i] <= backs[i - 1])) return false;
  }
  for (const TexelSample& s : a.texels.samples) {
    if (s.face >= faces || s.triangle != a.atlas.faceTriangle(s.face)) return false;
  }
  return true;
}

}  // namespace

BakeOptions WorkPlan::bakeOptions(const std::string& out_dir, int threads) const {
  BakeOptions options;
  options.level_path = level_path;
  options.out_dir = out_dir;
  options.seed = seed;
  options.quality = quality;
  options.passes = passes;
  options.texels_per_m = texels_per_m;
  options.max_page_size = max_page_size;
  options.threads = threads;
  return options;
}

std::vector<uint32_t> WorkPlan::shardTexels(uint32_t shard) const {
  std::vector<uint32_t> texels;
  for (size_t c = 0; c < chunk_shard.size(); ++c) {
    if (chunk_shard[c] != shard) continue;
    const uint64_t end = std::min<uint64_t>(texel_count, (c + 1) * uint64_t(chunk_texels));
    for (uint64_t j = c * uint64_t(chunk_texels); j < end; ++j) texels.push_back(uint32_t(j));
  }
  return texels;
}

std::vector<uint8_t> encodePlan(const WorkPlan& p) {
  ByteWriter w;
  w.putString(p.level_path);
  w.put(p.level_hash);
  w.put(p.seed);
  w.put(p.quality);
  w.put(p.passes);
  w.put(p.texels_per_m);
  w.put(p.max_page_size);
  w.put(p.shards);
  w.put(p.texel_count);
  w.put(p.chunk_texels);
  w.putVector(p.chunk_shard);
  w.putVector(p.shard_cost);
  w.put(p.solution_checksum);
  w.put(p.texels_checksum);
  return w.take();
}

Expected<WorkPlan> decodePlan(const std::vector<uint8_t>& payload, const std::string& path) {
  ByteReader r(payload);
  WorkPlan p;
  p.level_path = r.getString();
  p.level_hash = r.get<uint64_t>();
  p.seed = r.get<uint64_t>();
  p.quality = r.get<double>();
  p.passes = r.get<uint32_t>();
  p.texels_per_m = r.get<double>();
  p.max_page_size = r.get<int32_t>();
  p.shards = r.get<uint32_t>();
  p.texel_count = r.get<uint64_t>();
  p.chunk_texels = r.get<uint32_t>();
  p.chunk_shard = r.getVector<uint32_t>();
  p.shard_cost = r.getVector<uint64_t>();
  p.solution_checksum = r.get<uint64_t>();
  p.texels_checksum = r.get<uint64_t>();
  const uint64_t chunks =
      p.chunk_texels > 0 ? (p.texel_count + p.chunk_texels - 1) / p.chunk_texels : 0;
  bool fits = r.atEnd() && p.shards > 0 && p.chunk_texels > 0 && p.chunk_shard.size() == chunks &&
              p.shard_cost.size() == p.shards;
  for (uint32_t s : p.chunk_shard) fits = fits && s < p.shards;
  if (!fits) return notFitting(path, "the plan");
  return p;
}

std::vector<uint8_t> encodeAtlasTexels(const AtlasTexels& a) {
  ByteWriter w;
  putAtlas(w, a);
  w.put(int32_t(a.texels.page_width));
  w.put(int32_t(a.texels.page_height));
  w.put(int32_t(a.texels.page_count));
  w.putVector(a.texels.samples);
  w.putVector(a.texels.texel_to_sample);
  return w.take();
}

Expected<AtlasTexels> decodeAtlasTexels(const std::vector<uint8_t>& payload,
                                        const std::string& path) {
  ByteReader r(payload);
  AtlasTexels a;
  getAtlas(r, a);
  a.texels.page_width = r.get<int32_t>();
  a.texels.page_height = r.get<int32_t>();
  a.texels.page_count = r.get<int32_t>();
  a.texels.samples = r.getVector<TexelSample>();
  a.texels.texel_to_sample = r.getVector<int32_t>();
  const bool fits = r.atEnd() && facesFit(a) && texelsFit(a.texels);
  if (!fits) return notFitting(path, "the atlas and its texels");
  return a;
}

std::vector<uint8_t> encodeShard(const ShardLighting& s) {
  ByteWriter w;
  w.put(s.shard);
  w.put(s.shards);
  w.put(s.passes);
  w.putVector(s.sums);
  w.putVector(s.odd_sums);
  for (const std::vector<TexelIrradiance>& q : s.quarter_sums) w.putVector(q);
  w.putVector(s.spreads);
  return w.take();
}

Expected<ShardLighting> decodeShard(const std::vector<uint8_t>& payload, const std::string& path) {
  ByteReader r(payload);
  ShardLighting s;
  s.shard = r.get<uint32_t>();
  s.shards = r.get<uint32_t>();
  s.passes = r.get<uint32_t>();
  s.sums = r.getVector<TexelIrradiance>();
  s.odd_sums = r.getVector<TexelIrradiance>();
  for (std::vector<TexelIrradiance>& q : s.quarter_sums) q = r.getVector<TexelIrradiance>();
  s.spreads = r.getVector<PassSpread>();
  const bool sums_fit = s.odd_sums.size() == s.sums.size() &&
                        s.quarter_sums[0].size() == s.sums.size() &&
                        s.quarter_sums[1].size() == s.sums.size();
  if (!r.atEnd() || s.spreads.size() != s.passes || !sums_fit)
    return notFitting(path, "the shard's texels");
  return s;
}

}  // namespace svit::baker
