#pragma once
// Helpers shared by the scene tests: paths into tests/data, checks of a
// failed Status (code + message substrings), and small geometry helpers.

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

#include "svit/math_types.h"
#include "svit/scene.h"
#include "svit/status.h"

#ifndef SVIT_TEST_DATA_DIR
#error "SVIT_TEST_DATA_DIR must name tests/data (a string literal, no trailing slash)"
#endif

namespace svit::test {

/// Absolute path of a file in tests/data (written by tests/data/make_test_data.py).
inline std::string dataPath(std::string_view name) {
  return std::string(SVIT_TEST_DATA_DIR) + "/" + std::string(name);
}

/// Case-insensitive substring test, so checks do not depend on whether the
/// importer writes "Accessor" or "accessor", "POSITION" or "position".
inline bool containsNoCase(std::string_view haystack, std::string_view needle) {
  const auto it = std::search(haystack.begin(), haystack.end(), needle.begin(), needle.end(),
                              [](char a, char b) {
                                return std::tolower(static_cast<unsigned char>(a)) ==
                                       std::tolower(static_cast<unsigned char>(b));
                              });
  return it != haystack.end();
}

/// "invalid input: <message>", for failure output.
inline std::string describe(const Status& status) {
  return std::string(statusCodeName(status.code())) + ": " + status.message();
}

/// The lines of `lines`, each on its own line, for failure output.
inline std::string joinLines(const std::vector<std::string>& lines) {
  std::string out;
  for (const std::string& line : lines) out += "\n  " + line;
  return out;
}

/// Success when the message contains every one of `parts` (case-insensitive).
inline ::testing::AssertionResult messageHas(const Status& status,
                                             std::initializer_list<std::string_view> parts) {
  for (std::string_view part : parts) {
    if (!containsNoCase(status.message(), part)) {
      return ::testing::AssertionFailure()
             << "message lacks \"" << part << "\"; status was " << describe(status);
    }
  }
  return ::testing::AssertionSuccess();
}

/// Success when some warning contains every one of `parts` (case-insensitive).
inline ::testing::AssertionResult someWarningHas(const std::vector<std::string>& warnings,
                                                 std::initializer_list<std::string_view> parts) {
  for (const std::string& warning : warnings) {
    const bool all = std::all_of(parts.begin(), parts.end(), [&](std::string_view part) {
      return containsNoCase(warning, part);
    });
    if (all) return ::testing::AssertionSuccess();
  }
  ::testing::AssertionResult failure = ::testing::AssertionFailure();
  failure << "no warning contains all of {";
  for (std::string_view part : parts) failure << " \"" << part << "\"";
  failure << " }; warnings (" << warnings.size() << "):";
  for (const std::string& warning : warnings) failure << "\n  " << warning;
  return failure;
}

inline Vec3 sub(const Vec3& a, const Vec3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline float dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline float length(const Vec3& a) { return std::sqrt(dot(a, a)); }
inline Vec3 normalize(const Vec3& a) {
  const float len = length(a);
  return {a.x / len, a.y / len, a.z / len};
}

/// Corner `k` (0..2) of triangle `t`.
inline const Vec3& corner(const Mesh& mesh, size_t t, int k) {
  return mesh.positions.at(mesh.indices.at(3 * t + static_cast<size_t>(k)));
}

/// Unnormalised geometric normal of triangle `t`, (b - a) x (c - a): length = 2 x area.
inline Vec3 faceCross(const Mesh& mesh, size_t t) {
  const Vec3& a = corner(mesh, t, 0);
  return cross(sub(corner(mesh, t, 1), a), sub(corner(mesh, t, 2), a));
}

/// Sum of the triangle areas of `mesh`, m^2 (object space).
inline double meshArea(const Mesh& mesh) {
  double area = 0;
  for (size_t t = 0; t < mesh.triangleCount(); ++t) area += 0.5 * length(faceCross(mesh, t));
  return area;
}

/// Success when |a - b| <= tol on every component.
inline ::testing::AssertionResult vecNear(const Vec3& a, const Vec3& b, float tol) {
  if (std::abs(a.x - b.x) <= tol && std::abs(a.y - b.y) <= tol && std::abs(a.z - b.z) <= tol) {
    return ::testing::AssertionSuccess();
  }
  return ::testing::AssertionFailure()
         << "(" << a.x << ", " << a.y << ", " << a.z << ") vs (" << b.x << ", " << b.y << ", "
         << b.z << "), tolerance " << tol;
}

inline ::testing::AssertionResult rgbNear(const Rgb& a, const Rgb& b, float tol) {
  return vecNear(Vec3{a.r, a.g, a.b}, Vec3{b.r, b.g, b.b}, tol);
}

}  // namespace svit::test
