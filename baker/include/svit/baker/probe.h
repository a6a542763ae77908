#pragma once
// What svit-probe does: the baked irradiance at points, read from the
// lightmap the way a shader would (bilinear at the nearest surface point).

#include <string>
#include <vector>

#include "svit/baked_surfaces.h"
#include "svit/math_types.h"
#include "svit/status.h"

namespace svit::baker {

// The points file format is shared with svit-walk (svit/baked_surfaces.h).
using svit::ProbePoint;
using svit::readProbePoints;

struct ProbeResult {
  Rgb irradiance;         ///< lux, from the lightmap
  Vec3 surface_point;     ///< the nearest static surface point facing `normal`
  double distance_m = 0;  ///< from the query point to it
  uint32_t triangle = 0;
};

/// Opens the bake in `out_dir` (bake.svit, its pages, and the level named
/// in report.json, which must still hash to the bake's level hash) and looks
/// up each point on the nearest static triangle whose normal is within 60
/// degrees of the point's normal (brute force over triangles).
Expected<std::vector<ProbeResult>> probeBake(const std::string& out_dir,
                                             const std::vector<ProbePoint>& points);

}  // namespace svit::baker
