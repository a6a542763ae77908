#include "walk_probe.h"

#include <cstdio>

#include "scene/file_output.h"

namespace svit::walk {

Status writeIrradiance(const std::string& path, const std::vector<Rgb>& values) {
  std::string text;
  char line[128];
  for (const Rgb& c : values) {
    std::snprintf(line, sizeof line, "%.9g %.9g %.9g\n", c.r, c.g, c.b);
    text += line;
  }
  return writeFileReplacing(path, text.data(), text.size());
}

}  // namespace svit::walk
