// The stages a whole bake and a sharded one share (bake_stages.h;
// docs/architecture/baker-pipeline.md "The bake pipeline", "Sharded bakes").

#include "bake_stages.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>

#include "bake_output.h"
#include "radiosity/light_sources.h"
#include "scene/file_output.h"
#include "svit/bake_file.h"
#include "svit/baker/lightmap_pages.h"
#include "svit/baker/runtime_sections.h"
#include "svit/baker/shadow_masks.h"
#include "svit/level.h"
#include "svit/lightmap_image.h"
#include "util/double_math.h"
#include "util/random.h"

namespace svit::baker {
namespace {

namespace fs = std::filesystem;

// The bake file's sections with their sizes and what each holds, for the
// "pay for what is used" audit in report.json.
nlohmann::ordered_json sectionsJson(const BakeData& data) {
  const size_t probes = size_t(data.probes.dims[0]) * data.probes.dims[1] * data.probes.dims[2];
  const std::map<std::string, std::pair<std::string, std::string>> what = {
      {"HEAD", {"header", "level hash, seed"}},
      {"PAGE",
       {"pages", std::to_string(data.pages.size()) + " lightmap pages (names, sizes, hashes)"}},
      {"TUVS",
       {"triangle_uvs",
        std::to_string(data.triangle_uvs.size()) + " static triangles' lightmap coordinates"}},
      {"BUVS",
       {"back_uvs", std::to_string(data.back_uvs.size()) +
                        " double-sided triangles' back lightmap coordinates"}},
      {"PTCH",
       {"patches", std::to_string(data.patches.size()) + " patches the runtime's deltas live on"}},
      {"PELM",
       {"patch_elements",
        std::to_string(data.patch_elements.size()) + " elements of those patches"}},
      {"CLST",
       {"clusters", std::to_string(data.clusters.size()) + " cluster-tree nodes over the patches"}},
      {"EMIT",
       {"emitters",
        std::to_string(data.emitters.size()) + " baked emitters with their form factors"}},
      {"PRXY",
       {"proxy", std::to_string(data.proxy.indices.size() / 3) +
                     " LOD-proxy triangles the index maps draw"}},
      {"PROB", {"probes", std::to_string(probes) + " irradiance probes for dynamic objects"}},
      {"SMSK",
       {"shadow_masks", std::to_string(data.masks.lights.size()) +
                            " masked lights' static visibility per lightmap texel over " +
                            std::to_string(data.masks.channels) + " channels"}},
  };
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  for (const BakeSectionSize& section : bakeSectionSizes(data)) {
    const auto it = what.find(section.tag);
    out.push_back({{"section", it != what.end() ? it->second.first : section.tag},
                   {"tag", section.tag},
                   {"bytes", section.bytes},
                   {"holds", it != what.end() ? it->second.second : std::string()}});
  }
  return out;
}

const char* estimateName(ErrorEstimate estimate) {
  switch (estimate) {
    case ErrorEstimate::kSolverPasses: return "solver_passes";
    case ErrorEstimate::kSplitHalfPages: return "split_half_pages";
    case ErrorEstimate::kScaledTexelSpread: return "scaled_texel_spread";
    case ErrorEstimate::kTexelSpread: return "texel_spread";
  }
  return "unknown";
}

nlohmann::ordered_json seriesJson(const std::vector<ErrorPoint>& series, bool with_reference) {
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  for (const ErrorPoint& p : series) {
    nlohmann::ordered_json point;
    point["t_s"] = p.t_s;
    point["est_rel_error"] = p.est_rel_error;
    point["estimate"] = estimateName(p.estimate);
    if (std::isfinite(p.est_filter_bias)) point["est_filter_bias"] = p.est_filter_bias;
    if (with_reference)
      point["ref_rel_error"] =
          std::isfinite(p.ref_rel_error) ? nlohmann::ordered_json(p.ref_rel_error) : nullptr;
    out.push_back(point);
  }
  return out;
}

// Every double-sided triangle's back, ascending: on its own face where it
// has one, else unlit (kUnlitBackPage: no light reaches it, it reads black).
std::vector<BakeBackUv> backUvs(const BakeGeometry& geometry, const LightmapAtlas& atlas) {
  std::vector<BakeBackUv> backs;
  for (uint32_t t = 0; t < geometry.triangleCount(); ++t) {
    if (!geometry.double_sided[t]) continue;
    const uint32_t face = atlas.face(t, 1);
    BakeBackUv uv;
    uv.triangle = t;
    uv.page = face == t ? kUnlitBackPage : atlas.triangle_page[face];
    for (int k = 0; k < 3; ++k) uv.uv[k] = atlas.triangle_uv[face * 3 + size_t(k)];
    backs.push_back(uv);
  }
  return backs;
}

// The bake file's lightmap part, added to `data` (which holds the runtime's
// parts already): the pages' names and hashes, and every static triangle's
// lightmap coordinates.
void addLightmapSections(const BakeOptions& options, uint64_t level_hash,
                         const BakeGeometry& geometry, const LightmapAtlas& atlas,
                         const LightmapPages& pages, BakeData& data) {
  data.level_hash = level_hash;
  data.seed = options.seed;
  for (size_t p = 0; p < pages.images.size(); ++p) {
    BakeLightmapPage page;
    page.width = uint32_t(pages.images[p].width);
    page.height = uint32_t(pages.images[p].height);
    page.file = "lightmap-" + std::to_string(p) + ".exr";
    page.texel_hash =
        fnv1a64(pages.images[p].rgb.data(), pages.images[p].rgb.size() * sizeof(float));
    data.pages.push_back(page);
  }
  for (size_t t = 0; t < geometry.triangleCount(); ++t) {
    BakeTriangleUv uv;
    uv.instance = geometry.instance[t];
    uv.mesh_triangle = geometry.mesh_triangle[t];
    uv.page = atlas.triangle_page[t];
    for (int k = 0; k < 3; ++k) uv.uv[k] = atlas.triangle_uv[t * 3 + size_t(k)];
    data.triangle_uvs.push_back(uv);
  }
  data.back_uvs = backUvs(geometry, atlas);
}

// Adds the runtime's sections to `data` when the level needs them; returns
// the report's list of sections left out.
Expected<nlohmann::ordered_json> addRuntimeSections(BakeRun& run, const Scene& scene,
                                                    const BakeGeometry& geometry,
                                                    const RayCaster& caster,
                                                    const RadiositySolver& solver, BakeData& data) {
  nlohmann::ordered_json left_out = nlohmann::ordered_json::array();
  if (levelNeedsRuntimeSections(scene)) {
    RuntimeSectionSettings runtime_settings;
    runtime_settings.seed = run.options.seed;
    runtime_settings.threads = run.options.threads;
    if (Status s = buildRuntimeSections(scene, geometry, caster, solver, runtime_settings, data,
                                        run.cancel);
        !s.ok()) {
      return run.orCancelled(s);
    }
  } else {
    for (const char* section : {"patches", "clusters", "emitters", "proxy", "probes"}) {
      left_out.push_back({{"section", section},
                          {"reason", "the level has no dynamic objects and no runtime lights"}});
    }
  }
  return left_out;
}

// The report's account of one masked light: its emitter, channel, texels
// and bytes (a channel of every page, shared with the lights beside it).
nlohmann::ordered_json maskedLightJson(const Scene& scene, const BakeData& data, size_t k) {
  const BakeMaskedLight& light = data.masks.lights[k];
  const BakeEmitter& emitter = data.emitters[light.emitter];
  size_t texels = 0, page_texels = 0;
  for (size_t p = 0; p < data.masks.pages.size(); ++p) {
    texels += maskTexelsOf(data.masks, k, p);
    page_texels += data.masks.pages[p].size() / (size_t(data.masks.layers()) * 4);
  }
  const std::string name = emitter.kind == BakeEmitter::Kind::kSun ? std::string("sun")
                           : emitter.kind == BakeEmitter::Kind::kPatch
                               ? "emissive patch " + std::to_string(emitter.index)
                               : scene.lights[emitter.index].name;
  return {{"light", name},
          {"kind", emitter.kind == BakeEmitter::Kind::kPatch ? "area" : "punctual"},
          {"emitter", light.emitter},
          {"channel", light.channel},
          {"texels", texels},
          {"channel_bytes", page_texels * sizeof(uint16_t)}};
}

// Shadow masks for a level with dynamic objects (shadow_masks.h), into
// `data`; returns the report's "shadow_masks" object.
Expected<nlohmann::ordered_json> addShadowMasks(BakeRun& run, const LoadedLevel& level,
                                                const AtlasTexels& atlas, BakeData& data,
                                                nlohmann::ordered_json& left_out) {
  MaskChoice choice = chooseMaskedLights(level.scene, level.geometry, run.options.shadow_masks);
  addAreaLights(level.geometry, data.patches, data.patch_elements, choice.masked);
  nlohmann::ordered_json json;
  nlohmann::ordered_json unmasked = nlohmann::ordered_json::array();
  for (const UnmaskedLight& u : choice.unmasked)
    unmasked.push_back({{"light", u.light}, {"reason", u.reason}});
  if (choice.masked.count() == 0 || !data.has_runtime_sections) {
    left_out.push_back({{"section", "shadow_masks"}, {"reason", choice.none_reason}});
    json["lights"] = nlohmann::ordered_json::array();
    json["unmasked"] = unmasked;
    return json;
  }
  ShadowMaskSettings settings;
  settings.seed = hashIds(run.options.seed, 0x5ad0);
  settings.threads = run.options.threads;
  settings.sun_samples = std::max(16u, run.plan.sun_samples);
  settings.pages = bakePageSettings(atlas, run.options);
  const double start = run.clock.elapsed();
  Expected<BakeShadowMasks> masks =
      buildShadowMasks(level.scene, level.geometry, *level.caster, atlas.atlas, atlas.texels,
                       choice.masked, data.emitters, settings, run.cancel);
  if (!masks.ok()) return run.orCancelled(masks.status());
  data.masks = std::move(*masks);
  nlohmann::ordered_json lights = nlohmann::ordered_json::array();
  for (size_t k = 0; k < data.masks.lights.size(); ++k)
    lights.push_back(maskedLightJson(level.scene, data, k));
  uint64_t bytes = 0;
  for (const std::vector<uint16_t>& page : data.masks.pages)
    bytes += page.size() * sizeof(uint16_t);
  json["lights"] = lights;
  json["unmasked"] = unmasked;
  json["channels"] = data.masks.channels;
  json["layers"] = data.masks.layers();
  json["bytes"] = bytes;
  json["seconds"] = run.clock.elapsed() - start;
  return json;
}

// Lightmap texels written by the pass (valid 1) and by dilation (valid 2).
struct TexelCounts {
  size_t covered = 0, dilated = 0, buried = 0;
};

TexelCounts countTexels(const LightmapPages& pages) {
  TexelCounts counts;
  for (const auto& valid : pages.valid) {
    for (uint8_t v : valid) {
      counts.covered += v == 1;
      counts.dilated += v == 2;
      counts.buried += v == 3;
    }
  }
  return counts;
}

// Everything report.json says, but the final stage timings and total.
struct ReportInputs {
  const Scene& scene;
  const BakeGeometry& geometry;
  uint64_t level_hash;
  size_t degenerate;
  const RadiositySolver& solver;
  const AtlasSettings& atlas_settings;
  const LightmapAtlas& atlas;
  const TexelSet& texels;
  const LightmapPages& pages;
  const LightingPasses& lighting;
  const BakeData& data;
  const nlohmann::ordered_json& left_out;
  bool with_reference;
};

/// How the budget sized the lighting passes (pass_sizing.h); null without one.
nlohmann::ordered_json passSizingJson(const PassSizing& sizing, uint32_t gather_rays) {
  if (!sizing.sized) return nullptr;
  return {{"probe_s", sizing.probe_s},
          {"full_pass_s", sizing.full_pass_s},
          {"fixed_pass_s", sizing.fixed_pass_s},
          {"seconds_for_passes", sizing.seconds_for_passes},
          {"planned_passes", sizing.planned_passes},
          {"ray_share", sizing.ray_share},
          {"gather_rays_per_pass", gather_rays}};
}

/// The double-sided triangles whose backs no light reaches, left without
/// texels of their own (RadiositySolver::litBacks), and what they would
/// have cost at the atlas's density.
nlohmann::ordered_json unlitBacksJson(const BakeGeometry& geometry, const AtlasSettings& settings,
                                      const LightmapAtlas& atlas) {
  size_t double_sided = 0;
  double unlit_m2 = 0;
  for (uint32_t t = 0; t < geometry.triangleCount(); ++t) {
    if (!geometry.double_sided[t]) continue;
    ++double_sided;
    if (atlas.face(t, 1) == t) unlit_m2 += geometry.areas_m2[t];
  }
  const size_t unlit = double_sided - atlas.back_triangles.size();
  return {
      {"double_sided_triangles", double_sided},
      {"unlit", unlit},
      {"unlit_m2", unlit_m2},
      {"texels_left_out", std::llround(unlit_m2 * settings.texels_per_m * settings.texels_per_m)}};
}

/// The level the bake lit, as report.json names it for svit-probe and the
/// tools: with --sun/--sky that is OUT/level.json (the bare glTF alone
/// hashes differently), else the level given.
std::string bakedLevelPath(const BakeOptions& options) {
  if (options.sun_json.empty() && options.sky_json.empty())
    return fs::absolute(options.level_path).lexically_normal().string();
  return (fs::absolute(options.out_dir).lexically_normal() / "level.json").string();
}

nlohmann::ordered_json reportJson(const BakeRun& run, const ReportInputs& in) {
  const BakeOptions& options = run.options;
  const SolverStats stats = in.solver.stats();
  const TexelCounts counts = countTexels(in.pages);
  nlohmann::ordered_json json;
  json["level"] = bakedLevelPath(options);
  json["level_hash"] = in.level_hash;
  json["seed"] = options.seed;
  json["quality"] = options.quality;
  json["time_budget_s"] = run.plan.has_budget ? nlohmann::ordered_json(run.plan.budget_s) : nullptr;
  json["texels_per_m"] = in.atlas_settings.texels_per_m;
  json["threads"] = options.threads;
  json["machine"] = "CPU ray casting (Embree 3); no GPU used by the baker";
  nlohmann::ordered_json timings = nlohmann::ordered_json::object();
  for (const auto& [name, seconds] : run.clock.stageSeconds()) timings[name] = seconds;
  json["stage_seconds"] = timings;
  json["radiosity"] = {{"rays", stats.rays},
                       {"rays_per_s", stats.seconds > 0 ? double(stats.rays) / stats.seconds : 0.0},
                       {"passes", stats.passes_completed},
                       {"elements", stats.elements},
                       {"leaves", stats.leaves},
                       {"subdivisions", stats.subdivisions},
                       {"est_rel_error", in.lighting.solver_error},
                       {"compensation", stats.compensation},
                       {"captured_fraction", stats.captured_fraction},
                       {"back_absorbed_rays", stats.back_absorbed},
                       {"inside_origin_rays", stats.inside_origin_rays},
                       {"leak_guard",
                        {{"on", stats.leak_guard},
                         {"voxel_m", stats.leak_guard_voxel_m},
                         {"reached_free_voxels", stats.leak_guard_reached},
                         {"small_pockets_opened", stats.leak_guard_pockets_opened},
                         {"seconds", stats.leak_guard_seconds}}}};
  json["lightmap"] = {
      {"pages", in.pages.images.size()},
      {"page_width", in.texels.page_width},
      {"page_height", in.texels.page_height},
      {"atlas", in.atlas.authored ? "TEXCOORD_1" : "xatlas"},
      {"indirect_filter", options.indirect_filter},
      {"filter_noise_sigmas", in.lighting.filtered.filtered
                                  ? nlohmann::ordered_json(in.lighting.filtered.noise_sigmas)
                                  : nlohmann::ordered_json(nullptr)},
      {"covered_texels", counts.covered},
      {"dilated_texels", counts.dilated},
      {"buried_texels", counts.buried},
      {"back_faces", in.atlas.back_triangles.size()},
      {"unlit_backs", unlitBacksJson(in.geometry, in.atlas_settings, in.atlas)},
      {"back_texels", std::count_if(in.texels.samples.begin(), in.texels.samples.end(),
                                    [&](const TexelSample& s) { return in.atlas.isBack(s.face); })},
      {"lighting_passes", in.lighting.accumulator.passes()},
      {"gather_rays_per_texel", in.lighting.accumulator.passes() * in.lighting.gather_rays},
      {"pass_sizing", passSizingJson(in.lighting.sizing, in.lighting.gather_rays)}};
  nlohmann::ordered_json warnings = in.scene.warnings;
  if (in.degenerate > 0) {
    warnings.push_back(
        std::to_string(in.degenerate) +
        " static triangles flattened to zero area by their instance transform; skipped");
  }
  json["warnings"] = warnings;
  json["sections_written"] = sectionsJson(in.data);
  json["sections_left_out"] = in.left_out;
  json["error_vs_time"] = seriesJson(in.lighting.series, in.with_reference);
  return json;
}

// With --sun/--sky, OUT/level.json: the level the bake lit (the glTF by
// absolute path, with that sun and sky), which svit-walk and the runtime
// load to match the bake's level hash.
Status writeBakedLevelJson(const BakeOptions& options, const fs::path& staging) {
  if (options.sun_json.empty() && options.sky_json.empty()) return Status();
  nlohmann::ordered_json level;
  level["gltf"] = fs::absolute(options.level_path).lexically_normal().string();
  if (!options.sun_json.empty()) level["sun"] = nlohmann::ordered_json::parse(options.sun_json);
  if (!options.sky_json.empty()) level["sky"] = nlohmann::ordered_json::parse(options.sky_json);
  const std::string text = level.dump(2) + "\n";
  return writeFileReplacing((staging / "level.json").string(), text.data(), text.size());
}

// Writes the pages, the bake file and report.json into a fresh directory
// beside OUT, then swaps it in; OUT is left as it was on any failure.
Expected<BakeResult> writeBake(BakeRun& run, const LightmapPages& pages, const BakeData& data,
                               const std::vector<ErrorPoint>& series,
                               nlohmann::ordered_json& json) {
  const fs::path out = bakeOutputPath(run.options.out_dir);
  const fs::path staging = stagingDirectory(out);
  std::error_code ec;
  fs::remove_all(staging, ec);
  fs::create_directories(staging, ec);
  if (ec)
    return Status(StatusCode::kIoError, staging.string() + ": cannot create: " + ec.message());
  auto fail = [&](const Status& s) {
    std::error_code ignored;
    fs::remove_all(staging, ignored);
    if (s.code() == StatusCode::kCancelled) return s;
    return Status(s.code(), s.message() + "; " + out.string() + " left as it was");
  };
  for (size_t p = 0; p < pages.images.size(); ++p) {
    if (Status s = writeLightmapExr(pages.images[p], (staging / data.pages[p].file).string());
        !s.ok())
      return fail(s);
    if (run.cancelRequested()) return fail(run.cancelled);
  }
  if (Status s = writeBakeFile(data, (staging / "bake.svit").string()); !s.ok()) return fail(s);
  if (Status s = writeBakedLevelJson(run.options, staging); !s.ok()) return fail(s);
  BakeResult result;
  result.pages = pages.images.size();
  result.covered_texels = countTexels(pages).covered;
  result.est_rel_error = series.empty() ? 1.0 : series.back().est_rel_error;
  result.ref_rel_error =
      series.empty() ? std::numeric_limits<double>::quiet_NaN() : series.back().ref_rel_error;
  run.clock.endStage("done");
  json["stage_seconds"]["write"] = run.clock.stageSeconds().back().second;
  for (const auto& warning : json["warnings"])
    result.warnings.push_back(warning.get<std::string>());
  result.seconds = run.clock.elapsed();
  json["total_seconds"] = result.seconds;
  result.report_json = json.dump(2) + "\n";
  if (Status s = writeFileReplacing((staging / "report.json").string(), result.report_json.data(),
                                    result.report_json.size());
      !s.ok())
    return fail(s);
  if (run.cancelRequested()) return fail(run.cancelled);
  if (Status s = swapIntoPlace(staging, out); !s.ok()) return fail(s);
  return result;
}

}  // namespace

double BakeClock::elapsed() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

double BakeClock::remaining() const {
  return std::isfinite(budget_s_) ? std::max(0.0, budget_s_ - elapsed()) : -1.0;
}

void BakeClock::endStage(const std::string& next) {
  stage_seconds_.push_back({stage_, elapsed() - stage_start_});
  stage_ = next;
  stage_start_ = elapsed();
}

bool BakeClock::report(double fraction, double eta) const {
  if (cancel_ && cancel_->load()) return false;
  if (!progress_) return true;
  return progress_(BakeProgress{stage_, fraction, elapsed(), eta});
}

BakeRun makeBakeRun(const BakeOptions& options,
                    const std::function<bool(const BakeProgress&)>& progress,
                    const std::atomic<bool>* cancel, const std::string& first_stage) {
  return BakeRun{
      options, planBake(options), BakeClock(progress, cancel, options.time_budget_s, first_stage),
      cancel,
      Status(StatusCode::kCancelled, "bake cancelled; " + options.out_dir + " left as it was")};
}

namespace {

// What a user who bakes a glTF without lights (most glTF files carry none)
// must be told, instead of black lightmaps without a word.
std::string noLightWarning(const Scene& scene) {
  size_t runtime_lights = 0;
  for (const Light& light : scene.lights) runtime_lights += light.dynamic ? 1 : 0;
  std::string warning = scene.source_path +
                        ": no light source to bake (no static light, emissive surface, sun or "
                        "sky with any power): every lightmap texel is 0";
  if (runtime_lights > 0) {
    warning += "; its " + std::to_string(runtime_lights) +
               " dynamic light(s) are the runtime's, not baked";
  }
  return warning +
         ". Add KHR_lights_punctual lights or emissive materials to the glTF, a sun or sky in a "
         "level .json, or give svit-bake --sun/--sky";
}

}  // namespace

Expected<std::unique_ptr<LoadedLevel>> loadBakeLevel(const std::string& level_path,
                                                     const std::string& sun_json,
                                                     const std::string& sky_json) {
  auto level = std::make_unique<LoadedLevel>();
  Expected<Scene> scene = loadLevel(level_path);
  if (!scene.ok()) return scene.status();
  level->scene = std::move(scene).value();
  if (!sun_json.empty()) {
    Expected<Sun> sun = parseSunJson(sun_json, "--sun");
    if (!sun.ok()) return sun.status();
    level->scene.sun = *sun;
  }
  if (!sky_json.empty()) {
    Expected<Sky> sky = parseSkyJson(sky_json, "--sky");
    if (!sky.ok()) return sky.status();
    level->scene.sky = *sky;
  }
  level->level_hash = hashLevel(level->scene);
  Expected<BakeGeometry> geometry = flattenStaticGeometry(level->scene, &level->degenerate);
  if (!geometry.ok()) return geometry.status();
  level->geometry = std::move(geometry).value();
  level->emits_light = emitsAnyLight(level->scene, level->geometry);
  if (!level->emits_light) level->scene.warnings.push_back(noLightWarning(level->scene));
  Expected<std::unique_ptr<RayCaster>> caster = makeEmbreeCaster(level->geometry);
  if (!caster.ok()) return caster.status();
  level->caster = std::move(caster).value();
  return level;
}

Expected<std::unique_ptr<RadiositySolver>> solveRadiosity(BakeRun& run, const LoadedLevel& level) {
  RadiositySettings solver_settings;
  solver_settings.seed = run.options.seed;
  solver_settings.threads = run.options.threads;
  Expected<std::unique_ptr<RadiositySolver>> solver =
      RadiositySolver::create(level.scene, level.geometry, *level.caster, solver_settings);
  if (!solver.ok()) return solver.status();
  StopRule stop;
  stop.target_est_rel_error = run.plan.solver_target_est_rel_error;
  stop.max_seconds = run.plan.solver_max_seconds;
  stop.targets_at_pass_ends = run.plan.solver_targets_at_pass_ends;
  stop.cancel = run.cancel;
  stop.progress = [&](const SolverProgress& p) {
    const double fraction =
        std::min(1.0, std::max(p.elapsed_s / stop.max_seconds,
                               std::log(p.est_rel_error) / std::log(stop.target_est_rel_error)));
    return run.clock.report(std::max(0.0, fraction), run.clock.remaining());
  };
  if (Status s = (*solver)->improve(stop); !s.ok()) return run.orCancelled(s);
  return solver;
}

namespace {

// No light arrives at a texel whose sample lies in sealed space (a room
// sealed from every light, a crate's inside): black (buried), and no rays
// cast. Nor at one whose sample is walled in (under a wall or the crate,
// which tells nothing) while its square reaches sealed space and no lit
// space (a floor running under the wall into the room): lit, its light
// would be filtered into the room. A texel whose sample is lit stays lit
// even where its square reaches sealed space (a vault running into a
// wall's sealed core, a leaf into a vase): it is seen from the lit side,
// where black would show as a blotch; filtering spreads its light up to a
// texel into the sealed side.
bool buried(const RadiositySolver& solver, const LoadedLevel& level, const AtlasTexels& atlas,
            const TexelSample& s) {
  const LightReachVerdict centre = solver.lightReach(s.position, s.normal);
  if (centre != LightReachVerdict::kWalledIn) return centre == LightReachVerdict::kUnreached;
  bool sealed = false;
  for (const Vec3& corner : texelFootprint(level.geometry, atlas.atlas, s)) {
    const LightReachVerdict v = solver.lightReach(corner, s.normal);
    if (v == LightReachVerdict::kReached) return false;
    sealed = sealed || v == LightReachVerdict::kUnreached;
  }
  return sealed;
}

}  // namespace

Expected<AtlasTexels> buildAtlasTexels(BakeRun& run, const LoadedLevel& level,
                                       const RadiositySolver& solver) {
  AtlasTexels out;
  double total_area = 0;
  for (float a : level.geometry.areas_m2) total_area += a;
  out.settings.texels_per_m = atlasTexelsPerM(run.plan, total_area);
  out.settings.max_page_size = run.options.max_page_size;
  out.settings.threads = run.options.threads;
  if (!run.clock.report(0, run.clock.remaining())) return run.cancelled;
  out.settings.lit_backs = solver.litBacks();
  Expected<LightmapAtlas> atlas = buildLightmapAtlas(level.scene, level.geometry, out.settings);
  if (!atlas.ok()) return atlas.status();
  out.atlas = std::move(atlas).value();
  run.clock.endStage("texels");
  RasterSettings raster_settings;
  raster_settings.threads = run.options.threads;
  Expected<TexelSet> texels =
      rasterizeTexels(level.geometry, out.atlas, *level.caster, raster_settings);
  if (!texels.ok()) return texels.status();
  out.texels = std::move(texels).value();
  buryTexels(out.texels, [&](const TexelSample& s) { return buried(solver, level, out, s); });
  return out;
}

double referenceError(const TexelSet& texels, const std::vector<LightmapImage>& mine,
                      const std::vector<LightmapImage>& reference) {
  double difference = 0, sum = 0;
  for (const TexelSample& s : texels.samples) {
    const double ours = luminanceOf(mine[s.page].texel(int(s.x), int(s.y)));
    const double theirs = luminanceOf(reference[s.page].texel(int(s.x), int(s.y)));
    difference += (ours - theirs) * (ours - theirs);
    sum += theirs;
  }
  const double n = double(std::max<size_t>(1, texels.samples.size()));
  return sum > 0 ? std::sqrt(difference / n) / (sum / n) : 0.0;
}

PageSettings bakePageSettings(const AtlasTexels& atlas, const BakeOptions& options) {
  PageSettings settings;
  settings.dilation_texels = atlas.settings.padding_texels;
  // Gather noise; never crosses charts, creases or edges of the light.
  settings.edge_aware_filter = options.indirect_filter;
  settings.threads = options.threads;
  return settings;
}

FilteredPasses bakeLighting(const AtlasTexels& atlas, const BakeOptions& options,
                            const TexelAccumulator& accumulator) {
  return bestFilteredPasses(atlas.atlas, atlas.texels, accumulator,
                            bakePageSettings(atlas, options), kFilterNoiseSigmaChoices);
}
TexelLightingSettings passLightingSettings(const BakeRun& run, const LoadedLevel& level,
                                           uint32_t pass) {
  TexelLightingSettings settings;
  settings.masked =
      chooseMaskedLights(level.scene, level.geometry, run.options.shadow_masks).masked;
  settings.threads = run.options.threads;
  settings.gather_rays = run.plan.gather_rays;
  settings.area_light_samples = run.plan.area_light_samples;
  settings.sun_samples = run.plan.sun_samples;
  settings.seed = hashIds(run.options.seed, 0x1a7, pass);
  settings.solution = pass % 2 == 0 ? SolutionHalf::kEven : SolutionHalf::kOdd;
  return settings;
}

Expected<RuntimeParts> buildRuntimeParts(BakeRun& run, const LoadedLevel& level,
                                         const RadiositySolver& solver, const AtlasTexels& atlas) {
  RuntimeParts parts;
  Expected<nlohmann::ordered_json> left_out =
      addRuntimeSections(run, level.scene, level.geometry, *level.caster, solver, parts.data);
  if (!left_out.ok()) return left_out.status();
  parts.left_out = std::move(*left_out);
  Expected<nlohmann::ordered_json> masks =
      addShadowMasks(run, level, atlas, parts.data, parts.left_out);
  if (!masks.ok()) return masks.status();
  parts.masks = std::move(*masks);
  if (!run.clock.report(1, run.clock.remaining())) return run.cancelled;
  return parts;
}

Expected<BakeResult> finishBake(BakeRun& run, const LoadedLevel& level,
                                const RadiositySolver& solver, const AtlasTexels& atlas,
                                LightingPasses lighting, RuntimeParts runtime,
                                const std::vector<LightmapImage>& reference_pages,
                                const nlohmann::ordered_json& extra_report) {
  run.clock.endStage("pages");
  LightmapPages pages =
      buildLightmapPages(level.geometry, atlas.atlas, atlas.texels, lighting.filtered.mean,
                         bakePageSettings(atlas, run.options));
  const bool with_reference = !reference_pages.empty();
  if (with_reference && lighting.accumulator.passes() > 0) {
    lighting.series.back().ref_rel_error =
        referenceError(atlas.texels, pages.images, reference_pages);
  }
  if (!level.emits_light) {
    for (LightmapImage& page : pages.images) {
      page.comments = "svit: black: the level has no light source to bake (report.json)";
    }
  }
  BakeData& data = runtime.data;
  addLightmapSections(run.options, level.level_hash, level.geometry, atlas.atlas, pages, data);
  if (data.back_uvs.empty()) {
    runtime.left_out.push_back(
        {{"section", "back_uvs"}, {"reason", "the level has no double-sided static triangles"}});
  }
  if (!run.clock.report(1, run.clock.remaining())) return run.cancelled;
  run.clock.endStage("write");

  nlohmann::ordered_json json =
      reportJson(run, ReportInputs{level.scene, level.geometry, level.level_hash, level.degenerate,
                                   solver, atlas.settings, atlas.atlas, atlas.texels, pages,
                                   lighting, data, runtime.left_out, with_reference});
  json["shadow_masks"] = runtime.masks;
  for (const auto& [key, value] : extra_report.items()) json[key] = value;
  return writeBake(run, pages, data, lighting.series, json);
}

}  // namespace svit::baker
