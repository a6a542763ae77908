#include "leak_levels.h"

#include <utility>

namespace svit::test {
namespace {

// The room every sunlit level seals: 3 m square, 2.5 m high, on the ground.
constexpr float kRoomHalf = 1.5f, kRoomHeight = 2.5f;
// Walls built as slabs are this thick (outwards of the room).
constexpr float kSlab = 0.2f;

const char* const kSun = R"({"direction_to_sun": [0.4, 1.0, 0.3], "illuminance_lux": 100000})";
const char* const kSky = R"({"model": "uniform", "zenith_luminance": [3000, 3000, 3000]})";

ProbePoint probe(Vec3 position, Vec3 normal) { return {position, normal}; }

/// The sunlit outside: a 20 m ground of two triangles (each runs under the
/// room), a crate resting on it, probes on open ground and under the crate.
LeakLevel sunlitGround(const std::string& name) {
  LeakLevel level;
  level.name = name;
  level.sun_json = kSun;
  level.sky_json = kSky;
  SceneBuilder b;
  const int grey = b.material({0.5f, 0.5f, 0.5f});
  b.addQuad("ground", {-10, 0, -10}, {-10, 0, 10}, {10, 0, 10}, {10, 0, -10}, grey);
  b.addMesh("crate", boxCorners({4, 0, -5}, {5, 1, -4}), grey);
  level.scene = std::move(b.scene());
  level.lit = {probe({6, 0.01f, 6}, {0, 1, 0}), probe({-6, 0.01f, 3}, {0, 1, 0}),
               probe({4.5f, 0.01f, -3.5f}, {0, 1, 0})};
  level.dark = {probe({4.5f, 0.001f, -4.5f}, {0, 1, 0}), probe({4.2f, 0.001f, -4.2f}, {0, 1, 0})};
  level.edge = {probe({4.05f, 0.001f, -4.5f}, {0, 1, 0})};
  return level;
}

/// Probes on every inner face of the sealed room (inner half-width `half`),
/// and on its floor 2 cm from a wall and in a corner.
void addRoomProbes(LeakLevel& level, float half) {
  const float near = half - 0.15f, at = half - 0.02f;
  level.dark.push_back(probe({0, 0.01f, 0}, {0, 1, 0}));
  level.dark.push_back(probe({near, 0.01f, 0.3f}, {0, 1, 0}));    // the floor near a wall
  level.dark.push_back(probe({-near, 0.01f, -near}, {0, 1, 0}));  // and near a corner
  level.edge.push_back(probe({at, 0.01f, 0.3f}, {0, 1, 0}));
  level.edge.push_back(probe({-at, 0.01f, -at}, {0, 1, 0}));
  level.dark.push_back(probe({-half + 0.01f, 1.2f, 0.5f}, {1, 0, 0}));
  level.dark.push_back(probe({half - 0.01f, 0.1f, -0.5f}, {-1, 0, 0}));
  level.dark.push_back(probe({0.4f, 1.3f, half - 0.01f}, {0, 0, -1}));
  level.dark.push_back(probe({0.3f, kRoomHeight - 0.01f, -0.3f}, {0, -1, 0}));
}

/// glTF carries a light on a node; writeGltf writes only those.
void hangOnNode(Scene& scene, Light& light) {
  Node node;
  node.name = light.name;
  node.has_trs = true;
  node.translation = light.position;
  scene.nodes.push_back(node);
  light.node = int(scene.nodes.size() - 1);
}

int grey(SceneBuilder& b) { return b.material({0.5f, 0.5f, 0.5f}); }

// ------------------------------------------------------------ the cases

/// One closed inward mesh, its floor on the ground.
LeakLevel inwardRoom() {
  LeakLevel level = sunlitGround("inward room");
  SceneBuilder b;
  b.scene() = std::move(level.scene);
  b.addMesh("room", roomCorners({-kRoomHalf, 0, -kRoomHalf}, {kRoomHalf, kRoomHeight, kRoomHalf}),
            grey(b));
  level.scene = std::move(b.scene());
  addRoomProbes(level, kRoomHalf);
  return level;
}

/// Four walls and a ceiling, inward, standing on the ground: the ground's
/// triangles run under the walls from outside to inside.
LeakLevel wallsOnGround() {
  LeakLevel level = sunlitGround("walls on the ground");
  SceneBuilder b;
  b.scene() = std::move(level.scene);
  std::vector<Vec3> corners =
      roomCorners({-kRoomHalf, 0, -kRoomHalf}, {kRoomHalf, kRoomHeight, kRoomHalf});
  corners.erase(corners.begin(), corners.begin() + 6);  // no floor of its own
  b.addMesh("walls", corners, grey(b));
  level.scene = std::move(b.scene());
  addRoomProbes(level, kRoomHalf);
  return level;
}

/// Six separate inward quads; each reaches `overlap` metres past the
/// others at the corners (0: they touch along edges, nothing shared).
LeakLevel quadRoom(const std::string& name, float overlap) {
  LeakLevel level = sunlitGround(name);
  SceneBuilder b;
  b.scene() = std::move(level.scene);
  const int m = grey(b);
  const float h = kRoomHalf, o = kRoomHalf + overlap, y1 = kRoomHeight, yo = kRoomHeight + overlap;
  b.addQuad("floor", {-o, 0, -o}, {-o, 0, o}, {o, 0, o}, {o, 0, -o}, m);
  b.addQuad("ceiling", {-o, y1, -o}, {o, y1, -o}, {o, y1, o}, {-o, y1, o}, m);
  b.addQuad("wall -x", {-h, 0, -o}, {-h, yo, -o}, {-h, yo, o}, {-h, 0, o}, m);
  b.addQuad("wall +x", {h, 0, -o}, {h, 0, o}, {h, yo, o}, {h, yo, -o}, m);
  b.addQuad("wall -z", {-o, 0, -h}, {o, 0, -h}, {o, yo, -h}, {-o, yo, -h}, m);
  b.addQuad("wall +z", {-o, 0, h}, {-o, yo, h}, {o, yo, h}, {o, 0, h}, m);
  level.scene = std::move(b.scene());
  addRoomProbes(level, kRoomHalf);
  return level;
}

/// Walls as slabs that meet their neighbours only along an edge (the corner
/// columns stay empty), standing on the ground, under a roof slab; probes
/// also on the ground under the walls.
LeakLevel edgeSlabs() {
  LeakLevel level = sunlitGround("slabs touching along edges");
  SceneBuilder b;
  b.scene() = std::move(level.scene);
  const int m = grey(b);
  const float h = kRoomHalf, s = kRoomHalf + kSlab, y1 = kRoomHeight;
  b.addMesh("slab -x", boxCorners({-s, 0, -h}, {-h, y1, h}), m);
  b.addMesh("slab +x", boxCorners({h, 0, -h}, {s, y1, h}), m);
  b.addMesh("slab -z", boxCorners({-h, 0, -s}, {h, y1, -h}), m);
  b.addMesh("slab +z", boxCorners({-h, 0, h}, {h, y1, s}), m);
  b.addMesh("roof", boxCorners({-s, y1, -s}, {s, y1 + kSlab, s}), m);
  level.scene = std::move(b.scene());
  addRoomProbes(level, kRoomHalf);
  level.dark.push_back(probe({-h - kSlab / 2, 0.001f, 0.2f}, {0, 1, 0}));  // under a wall
  level.dark.push_back(probe({0.4f, 0.001f, h + kSlab / 2}, {0, 1, 0}));
  return level;
}

/// A hollow box: a closed outward shell with a closed inward room inside
/// it, resting on the ground. Nothing crosses its walls; only the ambient
/// estimate could light the room.
LeakLevel hollowBox() {
  LeakLevel level = sunlitGround("hollow box");
  SceneBuilder b;
  b.scene() = std::move(level.scene);
  const int m = grey(b);
  const float h = kRoomHalf, s = kRoomHalf + kSlab;
  b.addMesh("shell", boxCorners({-s, 0, -s}, {s, kRoomHeight + 2 * kSlab, s}), m);
  b.addMesh("room", roomCorners({-h, kSlab, -h}, {h, kRoomHeight + kSlab, h}), m);
  level.scene = std::move(b.scene());
  level.dark.push_back(probe({0, kSlab + 0.01f, 0}, {0, 1, 0}));
  level.dark.push_back(probe({-h + 0.01f, 1.2f, 0.5f}, {1, 0, 0}));
  level.dark.push_back(probe({0.3f, kRoomHeight + kSlab - 0.01f, -0.3f}, {0, -1, 0}));
  return level;
}

/// Two rooms in one inward box split by a partition at x = 0; a lamp in the
/// -x room. A double-sided partition has a lightmap per side. The floor, ceiling and side walls run
/// under the partition from one room to the other.
LeakLevel partitionedRooms(const std::string& name, bool double_sided) {
  LeakLevel level;
  level.name = name;
  SceneBuilder b;
  const int m = grey(b);
  const int partition = b.material({0.5f, 0.5f, 0.5f}, {0, 0, 0}, double_sided);
  const float w = 2 * kRoomHalf, h = kRoomHalf, y1 = kRoomHeight;
  b.addMesh("rooms", roomCorners({-w, 0, -h}, {w, y1, h}), m);
  // faces -x: the lit room sees its front
  b.addQuad("partition", {0, 0, -h}, {0, 0, h}, {0, y1, h}, {0, y1, -h}, partition);
  b.addPointLight({-h, 1.5f, 0}, 100.0f);
  level.scene = std::move(b.scene());
  hangOnNode(level.scene, level.scene.lights.back());
  for (float sign : {-1.0f, 1.0f}) {
    std::vector<ProbePoint>& probes = sign < 0 ? level.lit : level.dark;
    probes.push_back(probe({sign * 1.0f, 0.01f, 0.3f}, {0, 1, 0}));
    // the floor near the partition
    probes.push_back(probe({sign * 0.15f, 0.01f, -0.6f}, {0, 1, 0}));
    if (sign > 0) level.edge.push_back(probe({0.02f, 0.01f, -0.6f}, {0, 1, 0}));
    probes.push_back(probe({sign * 2.0f, 1.2f, -h + 0.01f}, {0, 0, 1}));
    // The partition; a one-sided one has no surface on the dark side.
    if (sign < 0 || double_sided) probes.push_back(probe({sign * 0.01f, 1.3f, 0.2f}, {sign, 0, 0}));
    probes.push_back(probe({sign * (w - 0.01f), 1.0f, 0}, {-sign, 0, 0}));
    probes.push_back(probe({sign * 1.5f, y1 - 0.01f, 0.4f}, {0, -1, 0}));
  }
  return level;
}

}  // namespace

std::vector<LeakLevel> leakLevels() {
  std::vector<LeakLevel> levels;
  levels.push_back(inwardRoom());
  levels.push_back(wallsOnGround());
  levels.push_back(quadRoom("overlapping quads", 0.25f));
  levels.push_back(quadRoom("touching quads", 0.0f));
  levels.push_back(edgeSlabs());
  levels.push_back(hollowBox());
  levels.push_back(partitionedRooms("one-sided partition", false));
  levels.push_back(partitionedRooms("double-sided partition", true));
  return levels;
}

}  // namespace svit::test
