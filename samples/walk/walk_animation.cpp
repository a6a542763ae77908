// Key-frame sampling. glTF 2.0 spec, "Animations" and Appendix C
// (interpolation): step holds the earlier key; linear lerps (slerps
// rotations); cubic spline is the Hermite spline with per-key in/out
// tangents scaled by the key interval.

#include "walk_animation.h"

#include <algorithm>
#include <cmath>

#include "walk_math.h"

namespace svit::walk {
namespace {

// The key interval holding `t`: index k with times[k] <= t < times[k+1] and
// the fraction within it, clamped at both ends.
struct KeySpan {
  size_t k0 = 0, k1 = 0;
  float u = 0;
  float dt_s = 0;
};

template <typename TimeOf>
KeySpan findSpan(size_t count, float t, TimeOf time_of) {
  if (count <= 1 || t <= time_of(0)) return {0, 0, 0, 0};
  if (t >= time_of(count - 1)) return {count - 1, count - 1, 0, 0};
  size_t lo = 0, hi = count - 1;  // time_of(lo) <= t < time_of(hi)
  while (hi - lo > 1) {
    const size_t mid = (lo + hi) / 2;
    (time_of(mid) <= t ? lo : hi) = mid;
  }
  const float dt = time_of(hi) - time_of(lo);
  return {lo, hi, dt > 0 ? (t - time_of(lo)) / dt : 0.0f, dt};
}

glm::quat slerpShortest(const glm::quat& a, const glm::quat& b, float u) {
  return glm::normalize(glm::slerp(a, b, u));  // glm negates b when the dot is negative
}

}  // namespace

Mat4 composeTrs(const Trs& trs) {
  glm::mat4 m = glm::mat4_cast(toGlm(trs.rotation));
  m[0] *= trs.scale.x;
  m[1] *= trs.scale.y;
  m[2] *= trs.scale.z;
  m[3] = glm::vec4(toGlm(trs.translation), 1.0f);
  return fromGlm(m);
}

float clipTime(float t_s, float duration_s, bool loop) {
  if (!(duration_s > 0)) return 0;
  if (!loop) return std::clamp(t_s, 0.0f, duration_s);
  const float wrapped = std::fmod(t_s, duration_s);
  return wrapped < 0 ? wrapped + duration_s : wrapped;
}

Trs samplePathKeys(std::span<const PathKey> keys, float t_s, bool loop) {
  if (keys.empty()) return {};
  const float t = loop ? clipTime(t_s, keys.back().t_s, true) : t_s;
  const KeySpan s = findSpan(keys.size(), t, [&](size_t k) { return keys[k].t_s; });
  const PathKey& a = keys[s.k0];
  const PathKey& b = keys[s.k1];
  Trs out;
  out.translation = fromGlm(glm::mix(toGlm(a.translation), toGlm(b.translation), s.u));
  out.scale = fromGlm(glm::mix(toGlm(a.scale), toGlm(b.scale), s.u));
  out.rotation = fromGlm(
      slerpShortest(glm::normalize(toGlm(a.rotation)), glm::normalize(toGlm(b.rotation)), s.u));
  return out;
}

void applyTrack(const AnimationTrack& track, float t_s, Trs& trs) {
  if (track.path == AnimationPath::kWeights || track.times_s.empty()) return;
  const int n = track.components;
  const bool cubic = track.interpolation == Interpolation::kCubicSpline;
  const size_t stride = size_t(n) * (cubic ? 3 : 1);
  // Component c of key k: the value, or for cubic splines the in-tangent
  // (part 0), value (1) or out-tangent (2).
  auto at = [&](size_t k, int part, int c) {
    return track.values[k * stride + size_t(part * n + c)];
  };
  const int value_part = cubic ? 1 : 0;
  const KeySpan s = findSpan(track.times_s.size(), t_s, [&](size_t k) { return track.times_s[k]; });
  float v[4] = {0, 0, 0, 1};
  if (track.interpolation == Interpolation::kStep || s.k0 == s.k1) {
    for (int c = 0; c < n && c < 4; ++c) v[c] = at(s.k0, value_part, c);
  } else if (cubic) {
    const float u = s.u, u2 = u * u, u3 = u2 * u;
    const float h00 = 2 * u3 - 3 * u2 + 1, h10 = u3 - 2 * u2 + u, h01 = -2 * u3 + 3 * u2,
                h11 = u3 - u2;
    for (int c = 0; c < n && c < 4; ++c) {
      v[c] = h00 * at(s.k0, 1, c) + h10 * s.dt_s * at(s.k0, 2, c) + h01 * at(s.k1, 1, c) +
             h11 * s.dt_s * at(s.k1, 0, c);
    }
  } else if (track.path == AnimationPath::kRotation) {
    const glm::quat a(at(s.k0, 0, 3), at(s.k0, 0, 0), at(s.k0, 0, 1), at(s.k0, 0, 2));
    const glm::quat b(at(s.k1, 0, 3), at(s.k1, 0, 0), at(s.k1, 0, 1), at(s.k1, 0, 2));
    const glm::quat q = slerpShortest(a, b, s.u);
    v[0] = q.x, v[1] = q.y, v[2] = q.z, v[3] = q.w;
  } else {
    for (int c = 0; c < n && c < 4; ++c) v[c] = (1 - s.u) * at(s.k0, 0, c) + s.u * at(s.k1, 0, c);
  }
  switch (track.path) {
    case AnimationPath::kTranslation: trs.translation = {v[0], v[1], v[2]}; break;
    case AnimationPath::kScale: trs.scale = {v[0], v[1], v[2]}; break;
    case AnimationPath::kRotation: {
      const glm::quat q(v[3], v[0], v[1], v[2]);
      const float length = glm::length(q);
      trs.rotation = length > 0 ? fromGlm(q / length) : Quat{};
      break;
    }
    case AnimationPath::kWeights: break;
  }
}

CameraKey sampleCameraKeys(std::span<const CameraKey> keys, float t_s, bool loop) {
  if (keys.empty()) return {};
  const float t = loop ? clipTime(t_s, keys.back().t_s, true) : t_s;
  const KeySpan s = findSpan(keys.size(), t, [&](size_t k) { return keys[k].t_s; });
  const CameraKey& a = keys[s.k0];
  const CameraKey& b = keys[s.k1];
  CameraKey out;
  out.t_s = t_s;
  out.position = fromGlm(glm::mix(toGlm(a.position), toGlm(b.position), s.u));
  out.look_at = fromGlm(glm::mix(toGlm(a.look_at), toGlm(b.look_at), s.u));
  out.yfov_rad = (1 - s.u) * a.yfov_rad + s.u * b.yfov_rad;
  return out;
}

}  // namespace svit::walk
