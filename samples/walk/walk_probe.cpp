#include "walk_probe.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace svit::walk {

Expected<std::vector<ProbePoint>> readProbePoints(const std::string& path) {
  std::ifstream file(path);
  if (!file) return Status(StatusCode::kNotFound, path + ": cannot open");
  std::vector<ProbePoint> points;
  std::string line;
  for (size_t number = 1; std::getline(file, line); ++number) {
    const std::string where = path + ":" + std::to_string(number) + ": ";
    if (const size_t hash = line.find('#'); hash != std::string::npos) line.resize(hash);
    std::istringstream in(line);
    std::vector<std::string> tokens;
    for (std::string token; in >> token;) tokens.push_back(token);
    if (tokens.empty()) continue;
    float v[6];
    bool numbers = tokens.size() == 6;
    for (size_t i = 0; numbers && i < 6; ++i) {
      char* end = nullptr;
      v[i] = std::strtof(tokens[i].c_str(), &end);
      numbers = end != tokens[i].c_str() && *end == '\0';
    }
    if (!numbers) return Status(StatusCode::kInvalidInput, where + "expected 6 numbers 'x y z nx ny nz'");
    for (float x : v) {
      if (!std::isfinite(x)) return Status(StatusCode::kInvalidInput, where + "not finite");
    }
    if (v[3] == 0 && v[4] == 0 && v[5] == 0) return Status(StatusCode::kInvalidInput, where + "the normal is zero");
    const float length = std::sqrt(v[3] * v[3] + v[4] * v[4] + v[5] * v[5]);
    points.push_back({{v[0], v[1], v[2]}, {v[3] / length, v[4] / length, v[5] / length}});
  }
  return points;
}

Status writeIrradiance(const std::string& path, const std::vector<Rgb>& values) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream file(tmp);
    char line[128];
    for (const Rgb& c : values) {
      std::snprintf(line, sizeof line, "%.9g %.9g %.9g\n", c.r, c.g, c.b);
      file << line;
    }
    if (!file) return Status(StatusCode::kIoError, tmp + ": cannot write");
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) return Status(StatusCode::kIoError, path + ": cannot rename from " + tmp + ": " + ec.message());
  return Status();
}

}  // namespace svit::walk
