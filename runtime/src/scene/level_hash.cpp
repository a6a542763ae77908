// hashLevel: FNV-1a 64 over a canonical little-endian serialization of what
// a bake depends on, so a bake can tell whether it still matches its level
// (svit-bake --reference, svit-probe, the runtime's load check).
//
// In: geometry (positions, indices, both UV sets: uv0 places the textures
// the per-triangle albedo is taken from, uv1 is the authored lightmap
// layout), per-triangle materials, materials (factors, alpha, sidedness and
// every texture reference with its transform), textures (size, channels,
// wrap modes, texels), instances (mesh, transform, dynamic mark), lights
// (every field but the name), sun and sky.
// Out: names, warnings, paths, nodes as such (instances carry their world
// transforms), shading normals (the baker uses geometric normals), import
// counters, animations, object and camera paths: none changes a bake.
//
// Every array is preceded by its length so that moving a value from one
// array to the next changes the hash; floats go in as their IEEE bits.
// Changing what goes in changes every level's hash: bump kDomain with it so
// old bakes are reported stale rather than silently matched.

#include <algorithm>
#include <bit>
#include <cstdint>
#include <string_view>

#include "bake_file_io.h"
#include "svit/bake_file.h"

namespace svit {
namespace {

constexpr std::string_view kDomain = "svit level hash 1";

// Feeds little-endian fields to FNV-1a 64 through a small buffer (one call
// per field would dominate the time on large levels).
class Hasher : public bakeio::LittleEndianEncoder<Hasher> {
 public:
  void put(const uint8_t* p, size_t size) {
    if (size >= sizeof buffer_) {  // texels: hash in place, no copy
      flush();
      state_ = fnv1a64(p, size, state_);
      return;
    }
    while (size > 0) {
      const size_t n = std::min(size, sizeof buffer_ - used_);
      for (size_t i = 0; i < n; ++i) buffer_[used_ + i] = p[i];
      used_ += n;
      p += n;
      size -= n;
      if (used_ == sizeof buffer_) flush();
    }
  }
  void count(size_t n) { u64(uint64_t(n)); }
  void mat4(const Mat4& m) {
    for (float v : m.m) f32(v);
  }
  uint64_t finish() {
    flush();
    return state_;
  }

 private:
  void flush() {
    state_ = fnv1a64(buffer_, used_, state_);
    used_ = 0;
  }
  uint64_t state_ = 0xcbf29ce484222325ull;  // FNV-1a 64 offset basis
  uint8_t buffer_[4096];
  size_t used_ = 0;
};

void hashTextureRef(Hasher& h, const TextureRef& ref) {
  h.i32(ref.texture);
  h.i32(ref.texcoord);
  h.vec2(ref.offset);
  h.f32(ref.rotation_rad);
  h.vec2(ref.scale);
}

}  // namespace

uint64_t hashLevel(const Scene& scene) {
  Hasher h;
  h.raw(kDomain.data(), kDomain.size());

  h.count(scene.meshes.size());
  for (const Mesh& mesh : scene.meshes) {
    h.count(mesh.positions.size());
    for (const Vec3& p : mesh.positions) h.vec3(p);
    h.count(mesh.indices.size());
    for (uint32_t i : mesh.indices) h.u32(i);
    h.count(mesh.uv0.size());
    for (const Vec2& uv : mesh.uv0) h.vec2(uv);
    h.count(mesh.uv1.size());
    for (const Vec2& uv : mesh.uv1) h.vec2(uv);
    h.count(mesh.triangle_material.size());
    for (uint32_t m : mesh.triangle_material) h.u32(m);
  }

  h.count(scene.materials.size());
  for (const Material& m : scene.materials) {
    h.rgb(m.base_color);
    h.f32(m.base_alpha);
    hashTextureRef(h, m.base_color_texture);
    h.rgb(m.emissive_luminance);
    hashTextureRef(h, m.emissive_texture);
    h.u8(m.double_sided ? 1 : 0);
    h.u32(uint32_t(m.alpha_mode));
    h.f32(m.alpha_cutoff);
  }

  h.count(scene.textures.size());
  for (const Texture& t : scene.textures) {
    h.i32(t.width);
    h.i32(t.height);
    h.i32(t.channels);
    h.u32(uint32_t(t.wrap_s));
    h.u32(uint32_t(t.wrap_t));
    h.count(t.texels.size());
    h.raw(t.texels.data(), t.texels.size());  // bytes: no byte order to fix
  }

  h.count(scene.instances.size());
  for (const Instance& instance : scene.instances) {
    h.i32(instance.mesh);
    h.mat4(instance.world_from_object);
    h.u8(instance.dynamic ? 1 : 0);
  }

  h.count(scene.lights.size());
  for (const Light& light : scene.lights) {
    h.u32(uint32_t(light.type));
    h.rgb(light.color);
    h.f32(light.intensity);
    h.f32(light.range_m);
    h.f32(light.inner_cone_rad);
    h.f32(light.outer_cone_rad);
    h.vec3(light.position);
    h.vec3(light.direction);
    h.i32(light.node);
    h.u8(light.dynamic ? 1 : 0);
  }

  h.u8(scene.sun.enabled ? 1 : 0);
  h.vec3(scene.sun.direction_to_sun);
  h.f32(scene.sun.illuminance_lux);
  h.f32(scene.sun.angular_radius_rad);
  h.rgb(scene.sun.color);

  h.u32(uint32_t(scene.sky.model));
  h.rgb(scene.sky.zenith_luminance);
  h.rgb(scene.sky.horizon_luminance);
  h.rgb(scene.sky.ground_luminance);
  return h.finish();
}

}  // namespace svit
