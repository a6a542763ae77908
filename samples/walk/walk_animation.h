#pragma once
// Sampling of what moves in a level over time: level.json path keys, glTF
// animation tracks (translation / rotation / scale; linear, step, cubic
// spline as glTF 2.0 defines them) and camera keys. Pure functions of the
// scene data and a time; no GL.

#include <span>

#include "svit/math_types.h"
#include "svit/scene.h"

namespace svit::walk {

/// A node's local transform as translation, rotation, scale.
struct Trs {
  Vec3 translation{0, 0, 0};
  Quat rotation{};
  Vec3 scale{1, 1, 1};
};

/// parent_from_node = T * R * S, column-major (same composition as glTF).
Mat4 composeTrs(const Trs& trs);

/// Time into a clip of `duration_s` seconds at global time `t_s`: wraps with
/// `loop`, else clamps to [0, duration_s]. A clip of zero length gives 0.
float clipTime(float t_s, float duration_s, bool loop);

/// Level.json path keys at global time `t_s` (times relative to t = 0; keys
/// ascending; non-empty). Before the first key: the first key's pose; after
/// the last, the last (or, with `loop`, time wraps at the last key's t_s).
/// Translation and scale are linear, rotation spherical-linear (shortest arc).
Trs samplePathKeys(std::span<const PathKey> keys, float t_s, bool loop);

/// Sets the part of `trs` that `track` animates to its value at clip time
/// `t_s` (already wrapped, see clipTime). Linear rotation tracks slerp;
/// cubic-spline tracks use glTF's Hermite form with in/out tangents and
/// normalise rotations. Weights tracks (morph targets) are ignored.
void applyTrack(const AnimationTrack& track, float t_s, Trs& trs);

/// A camera path at global time `t_s`: position, look-at point and field of
/// view interpolate linearly between keys; clamped or wrapped like paths.
CameraKey sampleCameraKeys(std::span<const CameraKey> keys, float t_s, bool loop);

}  // namespace svit::walk
