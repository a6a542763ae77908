// Invariant checks of BakeData, shared by writeBakeFile (before it writes
// anything, so nothing bad is ever written) and readBakeFile (after it
// parses, so the runtime never receives an out-of-range index or a
// non-finite float). Messages name the section by its tag, as in the file,
// then the element and the value.

#include "bake_file_validate.h"

#include <cmath>
#include <cstdio>
#include <limits>

#include "numeric.h"

namespace svit::bakeio {
namespace {

// The longest page file name we accept: a name, not a path tree.
constexpr size_t kMaxPageFileChars = 1024;
// Shadow-mask owners are the high byte of a u16 texel value: 1..255, 0 for
// no light. A channel cap of 256 (64 RGBA layers) is far above any real
// overlap and bounds the owner tables below to 64 K entries.
constexpr uint32_t kMaxMaskOwner = 255;
constexpr uint32_t kMaxMaskChannels = 256;
constexpr uint32_t kMaskOwners = kMaxMaskOwner + 1;  // 0..255

std::string num(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}
std::string num(uint64_t v) { return std::to_string(v); }
std::string num(int64_t v) { return std::to_string(v); }
std::string num(uint32_t v) { return std::to_string(v); }
std::string num(int32_t v) { return std::to_string(v); }
std::string vecText(const Vec3& v) {
  return "(" + num(v.x) + ", " + num(v.y) + ", " + num(v.z) + ")";
}
std::string vecText(const Rgb& c) {
  return "(" + num(c.r) + ", " + num(c.g) + ", " + num(c.b) + ")";
}
std::string vecText(const Vec2& v) { return "(" + num(v.x) + ", " + num(v.y) + ")"; }

Status invalid(const std::string& path, const std::string& what) {
  return Status(StatusCode::kInvalidInput, path + ": " + what);
}

// out = a * b; false (out untouched) when that overflows 64 bits.
bool mulNoOverflow(uint64_t a, uint64_t b, uint64_t& out) {
  if (a != 0 && b > std::numeric_limits<uint64_t>::max() / a) return false;
  out = a * b;
  return true;
}

// A page file must stay inside the bake directory: relative, no "..", no
// NUL, so a hostile bake cannot make the runtime open /etc/passwd.
bool safeRelativeName(const std::string& name) {
  if (name.empty() || name.size() > kMaxPageFileChars) return false;
  if (name.find('\0') != std::string::npos) return false;
  if (name[0] == '/' || name[0] == '\\') return false;
  if (name.size() >= 2 && name[1] == ':') return false;  // a Windows drive
  size_t start = 0;
  while (start <= name.size()) {
    size_t end = name.find_first_of("/\\", start);
    if (end == std::string::npos) end = name.size();
    if (name.compare(start, end - start, "..") == 0 && end - start == 2) return false;
    start = end + 1;
  }
  return true;
}

Status checkCount(const std::string& path, const char* section, const char* what, size_t count) {
  if (count > std::numeric_limits<uint32_t>::max()) {
    return invalid(path, std::string("section ") + section + ": " + num(uint64_t(count)) + " " +
                             what + " exceed the format's limit of 4294967295");
  }
  return Status();
}

// A lightmap triangle: on a page, its 3 UVs finite.
Status checkLightmapCorners(const BakeData& d, const std::string& path, const std::string& where,
                            uint32_t page, const Vec2 (&uv)[3]) {
  if (page >= d.pages.size()) {
    return invalid(path,
                   where + "page " + num(page) + " >= page count " + num(uint64_t(d.pages.size())));
  }
  for (int k = 0; k < 3; ++k) {
    if (!finite(uv[k]))
      return invalid(path,
                     where + "uv " + std::to_string(k) + " " + vecText(uv[k]) + " is not finite");
  }
  return Status();
}

// Backs by ascending triangle (findBackUv searches them), each on a page or
// unlit (kUnlitBackPage).
Status validateBackUvs(const BakeData& d, const std::string& path) {
  if (Status s = checkCount(path, "BUVS", "backs", d.back_uvs.size()); !s.ok()) return s;
  for (size_t i = 0; i < d.back_uvs.size(); ++i) {
    const BakeBackUv& uv = d.back_uvs[i];
    const std::string where = "section BUVS back " + num(uint64_t(i)) + ": ";
    if (uv.triangle >= d.triangle_uvs.size()) {
      return invalid(path, where + "triangle " + num(uv.triangle) + " >= triangle count " +
                               num(uint64_t(d.triangle_uvs.size())));
    }
    if (i > 0 && uv.triangle <= d.back_uvs[i - 1].triangle) {
      return invalid(path, where + "triangle " + num(uv.triangle) +
                               " does not follow the previous back's " +
                               num(d.back_uvs[i - 1].triangle));
    }
    const uint32_t page = uv.page == kUnlitBackPage ? 0 : uv.page;
    if (Status s = checkLightmapCorners(d, path, where, page, uv.uv); !s.ok()) return s;
  }
  return Status();
}

Status validateStatic(const BakeData& d, const std::string& path) {
  if (Status s = checkCount(path, "PAGE", "pages", d.pages.size()); !s.ok()) return s;
  if (Status s = checkCount(path, "TUVS", "triangles", d.triangle_uvs.size()); !s.ok()) return s;
  for (size_t p = 0; p < d.pages.size(); ++p) {
    const BakeLightmapPage& page = d.pages[p];
    const std::string where = "section PAGE page " + num(uint64_t(p)) + ": ";
    if (page.width == 0 || page.height == 0) {
      return invalid(path,
                     where + "size " + num(page.width) + " x " + num(page.height) + " is empty");
    }
    if (!safeRelativeName(page.file)) {
      return invalid(
          path,
          where + "file \"" + page.file +
              "\" is not a relative name inside the bake directory (empty, absolute, '..', NUL "
              "or longer than " +
              num(uint64_t(kMaxPageFileChars)) + " characters)");
    }
  }
  for (size_t t = 0; t < d.triangle_uvs.size(); ++t) {
    const BakeTriangleUv& uv = d.triangle_uvs[t];
    const std::string where = "section TUVS triangle " + num(uint64_t(t)) + ": ";
    if (Status s = checkLightmapCorners(d, path, where, uv.page, uv.uv); !s.ok()) return s;
  }
  return validateBackUvs(d, path);
}

Status validateRuntimeAbsent(const BakeData& d, const std::string& path) {
  auto refuse = [&](const char* section, const char* what, size_t count) {
    return invalid(path, std::string("section ") + section +
                             ": has_runtime_sections is false but " + what + " holds " +
                             num(uint64_t(count)) + " entries, which would not be written");
  };
  if (!d.patches.empty()) return refuse("PTCH", "patches", d.patches.size());
  if (!d.patch_elements.empty()) return refuse("PELM", "patch_elements", d.patch_elements.size());
  if (!d.clusters.empty()) return refuse("CLST", "clusters", d.clusters.size());
  if (!d.emitters.empty()) return refuse("EMIT", "emitters", d.emitters.size());
  if (!d.proxy.positions.empty())
    return refuse("PRXY", "proxy.positions", d.proxy.positions.size());
  if (!d.proxy.indices.empty()) return refuse("PRXY", "proxy.indices", d.proxy.indices.size());
  if (!d.proxy.face_patch.empty())
    return refuse("PRXY", "proxy.face_patch", d.proxy.face_patch.size());
  if (!d.probes.sh.empty()) return refuse("PROB", "probes.sh", d.probes.sh.size());
  // Masks modulate runtime lights; without the emitters they name nothing.
  if (!d.masks.lights.empty()) return refuse("SMSK", "masks.lights", d.masks.lights.size());
  if (!d.masks.pages.empty()) return refuse("SMSK", "masks.pages", d.masks.pages.size());
  if (d.masks.channels != 0) {
    return invalid(path, "section SMSK: has_runtime_sections is false but masks.channels is " +
                             num(d.masks.channels) + ", which would not be written");
  }
  if (d.probes.dims[0] != 0 || d.probes.dims[1] != 0 || d.probes.dims[2] != 0) {
    return invalid(path, "section PROB: has_runtime_sections is false but probe dims are " +
                             num(d.probes.dims[0]) + " x " + num(d.probes.dims[1]) + " x " +
                             num(d.probes.dims[2]) + ", which would not be written");
  }
  return Status();
}

Status validatePatches(const BakeData& d, const std::string& path) {
  const size_t triangles = d.triangle_uvs.size();
  for (size_t p = 0; p < d.patches.size(); ++p) {
    const BakePatch& patch = d.patches[p];
    const std::string where = "section PTCH patch " + num(uint64_t(p)) + ": ";
    if (!finite(patch.centroid))
      return invalid(path, where + "centroid " + vecText(patch.centroid) + " is not finite");
    if (!finite(patch.normal))
      return invalid(path, where + "normal " + vecText(patch.normal) + " is not finite");
    if (!finite(patch.area_m2))
      return invalid(path, where + "area_m2 " + num(patch.area_m2) + " is not finite");
    if (!finite(patch.albedo))
      return invalid(path, where + "albedo " + vecText(patch.albedo) + " is not finite");
    if (!finite(patch.emission))
      return invalid(path, where + "emission " + vecText(patch.emission) + " is not finite");
    if (!finite(patch.radiosity))
      return invalid(path, where + "radiosity " + vecText(patch.radiosity) + " is not finite");
    const uint64_t end = uint64_t(patch.first_element) + patch.element_count;
    if (end > d.patch_elements.size()) {
      return invalid(path, where + "elements [" + num(patch.first_element) + ", " + num(end) +
                               ") exceed patch_elements size " +
                               num(uint64_t(d.patch_elements.size())));
    }
  }
  for (size_t e = 0; e < d.patch_elements.size(); ++e) {
    // element = triangle * 2 + side, triangles in TUVS order.
    const uint32_t element = d.patch_elements[e];
    if (element / 2 >= triangles) {
      return invalid(path, "section PELM element " + num(uint64_t(e)) + ": " + num(element) +
                               " names triangle " + num(element / 2) + " >= triangle count " +
                               num(uint64_t(triangles)));
    }
  }
  return Status();
}

// Clusters are stored in pre-order (runtime_sections.h): a parent precedes
// its children. Requiring that (parent < i < child) and that child and
// parent links agree rules out cycles, so the runtime can walk trees without
// guarding against them. Ranges first, for every node, so that a bad index
// is reported at the node that holds it.
Status validateClusters(const BakeData& d, const std::string& path) {
  const int64_t n = int64_t(d.clusters.size());
  for (int64_t i = 0; i < n; ++i) {
    const BakeClusterNode& c = d.clusters[size_t(i)];
    const std::string where = "section CLST cluster " + num(i) + ": ";
    if (c.parent != -1 && (c.parent < 0 || c.parent >= i)) {
      return invalid(path, where + "parent " + num(c.parent) +
                               " is not -1 or an earlier cluster (< " + num(i) +
                               "; clusters are stored in pre-order)");
    }
    for (int k = 0; k < 2; ++k) {
      const int32_t child = c.child[k];
      if (child != -1 && (child <= i || child >= n)) {
        return invalid(path, where + "child " + std::to_string(k) + " index " + num(child) +
                                 " is not -1 or a later cluster (in (" + num(i) + ", " + num(n) +
                                 "))");
      }
    }
    if (c.patch != -1 && (c.patch < 0 || uint64_t(c.patch) >= d.patches.size())) {
      return invalid(path, where + "patch " + num(c.patch) + " is not -1 or < patch count " +
                               num(uint64_t(d.patches.size())));
    }
    if (!finite(c.bounds.min) || !finite(c.bounds.max)) {
      return invalid(path, where + "bounds " + vecText(c.bounds.min) + " - " +
                               vecText(c.bounds.max) + " are not finite");
    }
    if (!finite(c.area_m2))
      return invalid(path, where + "area_m2 " + num(c.area_m2) + " is not finite");
  }
  for (int64_t i = 0; i < n; ++i) {
    const BakeClusterNode& c = d.clusters[size_t(i)];
    for (int k = 0; k < 2; ++k) {
      const int32_t child = c.child[k];
      if (child != -1 && d.clusters[size_t(child)].parent != i) {
        return invalid(path, "section CLST cluster " + num(i) + ": child " + std::to_string(k) +
                                 " (cluster " + num(child) + ") has parent " +
                                 num(d.clusters[size_t(child)].parent) + ", not " + num(i));
      }
    }
  }
  return Status();
}

Status validateEmitters(const BakeData& d, const std::string& path) {
  const size_t patches = d.patches.size();
  for (size_t e = 0; e < d.emitters.size(); ++e) {
    const BakeEmitter& emitter = d.emitters[e];
    const std::string where = "section EMIT emitter " + num(uint64_t(e)) + ": ";
    const uint32_t kind = uint32_t(emitter.kind);
    if (kind > uint32_t(BakeEmitter::Kind::kSky))
      return invalid(path, where + "kind " + num(kind) + " is unknown (0..3)");
    if (emitter.kind == BakeEmitter::Kind::kPatch && emitter.index >= patches) {
      return invalid(path, where + "emitting patch " + num(emitter.index) + " >= patch count " +
                               num(uint64_t(patches)));
    }
    if (!finite(emitter.flux))
      return invalid(path, where + "flux " + vecText(emitter.flux) + " is not finite");
    if (emitter.factors.size() != emitter.patches.size()) {
      return invalid(path, where + num(uint64_t(emitter.factors.size())) + " factors for " +
                               num(uint64_t(emitter.patches.size())) +
                               " patches (want one per patch)");
    }
    if (Status s = checkCount(path, "EMIT", "lit patches", emitter.patches.size()); !s.ok())
      return s;
    for (size_t i = 0; i < emitter.patches.size(); ++i) {
      const uint32_t patch = emitter.patches[i];
      if (patch >= patches) {
        return invalid(path, where + "lit patch " + num(uint64_t(i)) + " is " + num(patch) +
                                 " >= patch count " + num(uint64_t(patches)));
      }
      if (i > 0 && patch <= emitter.patches[i - 1]) {
        return invalid(path, where + "lit patch " + num(uint64_t(i)) + " is " + num(patch) +
                                 ", not above the previous " + num(emitter.patches[i - 1]) +
                                 " (patches must be ascending)");
      }
      if (!finite(emitter.factors[i])) {
        return invalid(path, where + "factor " + num(uint64_t(i)) + " " + num(emitter.factors[i]) +
                                 " is not finite");
      }
    }
  }
  return Status();
}

Status validateProxy(const BakeData& d, const std::string& path) {
  const BakeProxyMesh& proxy = d.proxy;
  for (size_t v = 0; v < proxy.positions.size(); ++v) {
    if (!finite(proxy.positions[v])) {
      return invalid(path, "section PRXY vertex " + num(uint64_t(v)) + ": position " +
                               vecText(proxy.positions[v]) + " is not finite");
    }
  }
  if (proxy.indices.size() % 3 != 0) {
    return invalid(path, "section PRXY: " + num(uint64_t(proxy.indices.size())) +
                             " indices, not a multiple of 3");
  }
  for (size_t i = 0; i < proxy.indices.size(); ++i) {
    if (proxy.indices[i] >= proxy.positions.size()) {
      return invalid(path, "section PRXY face " + num(uint64_t(i / 3)) + ": index " +
                               num(proxy.indices[i]) + " >= vertex count " +
                               num(uint64_t(proxy.positions.size())));
    }
  }
  if (proxy.face_patch.size() != proxy.indices.size() / 3) {
    return invalid(path, "section PRXY: " + num(uint64_t(proxy.face_patch.size())) +
                             " face patches for " + num(uint64_t(proxy.indices.size() / 3)) +
                             " faces (want one per face)");
  }
  for (size_t f = 0; f < proxy.face_patch.size(); ++f) {
    if (proxy.face_patch[f] >= d.patches.size()) {
      return invalid(path, "section PRXY face " + num(uint64_t(f)) + ": patch " +
                               num(proxy.face_patch[f]) + " >= patch count " +
                               num(uint64_t(d.patches.size())));
    }
  }
  return Status();
}

Status validateProbes(const BakeData& d, const std::string& path) {
  const BakeProbeGrid& grid = d.probes;
  if (!finite(grid.origin))
    return invalid(path, "section PROB: origin " + vecText(grid.origin) + " is not finite");
  if (!finite(grid.spacing))
    return invalid(path, "section PROB: spacing " + vecText(grid.spacing) + " is not finite");
  uint64_t floats = 12;
  const bool fits = mulNoOverflow(floats, grid.dims[0], floats) &&
                    mulNoOverflow(floats, grid.dims[1], floats) &&
                    mulNoOverflow(floats, grid.dims[2], floats);
  const std::string dims =
      num(grid.dims[0]) + " x " + num(grid.dims[1]) + " x " + num(grid.dims[2]);
  if (!fits || floats != grid.sh.size()) {
    return invalid(path, "section PROB: " + num(uint64_t(grid.sh.size())) + " SH floats for dims " +
                             dims + " (want 12 per probe" +
                             (fits ? " = " + num(floats) : std::string(", which overflows")) + ")");
  }
  for (size_t i = 0; i < grid.sh.size(); ++i) {
    if (!finite(grid.sh[i])) {
      return invalid(path, "section PROB probe " + num(uint64_t(i / 12)) + ": SH float " +
                               num(uint64_t(i % 12)) + " " + num(grid.sh[i]) + " is not finite");
    }
  }
  return Status();
}

// No lights: nothing else either, since only lights get SMSK written.
Status validateNoShadowMasks(const BakeShadowMasks& masks, const std::string& path) {
  if (masks.channels != 0) {
    return invalid(
        path, "section SMSK: no masked lights but " + num(masks.channels) + " channels (want 0)");
  }
  if (!masks.pages.empty()) {
    return invalid(path, "section SMSK: no masked lights but " + num(uint64_t(masks.pages.size())) +
                             " mask pages (want none)");
  }
  return Status();
}

const char* emitterKindName(BakeEmitter::Kind kind) {
  switch (kind) {
    case BakeEmitter::Kind::kLight: return "light";
    case BakeEmitter::Kind::kPatch: return "patch";
    case BakeEmitter::Kind::kSun: return "sun";
    case BakeEmitter::Kind::kSky: return "sky";
  }
  return "unknown";
}

// Each light: a light, sun or (a lamp's) patch emitter, masked once, in a
// channel under a (channel, owner) pair no other light holds. Fills `owner_allowed`
// (channel * kMaskOwners + owner: 1 where a texel may hold that owner in
// that channel; owner 0 always) for the texel check. `masks.channels` is
// already <= kMaxMaskChannels.
Status validateMaskedLights(const BakeData& d, const std::string& path,
                            std::vector<uint8_t>& owner_allowed) {
  const BakeShadowMasks& masks = d.masks;
  // Which light holds an emitter / a (channel, owner) pair; -1 for none yet.
  std::vector<int64_t> light_of_emitter(d.emitters.size(), -1);
  std::vector<int64_t> light_of_owner(size_t(masks.channels) * kMaskOwners, -1);
  owner_allowed.assign(size_t(masks.layers()) * 4 * kMaskOwners, 0);
  for (uint32_t c = 0; c < masks.layers() * 4; ++c) owner_allowed[size_t(c) * kMaskOwners] = 1;
  for (size_t i = 0; i < masks.lights.size(); ++i) {
    const BakeMaskedLight& light = masks.lights[i];
    const std::string where = "section SMSK light " + num(uint64_t(i)) + ": ";
    if (light.emitter >= d.emitters.size()) {
      return invalid(path, where + "emitter " + num(light.emitter) + " is out of range (" +
                               num(uint64_t(d.emitters.size())) + " emitters)");
    }
    const BakeEmitter::Kind kind = d.emitters[light.emitter].kind;
    if (kind == BakeEmitter::Kind::kSky) {
      return invalid(path, where + "emitter " + num(light.emitter) + " is a " +
                               emitterKindName(kind) + " (kind " + num(uint32_t(kind)) +
                               "), not a light, the sun or a lamp's patch");
    }
    int64_t& emitter_holder = light_of_emitter[light.emitter];
    if (emitter_holder >= 0) {
      return invalid(path, where + "emitter " + num(light.emitter) +
                               " is already masked by light " + num(emitter_holder));
    }
    emitter_holder = int64_t(i);
    if (light.channel >= masks.channels) {
      return invalid(path, where + "channel " + num(light.channel) + " >= channel count " +
                               num(masks.channels));
    }
    if (light.owner == 0 || light.owner > kMaxMaskOwner) {
      return invalid(path, where + "owner " + num(light.owner) + " is not in 1.." +
                               num(kMaxMaskOwner) + " (0 marks no light)");
    }
    const size_t slot = size_t(light.channel) * kMaskOwners + light.owner;
    if (light_of_owner[slot] >= 0) {
      return invalid(path, where + "channel " + num(light.channel) + " owner " + num(light.owner) +
                               " is already light " + num(light_of_owner[slot]) + "'s");
    }
    light_of_owner[slot] = int64_t(i);
    owner_allowed[slot] = 1;
  }
  return Status();
}

// The texel value at `index` of a mask page, whose owner its channel does
// not allow, named by layer, column, row and channel.
Status maskTexelError(const std::vector<uint16_t>& values, size_t index,
                      const BakeLightmapPage& page, const std::string& where,
                      const std::string& path) {
  const uint64_t texel = index / 4, layer_texels = uint64_t(page.width) * page.height;
  const uint64_t layer = texel / layer_texels, in_layer = texel % layer_texels;
  const uint64_t channel = layer * 4 + index % 4;
  const uint32_t value = values[index];
  return invalid(path, where + "layer " + num(layer) + " texel (" + num(in_layer % page.width) +
                           ", " + num(in_layer / page.width) + ") channel " + num(channel) +
                           ": value " + num(value) + " has owner " + num(value >> 8) +
                           ", not 0 or a light of channel " + num(channel));
}

// Every value's owner (its high byte) is allowed in its channel.
// `values` holds `layers` x height x width x 4 values (checked by the caller).
Status validateMaskTexels(const std::vector<uint16_t>& values, uint32_t layers,
                          const BakeLightmapPage& page, const std::vector<uint8_t>& owner_allowed,
                          const std::string& where, const std::string& path) {
  // Hot loop (4 values per texel and layer: millions on a large level): one
  // table lookup per value, no division; the position is worked out only
  // for a value that fails.
  const size_t layer_values = size_t(page.width) * page.height * 4;
  for (size_t layer = 0; layer < layers; ++layer) {
    const uint8_t* allowed = owner_allowed.data() + layer * 4 * kMaskOwners;
    const size_t first = layer * layer_values;
    for (size_t i = first; i < first + layer_values; i += 4) {
      for (size_t c = 0; c < 4; ++c) {
        if (!allowed[c * kMaskOwners + (values[i + c] >> 8)])
          return maskTexelError(values, i + c, page, where, path);
      }
    }
  }
  return Status();
}

// Per lightmap page, layers x height x width x 4 values whose owners are
// lights of their channel.
Status validateMaskPages(const BakeData& d, const std::string& path,
                         const std::vector<uint8_t>& owner_allowed) {
  const BakeShadowMasks& masks = d.masks;
  if (masks.pages.size() != d.pages.size()) {
    return invalid(path, "section SMSK: " + num(uint64_t(masks.pages.size())) + " mask pages for " +
                             num(uint64_t(d.pages.size())) + " lightmap pages (want one per page)");
  }
  for (size_t p = 0; p < masks.pages.size(); ++p) {
    const BakeLightmapPage& page = d.pages[p];
    const std::vector<uint16_t>& values = masks.pages[p];
    const std::string where = "section SMSK page " + num(uint64_t(p)) + ": ";
    uint64_t want = 4;
    const bool fits = mulNoOverflow(want, masks.layers(), want) &&
                      mulNoOverflow(want, page.width, want) &&
                      mulNoOverflow(want, page.height, want);
    if (!fits || want != values.size()) {
      return invalid(path, where + num(uint64_t(values.size())) + " values for " +
                               num(masks.layers()) + " layers of " + num(page.width) + " x " +
                               num(page.height) + " texels (want 4 per texel and layer" +
                               (fits ? " = " + num(want) : std::string(", which overflows")) + ")");
    }
    if (Status s = validateMaskTexels(values, masks.layers(), page, owner_allowed, where, path);
        !s.ok())
      return s;
  }
  return Status();
}

Status validateShadowMasks(const BakeData& d, const std::string& path) {
  const BakeShadowMasks& masks = d.masks;
  if (Status s = checkCount(path, "SMSK", "masked lights", masks.lights.size()); !s.ok()) return s;
  if (masks.lights.empty()) return validateNoShadowMasks(masks, path);
  if (masks.channels > kMaxMaskChannels) {
    return invalid(path, "section SMSK: " + num(masks.channels) + " channels exceed the limit of " +
                             num(kMaxMaskChannels));
  }
  std::vector<uint8_t> owner_allowed;
  if (Status s = validateMaskedLights(d, path, owner_allowed); !s.ok()) return s;
  return validateMaskPages(d, path, owner_allowed);
}

}  // namespace

Status validateBakeData(const BakeData& d, const std::string& path) {
  if (Status s = validateStatic(d, path); !s.ok()) return s;
  if (!d.has_runtime_sections) return validateRuntimeAbsent(d, path);
  if (Status s = checkCount(path, "PTCH", "patches", d.patches.size()); !s.ok()) return s;
  if (Status s = checkCount(path, "PELM", "patch elements", d.patch_elements.size()); !s.ok())
    return s;
  if (Status s = checkCount(path, "CLST", "clusters", d.clusters.size()); !s.ok()) return s;
  if (Status s = checkCount(path, "EMIT", "emitters", d.emitters.size()); !s.ok()) return s;
  if (Status s = checkCount(path, "PRXY", "vertices", d.proxy.positions.size()); !s.ok()) return s;
  if (Status s = checkCount(path, "PRXY", "indices", d.proxy.indices.size()); !s.ok()) return s;
  if (Status s = checkCount(path, "PROB", "SH floats", d.probes.sh.size()); !s.ok()) return s;
  if (Status s = validatePatches(d, path); !s.ok()) return s;
  if (Status s = validateClusters(d, path); !s.ok()) return s;
  if (Status s = validateEmitters(d, path); !s.ok()) return s;
  if (Status s = validateProxy(d, path); !s.ok()) return s;
  if (Status s = validateProbes(d, path); !s.ok()) return s;
  return validateShadowMasks(d, path);
}

}  // namespace svit::bakeio
