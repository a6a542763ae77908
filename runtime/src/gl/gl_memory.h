#pragma once
// Storage sizes of GL objects, asked of GL itself (level sizes and component
// bits), so the resource audit reports what the driver was asked to hold
// rather than what the code meant to allocate.

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "svit/resource_use.h"

namespace svit::gl {

struct GlObject {
  enum class Kind { kBuffer, kTexture, kRenderbuffer };
  Kind kind = Kind::kBuffer;
  uint32_t name = 0;  ///< 0: not allocated, counts nothing
};

inline GlObject glBufferObject(uint32_t name) { return {GlObject::Kind::kBuffer, name}; }
inline GlObject glTextureObject(uint32_t name) { return {GlObject::Kind::kTexture, name}; }
inline GlObject glRenderbufferObject(uint32_t name) {
  return {GlObject::Kind::kRenderbuffer, name};
}

/// Bytes of storage behind `object`: a buffer's size; a texture's texels
/// over all its levels, layers and cube faces times the bits of its
/// internal format; a renderbuffer's pixels times bits times samples.
/// Needs the context current. 0 for name 0.
uint64_t glObjectBytes(const GlObject& object);

struct GlFootprint {
  uint32_t objects = 0;
  uint64_t bytes = 0;
};

/// Sum over `objects`, skipping names of 0.
GlFootprint glFootprint(std::span<const GlObject> objects);

/// A resource-audit line named `name` for `objects`, measured: allocated
/// when any of them exists; the reason is the caller's to fill.
ResourceUse measuredUse(std::string name, const std::vector<GlObject>& objects);

}  // namespace svit::gl
