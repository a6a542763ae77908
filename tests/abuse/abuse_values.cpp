#include "abuse_values.h"

#include "box_mesh.h"

#include <cmath>
#include <limits>

namespace svit::abuse {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kHugeFloat = 3e38f;  // finite, and any product with it is not

template <typename T>
Arg<T> accept(T value) {
  return {std::move(value), Verdict::kAccept, ""};
}
template <typename T>
Arg<T> reject(T value, std::string names) {
  return {std::move(value), Verdict::kReject, std::move(names)};
}
template <typename T>
Arg<T> mayReject(T value, std::string names) {
  return {std::move(value), Verdict::kMayReject, std::move(names)};
}

Vec3 pointIn(Draws& draws, const LevelBox& box) {
  return {draws.between(box.min.x, box.max.x), draws.between(box.min.y, box.max.y),
          draws.between(box.min.z, box.max.z)};
}

Mat4 translation(const Vec3& at) {
  Mat4 m;
  m.m[12] = at.x;
  m.m[13] = at.y;
  m.m[14] = at.z;
  return m;
}

// A rotation about +Y by `angle` and a uniform `scale`, placed at `at`.
Mat4 placed(const Vec3& at, float angle, float scale) {
  Mat4 m = translation(at);
  m.m[0] = scale * std::cos(angle);
  m.m[2] = -scale * std::sin(angle);
  m.m[5] = scale;
  m.m[8] = scale * std::sin(angle);
  m.m[10] = scale * std::cos(angle);
  return m;
}

// A flat grid of `n` x `n` quads, 2 n^2 triangles: a detailed prop.
DynamicMesh grid(const std::string& name, int n, float size) {
  DynamicMesh mesh;
  mesh.name = name;
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) mesh.positions.push_back({size * i / n, 0, size * j / n});
  }
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const uint32_t a = uint32_t(j * (n + 1) + i), b = a + 1, c = a + uint32_t(n) + 1, d = c + 1;
      mesh.indices.insert(mesh.indices.end(), {a, c, b, b, c, d});
    }
  }
  return mesh;
}

Rgb colour(Draws& draws) {
  return {draws.between(0, 0.95f), draws.between(0, 0.95f), draws.between(0, 0.95f)};
}

}  // namespace

Arg<Mat4> drawTransform(Draws& draws, const LevelBox& box) {
  const Vec3 at = pointIn(draws, box);
  const float angle = draws.between(0, 6.2831853f);
  switch (draws.below(12)) {
    case 0: return accept(translation(at));
    case 1: return accept(placed(at, angle, draws.between(0.2f, 2.0f)));
    case 2: return accept(placed(at, angle, 0.0f));          // collapsed to a point
    case 3: return accept(placed(at, angle, -1.0f));         // mirrored
    case 4: return accept(placed(at, angle, 1e-30f));        // all but collapsed
    case 5: return accept(translation({5e5f, at.y, at.z}));  // 500 km away, inside the world
    case 6: {
      Mat4 m = translation(at);
      m.m[draws.below(16)] = kNaN;
      return reject(m, "transform");
    }
    case 7: {
      Mat4 m = translation(at);
      m.m[draws.below(16)] = draws.chance(2) ? kInf : -kInf;
      return reject(m, "transform");
    }
    case 8: return reject(translation({1e30f, at.y, at.z}), "beyond");
    case 9: return reject(placed(at, angle, 1e20f), "beyond");
    case 10: {
      Mat4 m = translation(at);
      m.m[3 + 4 * draws.below(3)] = 0.5f;  // a projective row: not a placement
      return reject(m, "affine");
    }
    default: {
      Mat4 m = translation(at);
      m.m[15] = 2.0f;
      return reject(m, "affine");
    }
  }
}

Arg<DynamicMesh> drawMesh(Draws& draws) {
  DynamicMesh mesh = test::boxMesh("prop", draws.between(0.02f, 0.3f));
  mesh.albedo = colour(draws);
  mesh.double_sided = draws.chance(4);
  switch (draws.below(14)) {
    case 0:
    case 1: return accept(mesh);
    case 2: {
      mesh.emission = {draws.between(0, 50), draws.between(0, 50), draws.between(0, 50)};
      return accept(mesh);
    }
    case 3: {
      mesh.positions.resize(3);
      mesh.indices = {0, 1, 2};
      return accept(mesh);
    }
    case 4: {
      for (Vec3& p : mesh.positions) p = {0.1f, 0.2f, 0.3f};  // every triangle of zero area
      return accept(mesh);
    }
    case 5: {
      DynamicMesh detailed = grid("detailed prop", 24, draws.between(0.1f, 1.0f));
      detailed.albedo = mesh.albedo;
      return accept(detailed);
    }
    case 6: {
      mesh.albedo = {0.999f, 0.999f, 0.999f};  // stiff: all but lossless
      return accept(mesh);
    }
    case 7: {
      mesh.emission = {1e6f, 1e6f, 1e6f};
      return mayReject(mesh, "emission");
    }
    case 8: mesh.indices.clear(); return reject(mesh, "indices");
    case 9: mesh.indices.pop_back(); return reject(mesh, "indices");
    case 10: mesh.indices[draws.below(36)] = 8 + draws.below(1000); return reject(mesh, "index");
    case 11: mesh.positions[draws.below(8)].y = kNaN; return reject(mesh, "position");
    case 12: mesh.albedo.g = draws.chance(2) ? 1.0f : -0.1f; return reject(mesh, "albedo");
    default: mesh.emission.r = draws.chance(2) ? -1.0f : kNaN; return reject(mesh, "emission");
  }
}

Arg<std::vector<Vec3>> drawPositions(Draws& draws, size_t count) {
  std::vector<Vec3> positions(count);
  const float size = draws.between(0.02f, 0.3f);
  for (Vec3& p : positions)
    p = {draws.between(-size, size), draws.between(-size, size), draws.between(-size, size)};
  switch (draws.below(5)) {
    case 0: positions.push_back({0, 0, 0}); return reject(positions, "positions");
    case 1:
      if (!positions.empty()) positions[draws.below(uint32_t(count))].z = kInf;
      return reject(positions, count == 0 ? "positions" : "position");
    case 2:
      for (Vec3& p : positions) p = {1e30f, 0, 0};
      return reject(positions, "beyond");
    default: return accept(positions);
  }
}

Arg<Light> drawLight(Draws& draws, const LevelBox& box) {
  Light light;
  light.name = "abuse lamp";
  light.position = pointIn(draws, box);
  light.intensity = draws.between(0.5f, 20.0f);
  light.color = {draws.between(0.2f, 1), draws.between(0.2f, 1), draws.between(0.2f, 1)};
  if (draws.chance(2)) {
    light.type = LightType::kSpot;
    light.direction = {draws.between(-1, 1), -1, draws.between(-1, 1)};
    light.outer_cone_rad = draws.between(0.2f, 1.5f);
    light.inner_cone_rad = light.outer_cone_rad * draws.unit() * 0.9f;
  }
  switch (draws.below(14)) {
    case 0:
    case 1:
    case 2: return accept(light);
    case 3: light.intensity = 0; return accept(light);
    case 4: light.intensity = 1e12f; return mayReject(light, "intensity");
    case 5: light.intensity = kHugeFloat; return mayReject(light, "intensity");
    case 6: light.intensity = -1; return reject(light, "intensity");
    case 7: light.intensity = kInf; return reject(light, "intensity");
    case 8: light.position.x = kNaN; return reject(light, "position");
    case 9: light.position.x = 1e30f; return reject(light, "beyond");
    case 10: light.color.b = -0.5f; return reject(light, "colour");
    case 11: light.type = LightType::kDirectional; return reject(light, "directional");
    case 12:
      light.type = LightType::kSpot;
      light.inner_cone_rad = 1.0f;
      light.outer_cone_rad = 0.5f;
      return reject(light, "cone");
    default:
      light.type = LightType::kSpot;
      light.direction = {0, 0, 0};
      return reject(light, "direction");
  }
}

Arg<float> drawScale(Draws& draws, const std::string& name) {
  switch (draws.below(10)) {
    case 0: return accept(0.0f);
    case 1: return accept(1.0f);
    case 2:
    case 3: return accept(draws.between(0, 2));
    case 4: return mayReject(1e6f, name);
    case 5: return mayReject(kHugeFloat, name);
    case 6: return reject(-draws.between(0.001f, 2), name);
    case 7: return reject(kNaN, name);
    case 8: return reject(kInf, name);
    default: return accept(draws.between(0, 0.5f));
  }
}

Arg<RuntimeView> drawView(Draws& draws, const LevelBox& box) {
  RuntimeView view;
  view.position = pointIn(draws, box);
  view.look_at = pointIn(draws, box);
  view.look_at.x += 0.01f;  // never the position itself by chance
  view.yfov_rad = draws.between(0.3f, 2.0f);
  view.aspect = draws.between(0.5f, 3.0f);
  switch (draws.below(10)) {
    case 0: view.yfov_rad = 0; return reject(view, "yfov_rad");
    case 1: view.yfov_rad = 3.1415927f; return reject(view, "yfov_rad");
    case 2: view.position.y = kNaN; return reject(view, "position");
    case 3: view.look_at = view.position; return reject(view, "look_at");
    case 4: view.up = {0, 0, 0}; return reject(view, "up");
    case 5: view.aspect = 0; return reject(view, "aspect");
    case 6: view.near_m = -draws.unit(); return reject(view, "near_m");
    default: return accept(view);
  }
}

Arg<Camera> drawCamera(Draws& draws, const LevelBox& box) {
  Camera camera;
  camera.position = pointIn(draws, box);
  camera.look_at = pointIn(draws, box);
  camera.look_at.z += 0.01f;
  camera.yfov_rad = draws.between(0.3f, 2.0f);
  switch (draws.below(10)) {
    case 0: camera.yfov_rad = 0; return reject(camera, "yfov_rad");
    case 1: camera.look_at.x = kInf; return reject(camera, "look_at");
    case 2: camera.near_m = camera.far_m; return reject(camera, "near");
    case 3: camera.far_m = kInf; return reject(camera, "far");
    case 4: camera.up = {0, 0, 0}; return reject(camera, "up");
    default: return accept(camera);
  }
}

Arg<int> drawSampleBudget(Draws& draws) {
  switch (draws.below(7)) {
    case 0: return accept(0);
    case 1: return accept(1);
    case 2: return accept(1000000000);
    case 3: return reject(-1, "max_samples_per_frame");
    case 4: return reject(std::numeric_limits<int>::min(), "max_samples_per_frame");
    default: return accept(int(1 + draws.below(32)));
  }
}

Arg<double> drawUpdateBudget(Draws& draws) {
  switch (draws.below(8)) {
    case 0: return accept(1e9);
    case 1: return accept(double(kInf));
    case 2: return reject(-1.0, "budget_ms");
    case 3: return reject(double(kNaN), "budget_ms");
    case 4: return reject(-double(kInf), "budget_ms");
    default: return accept(0.0);
  }
}

Arg<ShadingView> drawShadingView(Draws& draws) {
  const uint32_t value = draws.below(8);
  if (value < 3) return accept(ShadingView(value));
  return reject(ShadingView(value == 7 ? 255 : value), "view");
}

Arg<uint32_t> drawId(Draws& draws, const std::vector<uint32_t>& live,
                     const std::vector<uint32_t>& gone, uint32_t issued, const std::string& what) {
  const uint32_t kind = draws.below(8);
  if (kind < 5 && !live.empty()) return accept(live[draws.below(uint32_t(live.size()))]);
  if (kind == 5 && !gone.empty()) {
    const uint32_t id = gone[draws.below(uint32_t(gone.size()))];
    return reject(id, what + " " + std::to_string(id));
  }
  const uint32_t unknown = kind == 7 ? kInvalidId : issued + draws.below(3);
  return reject(unknown, what + " " + std::to_string(unknown));
}

}  // namespace svit::abuse
