#pragma once
// --probe / --probe-out: points 'x y z nx ny nz' in, the runtime's
// irradiance 'r g b' (lux) out, one line per point.

#include <string>
#include <vector>

#include "svit/baked_surfaces.h"
#include "svit/math_types.h"
#include "svit/status.h"

namespace svit::walk {

// Points are read with svit::readProbePoints (svit/baked_surfaces.h), the
// reader svit-probe uses.
using svit::ProbePoint;
using svit::readProbePoints;

/// Writes one 'r g b' line per value (NaN for a point off the static
/// surfaces) via `path`.tmp and a rename. Errors name the path.
Status writeIrradiance(const std::string& path, const std::vector<Rgb>& values);

}  // namespace svit::walk
