#include "walk_probe.h"

#include <cstdio>
#include <filesystem>
#include <fstream>

namespace svit::walk {

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
  if (ec)
    return Status(StatusCode::kIoError, path + ": cannot rename from " + tmp + ": " + ec.message());
  return Status();
}

}  // namespace svit::walk
