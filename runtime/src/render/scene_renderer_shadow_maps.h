#pragma once
// Lights the SceneRenderer shades per pixel, and their depth shadow maps:
// a cube (six faces of a cube-map array) for point lights and wide spots,
// one perspective face for spots up to 45 degrees, one orthographic face
// for the sun and other directional lights. Maps are re-rendered only for a
// light that changed or that sees where a caster (dynamic object) moved
// from or to; storage grows only when a frame has more lights than any
// before.

#include <cstdint>
#include <functional>
#include <vector>

#include <glm/glm.hpp>

#include "gl/gl_handle.h"
#include "gl/gl_memory.h"
#include "gl/gl_program.h"
#include "svit/math_types.h"
#include "svit/scene.h"
#include "svit/status.h"

namespace svit::gl {

/// A light as lit_static.frag / lit_dynamic.frag read it (std430, binding
/// render_binding::kLights; struct GpuLight in svit_shading.frag).
struct GpuLight {
  /// xyz world metres; w: 0 point, 1 spot, 2 directional, 3 a masked area
  /// light's point sample
  float position[4];
  /// xyz unit, the way light travels (an area sample: its element's
  /// normal); w: cos(outer cone) (an area sample: the light's first vec4
  /// in the area buffer, render_binding::kAreaLights)
  float direction[4];
  /// rgb: candela (point, spot) or lux (directional), colour x dimmer
  /// applied (an area sample: the dimmer in r); w: cos(inner cone) (an
  /// area sample: its light's sample count)
  float intensity[4];
  /// x: 0 none, 1 cube, 2 face; y: layer (cube index or face layer); z, w: near, far (m)
  float shadow[4];
  /// x: texel size per metre of distance (perspective); y: texel size in metres (ortho)
  float shadow_texel[4];
  float shadow_from_world[16];  ///< face maps: clip space of the map
};
static_assert(sizeof(GpuLight) == 144, "svit_shading.frag reads this layout");

/// A light to shade with this frame: type, position, direction, cones from
/// `light`; `rgb_intensity` = colour x intensity x dimmer.
struct FrameLight {
  Light light;
  Rgb rgb_intensity;
  bool casts_shadows = true;
  /// A masked baked light: its map holds the dynamic objects only, fitted
  /// to their bounds (the static level's shadow is in its mask).
  bool dynamic_casters_only = false;
  /// Its mask channel and owner (BakeMaskedLight), for lit_static.frag.
  uint32_t mask_channel = 0, mask_owner = 0;
  /// A masked area light's point sample (light: a point light there):
  /// the samples of one light follow each other, each with the light's
  /// sample count and its first vec4 in the area buffer.
  bool area_sample = false;
  Vec3 area_normal{0, 0, 0};
  uint32_t area_samples = 0, area_offset = 0;
};

class LightShadowMaps {
 public:
  /// Compiles shadow_depth.*; allocates nothing until lights arrive.
  /// `map_size`: texels per face edge, 16..8192. Errors: a shader fails, a
  /// size out of range.
  static Expected<LightShadowMaps> create(int map_size);
  LightShadowMaps() = default;
  LightShadowMaps(LightShadowMaps&& other) noexcept;
  LightShadowMaps& operator=(LightShadowMaps&& other) noexcept;
  LightShadowMaps(const LightShadowMaps&) = delete;
  LightShadowMaps& operator=(const LightShadowMaps&) = delete;
  ~LightShadowMaps();

  /// Draws the shadow casters with the current program: everything, or
  /// the dynamic objects only; the callee sets nothing but its vertex
  /// arrays and draws (positions at attribute 0).
  using DrawCasters = std::function<void(bool dynamic_only)>;

  /// Brings the lights buffer and the maps up to date for `lights` within
  /// `scene_bounds` (world box holding every caster and receiver; sizes
  /// directional maps and near/far planes); the maps of
  /// dynamic_casters_only lights are fitted to `dynamic_bounds` instead (a
  /// sun's orthographic map to their box, a lamp's perspective map to the
  /// cone that sees them), none when it is empty. `casters_changed`: the casters
  /// moved since the last call; `moved_boxes` (may be null: every map is
  /// then re-rendered) are the boxes they moved from and to. A light's map
  /// is re-rendered only when one of those boxes is seen from the light:
  /// the boxes are drawn against its current map under an occlusion query,
  /// and a box wholly behind what the map holds cannot change it. Returns
  /// the number of maps rendered (a cube counts once). Leaves the draw
  /// framebuffer and viewport changed; the caller restores its own.
  uint32_t update(const std::vector<FrameLight>& lights, const Aabb& scene_bounds,
                  const Aabb& dynamic_bounds, bool casters_changed,
                  const std::vector<Aabb>* moved_boxes, const DrawCasters& draw_casters);

  /// Binds the lights buffer and the two shadow textures (units of
  /// scene_renderer_bindings.h); valid after update().
  void bind() const;
  size_t lightCount() const { return gpu_lights_.size(); }

  std::vector<GlObject> glObjects() const {
    return {glTextureObject(cube_array_.id()), glTextureObject(face_array_.id()),
            glBufferObject(lights_buffer_.id())};
  }

 private:
  struct MapCounts {
    uint32_t cubes = 0, faces = 0;
  };
  /// update()'s stages: gpu_lights_ and each face light's clip transform
  /// (into face_views) from `lights`, with the maps they need; the lights
  /// buffer filled; the maps that may have changed rendered (returns how many).
  MapCounts layOutLights(const std::vector<FrameLight>& lights, const Aabb& scene_bounds,
                         const Aabb& dynamic_bounds, std::vector<glm::mat4>& face_views);
  /// A light's map: its kind, layer, planes, texel sizes and clip
  /// transform, fitted to `bounds`; `fit_cone`: a point light outside them
  /// gets one perspective face around them instead of a cube.
  void layOutMap(const Light& l, const Aabb& bounds, bool fit_cone, GpuLight& g, glm::mat4& view,
                 MapCounts& counts) const;
  void uploadLights();
  uint32_t renderMaps(const std::vector<Aabb>& light_bounds,
                      const std::vector<glm::mat4>& face_views, bool casters_changed,
                      const std::vector<Aabb>* moved_boxes, const DrawCasters& draw_casters);
  void release();
  void ensureCapacity(uint32_t cubes, uint32_t faces);
  /// Depth-only drawing into the maps: writing (with the casters' polygon
  /// offset) or testing against what they hold.
  void setDepthState(bool write) const;
  /// Attaches each face of light `light`'s map in turn (one for a face
  /// light, six for a cube), sets its clip transform and calls `draw`.
  void forEachFace(size_t light, const glm::mat4& face_view,
                   const std::function<void()>& draw) const;
  /// Uploads the triangles of `boxes` for boxesSeen(); returns their vertex count.
  uint32_t uploadBoxes(const std::vector<Aabb>& boxes);
  /// Whether any of the uploaded boxes passes the depth test against light
  /// `light`'s current map (any face).
  bool boxesSeen(size_t light, uint32_t box_vertices, const glm::mat4& face_view) const;
  GlProgram program_;
  int map_size_ = 512;
  GlFramebuffer framebuffer_;
  GlTexture cube_array_, face_array_;
  GlBuffer lights_buffer_;
  uint32_t cube_capacity_ = 0, face_capacity_ = 0, light_capacity_ = 0;
  GlVertexArray box_vao_;
  GlBuffer box_buffer_;
  GlQuery box_query_;
  size_t box_capacity_ = 0;  ///< vertices box_buffer_ holds
  std::vector<GpuLight> gpu_lights_;
  std::vector<uint8_t> dynamic_only_;  ///< per light: its map holds dynamic casters only
  /// per light slot: what its map was rendered for
  std::vector<std::vector<float>> rendered_keys_;
};

}  // namespace svit::gl
