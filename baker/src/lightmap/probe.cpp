#include "svit/baker/probe.h"

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "svit/bake_file.h"
#include "svit/baked_surfaces.h"
#include "svit/level.h"
#include "svit/lightmap_image.h"
#include "svit/masked_lights.h"

namespace svit::baker {
namespace {

namespace fs = std::filesystem;

}  // namespace

Expected<std::vector<ProbeResult>> probeBake(const std::string& out_dir,
                                             const std::vector<ProbePoint>& points) {
  const std::string bake_path = (fs::path(out_dir) / "bake.svit").string();
  Expected<BakeData> bake = readBakeFile(bake_path);
  if (!bake.ok()) return bake.status();
  const std::string report_path = (fs::path(out_dir) / "report.json").string();
  std::ifstream report_file(report_path);
  if (!report_file)
    return Status(StatusCode::kNotFound, report_path + ": cannot open (it names the level)");
  nlohmann::json report;
  try {
    report_file >> report;
  } catch (const nlohmann::json::exception& e) {
    return Status(StatusCode::kInvalidInput, report_path + ": not valid JSON: " + e.what());
  }
  if (!report.contains("level") || !report["level"].is_string()) {
    return Status(StatusCode::kInvalidInput, report_path + ": no \"level\" field");
  }
  const std::string level_path = report["level"].get<std::string>();
  Expected<Scene> scene = loadLevel(level_path, LoadOptions{true});
  if (!scene.ok()) return scene.status();
  if (hashLevel(*scene) != bake->level_hash) {
    return Status(StatusCode::kInvalidInput, bake_path + ": the level " + level_path +
                                                 " changed since it was baked; bake it again");
  }
  Expected<BakedSurfaces> surfaces = BakedSurfaces::build(*scene, *bake);
  if (!surfaces.ok())
    return Status(surfaces.status().code(), bake_path + ": " + surfaces.status().message());
  Expected<std::vector<LightmapImage>> pages = readLightmapPages(*bake, out_dir);
  if (!pages.ok()) return pages.status();
  Expected<MaskedLightField> masked = MaskedLightField::create(*scene, *bake, *surfaces);
  if (!masked.ok())
    return Status(masked.status().code(), out_dir + "/" + masked.status().message());
  const double cos_limit = 0.5;  // 60 degrees
  std::vector<ProbeResult> results;
  for (const ProbePoint& point : points) {
    const std::optional<SurfaceHit> hit =
        surfaces->nearest(point.position, point.normal, cos_limit);
    if (!hit) {
      return Status(StatusCode::kInvalidInput, "no static surface faces the normal (" +
                                                   std::to_string(point.normal.x) + ", " +
                                                   std::to_string(point.normal.y) + ", " +
                                                   std::to_string(point.normal.z) + ")");
    }
    ProbeResult result;
    result.irradiance = samplePage(*pages, hit->page, hit->uv);
    if (!masked->empty()) {  // the lightmap leaves the masked lights' direct light to shading
      const Vec3& n = surfaces->normal(hit->triangle);
      const Vec3 side = hit->side == 0 ? n : Vec3{-n.x, -n.y, -n.z};
      const Rgb m = masked->bakedIrradiance(hit->point, side, hit->page, hit->uv);
      result.irradiance = {result.irradiance.r + m.r, result.irradiance.g + m.g,
                           result.irradiance.b + m.b};
    }
    result.surface_point = hit->point;
    result.distance_m = hit->distance_m;
    result.triangle = hit->triangle;
    results.push_back(result);
  }
  return results;
}

}  // namespace svit::baker
