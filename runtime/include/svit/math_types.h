#pragma once
// Plain vector and matrix types of the public API. Layout-compatible with
// float arrays (and with GLM, which svit uses inside), so a game can pass its
// own math types by copying floats; no third-party type appears in svit's
// public headers.

#include <array>

namespace svit {

struct Vec2 {
  float x = 0, y = 0;
};
struct Vec3 {
  float x = 0, y = 0, z = 0;
};
struct Vec4 {
  float x = 0, y = 0, z = 0, w = 0;
};
/// Unit quaternion, glTF order (x, y, z, w).
struct Quat {
  float x = 0, y = 0, z = 0, w = 1;
};
/// Linear Rec.709 RGB.
struct Rgb {
  float r = 0, g = 0, b = 0;
};
/// 4x4 matrix, column-major like glTF and OpenGL: m[column * 4 + row].
struct Mat4 {
  std::array<float, 16> m = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
};
/// Axis-aligned box; empty when min > max on any axis.
struct Aabb {
  Vec3 min{1e30f, 1e30f, 1e30f};
  Vec3 max{-1e30f, -1e30f, -1e30f};
  bool empty() const { return min.x > max.x || min.y > max.y || min.z > max.z; }
  /// The box holding all of space: what a parallel light (the sun) or an
  /// emitter of unknown reach may touch.
  static Aabb everything() {
    return {{-kEverywhere, -kEverywhere, -kEverywhere}, {kEverywhere, kEverywhere, kEverywhere}};
  }
  bool isEverything() const { return max.x >= kEverywhere; }
  /// Beyond any level's coordinates, and still finite in float.
  static constexpr float kEverywhere = 3e38f;
};

/// Relative luminance Y of linear Rec.709 RGB (ITU-R BT.709 weights).
inline float luminance(const Rgb& c) { return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b; }

}  // namespace svit
