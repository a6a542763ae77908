#pragma once
// --probe / --probe-out: points 'x y z nx ny nz' in, the runtime's
// irradiance 'r g b' (lux) out, one line per point.

#include <string>
#include <vector>

#include "svit/math_types.h"
#include "svit/status.h"

namespace svit::walk {

struct ProbePoint {
  Vec3 position;  ///< world, metres
  Vec3 normal;    ///< unit (normalised on read), picks the surface side
};

/// Reads lines of six numbers; '#' starts a comment, blank lines are skipped.
/// Errors name the file and line: `points.txt:3: expected 6 numbers 'x y z nx ny nz'`,
/// non-finite values, a zero normal.
Expected<std::vector<ProbePoint>> readProbePoints(const std::string& path);

/// Writes one 'r g b' line per value (NaN for a point off the static
/// surfaces) via `path`.tmp and a rename. Errors name the path.
Status writeIrradiance(const std::string& path, const std::vector<Rgb>& values);

}  // namespace svit::walk
