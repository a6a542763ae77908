#include "double_math.h"
#include "svit/baker/probe.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "svit/bake_file.h"
#include "svit/baker/bake_geometry.h"
#include "svit/level.h"
#include "svit/lightmap_image.h"

namespace svit::baker {
namespace {

namespace fs = std::filesystem;

// Closest point on triangle abc to p (Ericson, Real-Time Collision
// Detection 5.1.5), returned as barycentrics (weights of b and c).
glm::dvec2 closestOnTriangle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  const glm::dvec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return {0, 0};
  const glm::dvec3 bp = p - b;
  const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return {1, 0};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return {d1 / (d1 - d3), 0};
  const glm::dvec3 cp = p - c;
  const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return {0, 1};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return {0, d2 / (d2 - d6)};
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {1 - w, w};
  }
  const double denominator = 1.0 / (va + vb + vc);
  return {vb * denominator, vc * denominator};
}

}  // namespace

Expected<std::vector<ProbePoint>> readProbePoints(const std::string& path) {
  std::ifstream file(path);
  if (!file) return Status(StatusCode::kNotFound, path + ": cannot open");
  std::vector<ProbePoint> points;
  std::string line;
  for (size_t number = 1; std::getline(file, line); ++number) {
    const size_t hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    std::istringstream in(line);
    std::vector<std::string> tokens;
    for (std::string token; in >> token;) tokens.push_back(token);
    if (tokens.empty()) continue;
    double v[6];
    bool numbers = tokens.size() == 6;
    for (size_t i = 0; numbers && i < 6; ++i) {
      char* end = nullptr;
      v[i] = std::strtod(tokens[i].c_str(), &end);
      numbers = end != tokens[i].c_str() && *end == '\0';
    }
    if (!numbers) {
      return Status(StatusCode::kInvalidInput, path + ":" + std::to_string(number) + ": expected 6 numbers 'x y z nx ny nz'");
    }
    for (double x : v) {
      if (!std::isfinite(x)) return Status(StatusCode::kInvalidInput, path + ":" + std::to_string(number) + ": not finite");
    }
    if (v[3] == 0 && v[4] == 0 && v[5] == 0) {
      return Status(StatusCode::kInvalidInput, path + ":" + std::to_string(number) + ": the normal is zero");
    }
    points.push_back({{float(v[0]), float(v[1]), float(v[2])}, {float(v[3]), float(v[4]), float(v[5])}});
  }
  return points;
}

Expected<std::vector<ProbeResult>> probeBake(const std::string& out_dir, const std::vector<ProbePoint>& points) {
  const std::string bake_path = (fs::path(out_dir) / "bake.svit").string();
  Expected<BakeData> bake = readBakeFile(bake_path);
  if (!bake.ok()) return bake.status();
  const std::string report_path = (fs::path(out_dir) / "report.json").string();
  std::ifstream report_file(report_path);
  if (!report_file) return Status(StatusCode::kNotFound, report_path + ": cannot open (it names the level)");
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
    return Status(StatusCode::kInvalidInput, bake_path + ": the level " + level_path + " changed since it was baked; bake it again");
  }
  Expected<BakeGeometry> geometry = flattenStaticGeometry(*scene);
  if (!geometry.ok()) return geometry.status();
  if (geometry->triangleCount() != bake->triangle_uvs.size()) {
    return Status(StatusCode::kInvalidInput, bake_path + ": has " + std::to_string(bake->triangle_uvs.size()) +
                                                 " lightmapped triangles, the level " + std::to_string(geometry->triangleCount()));
  }
  std::vector<LightmapImage> pages;
  for (const BakeLightmapPage& page : bake->pages) {
    Expected<LightmapImage> image = readLightmapExr((fs::path(out_dir) / page.file).string());
    if (!image.ok()) return image.status();
    pages.push_back(std::move(image).value());
  }
  const double cos_limit = 0.5;  // 60 degrees
  std::vector<ProbeResult> results;
  for (const ProbePoint& point : points) {
    const glm::dvec3 p = dvec(point.position), n = glm::normalize(dvec(point.normal));
    double best = 1e300;
    ProbeResult result;
    bool found = false;
    for (uint32_t t = 0; t < geometry->triangleCount(); ++t) {
      if (glm::dot(dvec(geometry->normals[t]), n) < cos_limit) continue;
      const glm::dvec3 a = dvec(geometry->corner(t, 0)), b = dvec(geometry->corner(t, 1)), c = dvec(geometry->corner(t, 2));
      const glm::dvec2 w = closestOnTriangle(p, a, b, c);
      const glm::dvec3 q = a + w.x * (b - a) + w.y * (c - a);
      const double d = glm::length(q - p);
      if (d < best) {
        best = d;
        found = true;
        const BakeTriangleUv& uv = bake->triangle_uvs[t];
        const Vec2 lookup{float((1 - w.x - w.y) * uv.uv[0].x + w.x * uv.uv[1].x + w.y * uv.uv[2].x),
                          float((1 - w.x - w.y) * uv.uv[0].y + w.x * uv.uv[1].y + w.y * uv.uv[2].y)};
        result.irradiance = pages[uv.page].sampleBilinear(lookup);
        result.surface_point = {float(q.x), float(q.y), float(q.z)};
        result.distance_m = d;
        result.triangle = t;
      }
    }
    if (!found) {
      return Status(StatusCode::kInvalidInput, "no static surface faces the normal (" + std::to_string(point.normal.x) + ", " +
                                                   std::to_string(point.normal.y) + ", " + std::to_string(point.normal.z) + ")");
    }
    results.push_back(result);
  }
  return results;
}

}  // namespace svit::baker
