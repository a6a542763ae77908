// svit-walk's motion: level.json path keys, glTF animation tracks (linear,
// step, cubic spline; translation, rotation, scale), camera keys, and the
// node hierarchy (world = parent world x local TRS). Expectations are exact
// values of the interpolants; tolerances are float rounding (1e-5 relative
// to unit-sized values).

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "walk_animation.h"
#include "walk_motion.h"

namespace svit::walk {
namespace {

constexpr float kEps = 1e-5f;

Quat aboutY(float angle_rad) { return {0, std::sin(angle_rad / 2), 0, std::cos(angle_rad / 2)}; }

float angleAboutY(const Quat& q) { return 2 * std::atan2(q.y, q.w); }

void expectVec(const Vec3& v, float x, float y, float z) {
  EXPECT_NEAR(v.x, x, kEps);
  EXPECT_NEAR(v.y, y, kEps);
  EXPECT_NEAR(v.z, z, kEps);
}

PathKey key(float t_s, Vec3 translation, Quat rotation = {}, Vec3 scale = {1, 1, 1}) {
  return {t_s, translation, rotation, scale};
}

TEST(WalkAnimation, PathKeysInterpolateLinearlyAndSlerp) {
  const std::vector<PathKey> keys = {key(0, {0, 0, 0}),
                                     key(2, {2, 4, -2}, aboutY(1.0f), {3, 1, 1})};
  const Trs mid = samplePathKeys(keys, 1.0f, false);
  expectVec(mid.translation, 1, 2, -1);
  expectVec(mid.scale, 2, 1, 1);
  EXPECT_NEAR(angleAboutY(mid.rotation), 0.5f, kEps);  // slerp: half the angle at half the time
  const Trs quarter = samplePathKeys(keys, 0.5f, false);
  EXPECT_NEAR(angleAboutY(quarter.rotation), 0.25f, kEps);
}

TEST(WalkAnimation, PathKeysClampOrLoop) {
  const std::vector<PathKey> keys = {key(1, {1, 0, 0}), key(3, {3, 0, 0})};
  expectVec(samplePathKeys(keys, 0.0f, false).translation, 1, 0, 0);   // before the first key
  expectVec(samplePathKeys(keys, 10.0f, false).translation, 3, 0, 0);  // after the last
  // Looping wraps at the last key's time: t = 3.5 -> 0.5, before the first key.
  expectVec(samplePathKeys(keys, 3.5f, true).translation, 1, 0, 0);
  expectVec(samplePathKeys(keys, 5.0f, true).translation, 2, 0, 0);  // 5 -> 2
  const std::vector<PathKey> one = {key(0, {7, 8, 9})};
  expectVec(samplePathKeys(one, 4.0f, true).translation, 7, 8, 9);
}

TEST(WalkAnimation, RotationTakesTheShortestArc) {
  // q and -q are the same rotation: the path between them must not turn.
  const Quat q = aboutY(0.3f);
  const std::vector<PathKey> keys = {key(0, {}, q), key(1, {}, Quat{-q.x, -q.y, -q.z, -q.w})};
  const Trs mid = samplePathKeys(keys, 0.5f, false);
  EXPECT_NEAR(std::fabs(angleAboutY(mid.rotation)), 0.3f, 1e-4f);
}

TEST(WalkAnimation, ClipTime) {
  EXPECT_FLOAT_EQ(clipTime(2.5f, 2.0f, true), 0.5f);
  EXPECT_FLOAT_EQ(clipTime(2.5f, 2.0f, false), 2.0f);
  EXPECT_FLOAT_EQ(clipTime(-1.0f, 2.0f, false), 0.0f);
  EXPECT_FLOAT_EQ(clipTime(5.0f, 0.0f, true), 0.0f);  // a clip of no length
}

AnimationTrack track(AnimationPath path, Interpolation interpolation, std::vector<float> times,
                     std::vector<float> values) {
  AnimationTrack t;
  t.path = path;
  t.interpolation = interpolation;
  t.times_s = std::move(times);
  t.values = std::move(values);
  t.components = path == AnimationPath::kRotation ? 4 : 3;
  return t;
}

TEST(WalkAnimation, LinearAndStepTracks) {
  const AnimationTrack linear = track(AnimationPath::kTranslation, Interpolation::kLinear,
                                      {0, 1, 3}, {0, 0, 0, 1, 0, 0, 1, 4, 0});
  Trs trs;
  applyTrack(linear, 2.0f, trs);
  expectVec(trs.translation, 1, 2, 0);
  const AnimationTrack step =
      track(AnimationPath::kScale, Interpolation::kStep, {0, 1}, {1, 1, 1, 2, 2, 2});
  applyTrack(step, 0.99f, trs);
  expectVec(trs.scale, 1, 1, 1);  // holds the earlier key
  applyTrack(step, 1.0f, trs);
  expectVec(trs.scale, 2, 2, 2);
  expectVec(trs.translation, 1, 2, 0);  // other channels untouched
}

TEST(WalkAnimation, LinearRotationTrackSlerps) {
  const Quat a = aboutY(0), b = aboutY(1.5f);
  const AnimationTrack rotation = track(AnimationPath::kRotation, Interpolation::kLinear, {0, 2},
                                        {a.x, a.y, a.z, a.w, b.x, b.y, b.z, b.w});
  Trs trs;
  applyTrack(rotation, 0.5f, trs);
  EXPECT_NEAR(angleAboutY(trs.rotation), 0.375f, kEps);
}

TEST(WalkAnimation, CubicSplineTrack) {
  // Keys (in-tangent, value, out-tangent) per glTF. With tangents equal to
  // the slope the Hermite spline reproduces the line: x = t over [0, 2].
  const AnimationTrack line =
      track(AnimationPath::kTranslation, Interpolation::kCubicSpline, {0, 2},
            {1, 0, 0, 0, 0, 0, 1, 0, 0,  //
             1, 0, 0, 2, 0, 0, 1, 0, 0});
  Trs trs;
  applyTrack(line, 0.5f, trs);
  expectVec(trs.translation, 0.5f, 0, 0);
  // Zero tangents give smoothstep: h01(0.25) = 3u^2 - 2u^3 = 0.15625.
  const AnimationTrack ease =
      track(AnimationPath::kTranslation, Interpolation::kCubicSpline, {0, 1},
            {0, 0, 0, 0, 0, 0, 0, 0, 0,  //
             0, 0, 0, 0, 4, 0, 0, 0, 0});
  applyTrack(ease, 0.25f, trs);
  expectVec(trs.translation, 0, 4 * 0.15625f, 0);
  applyTrack(ease, 5.0f, trs);  // past the end: the last value
  expectVec(trs.translation, 0, 4, 0);
}

TEST(WalkAnimation, CameraKeys) {
  CameraKey a, b;
  a.t_s = 0, a.position = {0, 0, 0}, a.look_at = {0, 0, -1}, a.yfov_rad = 1.0f;
  b.t_s = 4, b.position = {4, 0, 0}, b.look_at = {4, 0, -1}, b.yfov_rad = 0.5f;
  const std::vector<CameraKey> keys = {a, b};
  const CameraKey c = sampleCameraKeys(keys, 1.0f, false);
  expectVec(c.position, 1, 0, 0);
  expectVec(c.look_at, 1, 0, -1);
  EXPECT_NEAR(c.yfov_rad, 0.875f, kEps);
  expectVec(sampleCameraKeys(keys, 9.0f, false).position, 4, 0, 0);
  expectVec(sampleCameraKeys(keys, 5.0f, true).position, 1, 0, 0);
}

TEST(WalkAnimation, ComposeTrsIsTranslateRotateScale) {
  const Mat4 m = composeTrs({{1, 2, 3}, aboutY(1.5707963f), {2, 1, 1}});
  // x axis scaled by 2 then turned a quarter about +y: (0, 0, -2).
  EXPECT_NEAR(m.m[0], 0, kEps);
  EXPECT_NEAR(m.m[2], -2, kEps);
  EXPECT_NEAR(m.m[12], 1, kEps);
  EXPECT_NEAR(m.m[13], 2, kEps);
  EXPECT_NEAR(m.m[14], 3, kEps);
}

// A static root translated by (10, 0, 0), a dynamic "arm" under it that
// follows a path, a "box" mesh under the arm, and a glTF animation that
// spins a "wheel" under the box.
Scene hierarchyScene() {
  Scene scene;
  auto addNode = [&](const std::string& name, int parent, Vec3 translation, bool dynamic) {
    Node node;
    node.name = name;
    node.parent = parent;
    node.translation = translation;
    node.parent_from_node = composeTrs({translation, {}, {1, 1, 1}});
    const glm::mat4 parent_world =
        parent >= 0 ? glm::make_mat4(scene.nodes[size_t(parent)].world_from_node.m.data())
                    : glm::mat4(1);
    const glm::mat4 world = parent_world * glm::make_mat4(node.parent_from_node.m.data());
    std::memcpy(node.world_from_node.m.data(), &world[0][0], sizeof(float) * 16);
    node.dynamic = dynamic;
    if (parent >= 0) scene.nodes[size_t(parent)].children.push_back(int(scene.nodes.size()));
    scene.nodes.push_back(node);
    return int(scene.nodes.size()) - 1;
  };
  const int root = addNode("root", -1, {10, 0, 0}, false);
  const int arm = addNode("arm", root, {0, 1, 0}, true);
  const int box = addNode("box", arm, {0, 0, 1}, true);
  const int wheel = addNode("wheel", box, {0, 0, 0}, true);
  scene.instances.push_back({box, 0, scene.nodes[size_t(box)].world_from_node, true});
  ObjectPath path;
  path.node = arm;
  path.loop = false;
  path.keys = {key(0, {0, 1, 0}), key(2, {0, 1, 4})};
  scene.object_paths.push_back(path);
  Animation spin;
  spin.duration_s = 1;
  const Quat a = aboutY(0), b = aboutY(1.0f);
  AnimationTrack t = track(AnimationPath::kRotation, Interpolation::kLinear, {0, 1},
                           {a.x, a.y, a.z, a.w, b.x, b.y, b.z, b.w});
  t.node = wheel;
  spin.tracks.push_back(t);
  scene.animations.push_back(spin);
  ObjectPath spin_path;
  spin_path.node = box;  // the animation's tracks under the path's node play
  spin_path.animation = 0;
  scene.object_paths.push_back(spin_path);
  return scene;
}

Vec3 translationOf(const Mat4& m) { return {m.m[12], m.m[13], m.m[14]}; }

TEST(WalkMotion, WorldIsParentWorldTimesLocal) {
  const Scene scene = hierarchyScene();
  LevelMotion motion(scene);
  motion.advance(1.0f);  // arm at (0, 1, 2) under the root at (10, 0, 0); box 1 m further in z
  expectVec(translationOf(motion.worldFromNode(1)), 10, 1, 2);
  expectVec(translationOf(motion.worldFromNode(2)), 10, 1, 3);
  ASSERT_EQ(motion.objectNodes().size(), 1u);
  EXPECT_EQ(motion.objectNodes()[0], 2);
  // The static root keeps the loader's matrix bit for bit.
  EXPECT_EQ(motion.worldFromNode(0).m, scene.nodes[0].world_from_node.m);
  // The looping 1 s glTF clip at t = 1.5 s plays its middle: the wheel has turned 0.5 of 1 rad.
  motion.advance(1.5f);
  EXPECT_NEAR(angleAboutY(motion.localTrs(3).rotation), 0.5f, kEps);
}

TEST(WalkMotion, AMovedNodeStopsFollowingItsPath) {
  const Scene scene = hierarchyScene();
  LevelMotion motion(scene);
  motion.advance(0.5f);
  motion.moveNode(1, {{0, 5, 0}, {}, {1, 1, 1}});
  motion.advance(2.0f);  // the path would put the arm at z = 4
  expectVec(translationOf(motion.worldFromNode(1)), 10, 5, 0);
  expectVec(translationOf(motion.worldFromNode(2)), 10, 5, 1);  // children follow
}

}  // namespace
}  // namespace svit::walk
