#pragma once
// The scene model shared by the baker, the runtime and the samples: meshes,
// materials, the flattened node hierarchy, lights, sun, sky and paths.
// Units (docs/architecture.md "Units and conventions"): metres, radians,
// candela (point/spot), lux (directional, sun), cd/m2 (emissive and sky
// luminance); linear Rec.709 RGB; +Y up.

#include <cstdint>
#include <string>
#include <vector>

#include "svit/math_types.h"

namespace svit {

/// glTF sampler wrap mode.
enum class WrapMode { kRepeat, kClampToEdge, kMirroredRepeat };

/// An 8-bit image as decoded from the file. Colour textures (base colour,
/// emission) hold sRGB-encoded values; sampling helpers decode to linear.
struct Texture {
  std::string name;  ///< image name or URI, for messages
  int width = 0;
  int height = 0;
  int channels = 0;             ///< 1..4 as stored in `texels`
  std::vector<uint8_t> texels;  ///< row-major, first row is v = 0 (glTF convention)
  WrapMode wrap_s = WrapMode::kRepeat;
  WrapMode wrap_t = WrapMode::kRepeat;
};

/// A material's use of a texture, with KHR_texture_transform applied as
/// uv' = offset + R(rotation) * (scale * uv).
struct TextureRef {
  int texture = -1;  ///< index into Scene::textures; -1 = none (or missing file)
  int texcoord = 0;  ///< UV set: 0 = TEXCOORD_0, 1 = TEXCOORD_1
  Vec2 offset{0, 0};
  float rotation_rad = 0;
  Vec2 scale{1, 1};
};

enum class AlphaMode { kOpaque, kMask, kBlend };

/// Diffuse material. The solver uses the per-triangle means in Mesh; the
/// lightmapper samples the textures per texel.
struct Material {
  std::string name;
  Rgb base_color{1, 1, 1};  ///< linear baseColorFactor.rgb (diffuse albedo before texture)
  float base_alpha = 1;     ///< baseColorFactor.a
  TextureRef base_color_texture;
  /// Emitted luminance in cd/m2 before the texture: emissiveFactor x
  /// KHR_materials_emissive_strength. A Lambertian surface of luminance L has
  /// exitance pi*L lm/m2 from each emitting side.
  Rgb emissive_luminance{0, 0, 0};
  TextureRef emissive_texture;
  bool double_sided = false;  ///< false: receives, reflects and emits on the front only
  AlphaMode alpha_mode = AlphaMode::kOpaque;
  float alpha_cutoff = 0.5f;
};

/// Where a triangle came from in the glTF, for messages and tooling.
struct TriangleSource {
  uint32_t primitive = 0;  ///< primitive index within the glTF mesh
  uint32_t triangle = 0;   ///< triangle index within that primitive (after strip/fan conversion)
};

/// One glTF mesh with all its triangle primitives merged. Every triangle has
/// positive area and finite data; degenerate ones were skipped at import.
struct Mesh {
  std::string name;
  std::vector<Vec3> positions;    ///< object space, metres
  std::vector<Vec3> normals;      ///< unit length, one per position
  std::vector<Vec2> uv0;          ///< TEXCOORD_0, empty when no primitive has it
  std::vector<Vec2> uv1;          ///< TEXCOORD_1 (authored lightmap UVs), empty when absent
  std::vector<uint32_t> indices;  ///< 3 per triangle, front face counter-clockwise
  std::vector<uint32_t> triangle_material;  ///< per triangle, index into Scene::materials
  /// per triangle: base colour x mean texture over the triangle
  std::vector<Rgb> triangle_albedo;
  std::vector<Rgb> triangle_emission;           ///< per triangle: mean emitted luminance, cd/m2
  std::vector<TriangleSource> triangle_source;  ///< per triangle
  size_t triangleCount() const { return indices.size() / 3; }
};

/// A node of the glTF hierarchy (lights and level.json nodes included).
struct Node {
  std::string name;
  int parent = -1;
  std::vector<int> children;
  int mesh = -1;  ///< index into Scene::meshes or -1
  /// Local transform. TRS is kept for animation; `parent_from_node` is
  /// always valid (glTF `matrix`, or T*R*S).
  Vec3 translation{0, 0, 0};
  Quat rotation{};
  Vec3 scale{1, 1, 1};
  bool has_trs = true;  ///< false when the glTF gave a matrix
  Mat4 parent_from_node;
  Mat4 world_from_node;
  /// moves at run time (extras.svit.dynamic or level.json, inherited by children)
  bool dynamic = false;
  bool animated = false;  ///< a glTF animation channel targets this node or an ancestor
  int camera = -1;        ///< glTF camera index it places, or -1
};

/// A mesh placed in the world: one per node that holds a mesh.
struct Instance {
  int node = -1;
  int mesh = -1;
  Mat4 world_from_object;
  bool dynamic = false;
};

enum class LightType { kPoint, kSpot, kDirectional };

/// A punctual light placed in the world (KHR_lights_punctual or level.json).
struct Light {
  std::string name;
  LightType type = LightType::kPoint;
  Rgb color{1, 1, 1};        ///< linear, multiplies intensity
  float intensity = 0;       ///< candela (point, spot) or lux (directional); >= 0
  float range_m = 0;         ///< 0 = unlimited
  float inner_cone_rad = 0;  ///< spot: full intensity inside
  float outer_cone_rad = 0.78539816339744831f;  ///< spot: zero outside; inner < outer <= pi/2
  Vec3 position{0, 0, 0};                       ///< world, metres (point, spot)
  Vec3 direction{0, 0, -1};  ///< world, unit, the way light travels (spot, directional)
  int node = -1;             ///< node it hangs on, -1 for level.json lights
  bool dynamic = false;      ///< a runtime light (moved/switched by the game), not baked
};

/// The sun: a directional light with an angular radius (soft shadows).
struct Sun {
  bool enabled = false;
  Vec3 direction_to_sun{0, 1, 0};       ///< world, unit, from the scene towards the sun
  float illuminance_lux = 0;            ///< on a surface facing the sun
  float angular_radius_rad = 0.00465f;  ///< the real sun's
  Rgb color{1, 1, 1};
};

enum class SkyModel { kNone, kUniform, kGradient };

/// Sky at infinity. Uniform: `zenith_luminance` everywhere above the horizon.
/// Gradient: luminance blends from horizon to zenith with the cosine of the
/// zenith angle; `ground_luminance` below the horizon.
struct Sky {
  SkyModel model = SkyModel::kNone;
  Rgb zenith_luminance{0, 0, 0};   ///< cd/m2
  Rgb horizon_luminance{0, 0, 0};  ///< cd/m2, gradient only
  Rgb ground_luminance{0, 0, 0};   ///< cd/m2, gradient only
};

enum class AnimationPath { kTranslation, kRotation, kScale, kWeights };
enum class Interpolation { kLinear, kStep, kCubicSpline };

/// One glTF animation channel with its sampler resolved.
struct AnimationTrack {
  int node = -1;
  AnimationPath path = AnimationPath::kTranslation;
  Interpolation interpolation = Interpolation::kLinear;
  std::vector<float> times_s;  ///< ascending
  std::vector<float> values;   ///< components per key (x3 for cubic spline: in, value, out)
  int components = 3;          ///< 3 (T, S), 4 (R), morph target count (weights)
};

struct Animation {
  std::string name;
  std::vector<AnimationTrack> tracks;
  float duration_s = 0;
};

/// A key of an object path from level.json.
struct PathKey {
  float t_s = 0;
  Vec3 translation{0, 0, 0};
  Quat rotation{};
  Vec3 scale{1, 1, 1};
};

/// How a dynamic node moves: its keys, or a glTF animation (`animation` >= 0).
struct ObjectPath {
  int node = -1;
  bool loop = true;
  std::vector<PathKey> keys;
  int animation = -1;  ///< index into Scene::animations, or -1
};

struct CameraKey {
  float t_s = 0;
  Vec3 position{0, 0, 0};
  Vec3 look_at{0, 0, -1};
  float yfov_rad = 1.0471975512f;  ///< 60 degrees
};

struct CameraPath {
  std::string name;
  bool loop = false;
  std::vector<CameraKey> keys;
};

/// A viewpoint the glTF names: a node holding a perspective camera, placed
/// by the node's world transform (glTF cameras look down their node's -Z,
/// +Y up). Cameras do not change the lighting: they are not in the level
/// hash.
struct SceneCamera {
  std::string name;  ///< the camera's name, else its node's, else "camera N"
  int node = -1;
  Vec3 position{0, 0, 0};
  Vec3 forward{0, 0, -1};  ///< world, unit
  Vec3 up{0, 1, 0};        ///< world, unit, perpendicular to forward
  float yfov_rad = 1.0471975512f;
  float near_m = 0.05f;
  float far_m = 0;  ///< 0: the glTF gives none (an infinite projection)
};

/// Counters of what import skipped or repaired; each also has a line in
/// Scene::warnings naming the element.
struct ImportCounters {
  size_t zero_area_triangles = 0;  ///< skipped
  size_t skipped_point_line_primitives = 0;
  size_t missing_textures = 0;  ///< the material's factor is used alone
  size_t meshes_with_generated_normals = 0;
  size_t repaired_normals = 0;      ///< zero-length normals replaced by the face normal
  size_t degenerate_instances = 0;  ///< singular world transform: skipped
};

/// A loaded level: the glTF plus what level.json adds.
struct Scene {
  std::string source_path;  ///< the file that was loaded (.gltf, .glb or level .json)
  std::string gltf_path;    ///< the glTF it names (same as source_path for a bare glTF)
  std::vector<Texture> textures;
  std::vector<Material> materials;
  std::vector<Mesh> meshes;
  std::vector<Node> nodes;
  std::vector<Instance> instances;
  std::vector<Light> lights;
  std::vector<Animation> animations;
  Sun sun;
  Sky sky;
  std::vector<ObjectPath> object_paths;
  std::vector<CameraPath> camera_paths;
  std::vector<SceneCamera> cameras;  ///< the glTF's, in node order
  std::vector<std::string> warnings;
  ImportCounters counters;

  /// Index of the node called `name`, or -1. Names are not unique in glTF:
  /// returns the first in file order.
  int findNode(const std::string& name) const;
};

}  // namespace svit
