#pragma once
// Conversions between svit's public POD math types and GLM, used inside the
// libraries only (GLM never appears in a public header).

#include <cstring>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "svit/math_types.h"

namespace svit {

inline glm::vec2 toGlm(const Vec2& v) { return {v.x, v.y}; }
inline glm::vec3 toGlm(const Vec3& v) { return {v.x, v.y, v.z}; }
inline glm::vec3 toGlm(const Rgb& c) { return {c.r, c.g, c.b}; }
inline glm::quat toGlm(const Quat& q) { return glm::quat(q.w, q.x, q.y, q.z); }
inline glm::mat4 toGlm(const Mat4& m) {
  glm::mat4 out;
  std::memcpy(&out[0][0], m.m.data(), sizeof(float) * 16);  // both column-major
  return out;
}
inline Vec2 fromGlm(const glm::vec2& v) { return {v.x, v.y}; }
inline Vec3 fromGlm(const glm::vec3& v) { return {v.x, v.y, v.z}; }
inline Rgb rgbFromGlm(const glm::vec3& v) { return {v.x, v.y, v.z}; }
inline Quat fromGlm(const glm::quat& q) { return {q.x, q.y, q.z, q.w}; }
inline Mat4 fromGlm(const glm::mat4& m) {
  Mat4 out;
  std::memcpy(out.m.data(), &m[0][0], sizeof(float) * 16);
  return out;
}

/// Point transform (w = 1).
inline glm::vec3 transformPoint(const glm::mat4& m, const glm::vec3& p) {
  return glm::vec3(m * glm::vec4(p, 1.0f));
}

}  // namespace svit
