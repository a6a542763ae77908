// bake.svit reader and writer. Layout (all integers little-endian, floats as
// IEEE-754 binary32 bits):
//   "SVITBAKE"  u32 version  u32 section_count
//   section_count x { u32 tag (four ASCII chars in file order), u64 payload bytes, payload }
//   u64 FNV-1a 64 of every preceding byte
// HEAD, PAGE and TUVS are always present; PTCH, PELM, CLST, EMIT, PRXY and
// PROB all together or not at all (BakeData::has_runtime_sections); BUVS
// when some double-sided triangle has a back lightmap; SMSK, after the
// runtime sections, when the bake masks some light (only with runtime
// sections). Readers skip unknown tags, so a version can gain sections
// without a bump; a known section's payload layout is fixed per version.
// The payloads are described beside their encoders below.
//
// Trust: a bake file is input. The reader walks the section table before it
// believes any size, checks the checksum before it parses a payload, checks
// every count against the bytes left before it allocates, and then applies
// the same invariant check the writer applies before it writes
// (bake_file_validate.cpp), so whatever the runtime receives has indices in
// range and finite floats.

#include "svit/bake_file.h"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <system_error>

#include "bake_file_decode.h"
#include "bake_file_io.h"
#include "bake_file_validate.h"
#include "file_output.h"

namespace svit {
namespace {

namespace fs = std::filesystem;
using bakeio::ByteReader;
using bakeio::ByteWriter;
using bakeio::validateBakeData;

constexpr char kMagic[8] = {'S', 'V', 'I', 'T', 'B', 'A', 'K', 'E'};
constexpr size_t kHeaderBytes = 16;  // magic, version, section count
constexpr size_t kChecksumBytes = 8;
constexpr size_t kSectionHeaderBytes = 12;  // tag, payload size

constexpr uint32_t makeTag(const char (&s)[5]) {
  return uint32_t(uint8_t(s[0])) | uint32_t(uint8_t(s[1])) << 8 | uint32_t(uint8_t(s[2])) << 16 |
         uint32_t(uint8_t(s[3])) << 24;
}
constexpr uint32_t kHead = makeTag("HEAD");
constexpr uint32_t kPage = makeTag("PAGE");
constexpr uint32_t kTuvs = makeTag("TUVS");
constexpr uint32_t kPtch = makeTag("PTCH");
constexpr uint32_t kPelm = makeTag("PELM");
constexpr uint32_t kClst = makeTag("CLST");
constexpr uint32_t kEmit = makeTag("EMIT");
constexpr uint32_t kPrxy = makeTag("PRXY");
constexpr uint32_t kProb = makeTag("PROB");
constexpr uint32_t kBuvs = makeTag("BUVS");
constexpr uint32_t kSmsk = makeTag("SMSK");

// Fixed sizes of the per-element records (bytes), used to bound counts.
constexpr uint64_t kPageMinBytes = 4 + 4 + 8 + 4;  // width, height, hash, name length
constexpr uint64_t kTriangleUvBytes = 4 * 3 + 6 * 4;
constexpr uint64_t kBackUvBytes = 4 * 2 + 6 * 4;
constexpr uint64_t kPatchBytes = 16 * 4 + 2 * 4;       // 16 floats, first, count
constexpr uint64_t kClusterBytes = 4 * 4 + 7 * 4;      // 4 ints, bounds, area
constexpr uint64_t kEmitterMinBytes = 4 + 4 + 12 + 4;  // kind, index, flux, count
constexpr uint64_t kMaskedLightBytes = 3 * 4;          // emitter, channel, owner
constexpr uint64_t kMaskPageMinBytes = 8;              // value count

// Printable form of a tag: its four characters, or hex when they are not ASCII.
std::string tagName(uint32_t tag) {
  std::string name;
  for (int i = 0; i < 4; ++i) {
    const char c = char((tag >> (8 * i)) & 0xff);
    if (c < 0x20 || c > 0x7e) {
      char hex[16];
      std::snprintf(hex, sizeof hex, "0x%08x", unsigned(tag));
      return hex;
    }
    name += c;
  }
  return name;
}

std::string num(uint64_t v) { return std::to_string(v); }
std::string num(uint32_t v) { return std::to_string(v); }
std::string num(int32_t v) { return std::to_string(v); }

Status invalid(const std::string& path, const std::string& what) {
  return Status(StatusCode::kInvalidInput, path + ": " + what);
}

std::string truncatedText(const std::string& what, uint64_t need, uint64_t left) {
  return "truncated: " + what + " needs " + num(need) + " bytes, " + num(left) + " left";
}

// ---------------------------------------------------------------------------
// Encoding. Counts are u32 (validateBakeData() bounds them).

void encodeHead(ByteWriter& w, const BakeData& d) {
  w.u64(d.level_hash);
  w.u64(d.seed);
}

// u32 count, then per page: u32 width, u32 height, u64 texel_hash, u32 name
// length, name bytes (UTF-8, no terminator).
void encodePages(ByteWriter& w, const BakeData& d) {
  w.u32(uint32_t(d.pages.size()));
  for (const BakeLightmapPage& page : d.pages) {
    w.u32(page.width);
    w.u32(page.height);
    w.u64(page.texel_hash);
    w.u32(uint32_t(page.file.size()));
    w.raw(page.file.data(), page.file.size());
  }
}

// u32 count, then per triangle: u32 instance, u32 mesh_triangle, u32 page, 3 x (f32 u, f32 v).
void encodeTriangleUvs(ByteWriter& w, const BakeData& d) {
  w.u32(uint32_t(d.triangle_uvs.size()));
  for (const BakeTriangleUv& uv : d.triangle_uvs) {
    w.u32(uv.instance);
    w.u32(uv.mesh_triangle);
    w.u32(uv.page);
    for (const Vec2& c : uv.uv) w.vec2(c);
  }
}

// u32 count, then per back: u32 triangle, u32 page, 3 x (f32 u, f32 v).
void encodeBackUvs(ByteWriter& w, const BakeData& d) {
  w.u32(uint32_t(d.back_uvs.size()));
  for (const BakeBackUv& uv : d.back_uvs) {
    w.u32(uv.triangle);
    w.u32(uv.page);
    for (const Vec2& c : uv.uv) w.vec2(c);
  }
}

// u32 count, then per patch: centroid, normal (3 f32 each), f32 area_m2,
// albedo, emission, radiosity (3 f32 each), u32 first_element, u32 element_count.
void encodePatches(ByteWriter& w, const BakeData& d) {
  w.u32(uint32_t(d.patches.size()));
  for (const BakePatch& p : d.patches) {
    w.vec3(p.centroid);
    w.vec3(p.normal);
    w.f32(p.area_m2);
    w.rgb(p.albedo);
    w.rgb(p.emission);
    w.rgb(p.radiosity);
    w.u32(p.first_element);
    w.u32(p.element_count);
  }
}

// u32 count, then u32 per element.
void encodeU32s(ByteWriter& w, const std::vector<uint32_t>& values) {
  w.u32(uint32_t(values.size()));
  for (uint32_t v : values) w.u32(v);
}

// u32 count, then per node: i32 parent, i32 child[2], i32 patch, bounds min
// and max (3 f32 each), f32 area_m2.
void encodeClusters(ByteWriter& w, const BakeData& d) {
  w.u32(uint32_t(d.clusters.size()));
  for (const BakeClusterNode& c : d.clusters) {
    w.i32(c.parent);
    w.i32(c.child[0]);
    w.i32(c.child[1]);
    w.i32(c.patch);
    w.vec3(c.bounds.min);
    w.vec3(c.bounds.max);
    w.f32(c.area_m2);
  }
}

// u32 count, then per emitter: u32 kind, u32 index, flux (3 f32), u32 n,
// n x u32 patch, n x f32 factor.
void encodeEmitters(ByteWriter& w, const BakeData& d) {
  w.u32(uint32_t(d.emitters.size()));
  for (const BakeEmitter& e : d.emitters) {
    w.u32(uint32_t(e.kind));
    w.u32(e.index);
    w.rgb(e.flux);
    w.u32(uint32_t(e.patches.size()));
    for (uint32_t p : e.patches) w.u32(p);
    for (float f : e.factors) w.f32(f);
  }
}

// u32 vertex count, positions (3 f32 each); u32 index count, u32 indices;
// u32 face count, u32 face_patch.
void encodeProxy(ByteWriter& w, const BakeData& d) {
  w.u32(uint32_t(d.proxy.positions.size()));
  for (const Vec3& p : d.proxy.positions) w.vec3(p);
  encodeU32s(w, d.proxy.indices);
  encodeU32s(w, d.proxy.face_patch);
}

// origin, spacing (3 f32 each), dims (3 u32), u32 SH float count, f32 SH.
void encodeProbes(ByteWriter& w, const BakeData& d) {
  w.vec3(d.probes.origin);
  w.vec3(d.probes.spacing);
  for (uint32_t dim : d.probes.dims) w.u32(dim);
  w.u32(uint32_t(d.probes.sh.size()));
  for (float v : d.probes.sh) w.f32(v);
}

// u32 light count, then per light: u32 emitter, u32 channel, u32 owner;
// u32 channels; u32 page count, then per page: u64 value count, that many
// u16 values (BakeShadowMasks::pages order).
void encodeShadowMasks(ByteWriter& w, const BakeData& d) {
  w.u32(uint32_t(d.masks.lights.size()));
  for (const BakeMaskedLight& light : d.masks.lights) {
    w.u32(light.emitter);
    w.u32(light.channel);
    w.u32(light.owner);
  }
  w.u32(d.masks.channels);
  w.u32(uint32_t(d.masks.pages.size()));
  for (const std::vector<uint16_t>& page : d.masks.pages) {
    w.u64(page.size());
    w.u16s(page.data(), page.size());
  }
}

template <typename Encode>
void section(ByteWriter& w, uint32_t tag, Encode encode) {
  w.u32(tag);
  const size_t size_at = w.size();
  w.u64(0);  // patched below, once the payload's size is known
  const size_t start = w.size();
  encode();
  w.patchU64(size_at, uint64_t(w.size() - start));
}

// The sections encode() writes: 3 required, 6 runtime, BUVS, SMSK.
uint32_t sectionCount(const BakeData& d) {
  return (d.has_runtime_sections ? 9 : 3) + (d.back_uvs.empty() ? 0 : 1) +
         (d.masks.lights.empty() ? 0 : 1);
}

std::vector<uint8_t> encode(const BakeData& d) {
  ByteWriter w;
  w.raw(kMagic, sizeof kMagic);
  w.u32(kBakeFileVersion);
  w.u32(sectionCount(d));
  section(w, kHead, [&] { encodeHead(w, d); });
  section(w, kPage, [&] { encodePages(w, d); });
  section(w, kTuvs, [&] { encodeTriangleUvs(w, d); });
  if (!d.back_uvs.empty()) section(w, kBuvs, [&] { encodeBackUvs(w, d); });
  if (d.has_runtime_sections) {
    section(w, kPtch, [&] { encodePatches(w, d); });
    section(w, kPelm, [&] { encodeU32s(w, d.patch_elements); });
    section(w, kClst, [&] { encodeClusters(w, d); });
    section(w, kEmit, [&] { encodeEmitters(w, d); });
    section(w, kPrxy, [&] { encodeProxy(w, d); });
    section(w, kProb, [&] { encodeProbes(w, d); });
  }
  if (!d.masks.lights.empty()) section(w, kSmsk, [&] { encodeShadowMasks(w, d); });
  w.u64(fnv1a64(w.bytes().data(), w.size()));
  return std::move(w.bytes());
}

// ---------------------------------------------------------------------------
// Decoding: each reads one section's payload; a short read leaves the reader
// failed and the caller reports it. Counts are checked against the bytes left
// (needArray) before anything is allocated.

void decodeHead(ByteReader& r, BakeData& d) {
  d.level_hash = r.u64();
  d.seed = r.u64();
}

void decodePages(ByteReader& r, BakeData& d) {
  const uint32_t n = r.u32();
  if (!r.needArray(n, kPageMinBytes)) return;
  d.pages.resize(n);
  for (BakeLightmapPage& page : d.pages) {
    page.width = r.u32();
    page.height = r.u32();
    page.texel_hash = r.u64();
    page.file = r.string(r.u32());
  }
}

void decodeTriangleUvs(ByteReader& r, BakeData& d) {
  const uint32_t n = r.u32();
  if (!r.needArray(n, kTriangleUvBytes)) return;
  d.triangle_uvs.resize(n);
  for (BakeTriangleUv& uv : d.triangle_uvs) {
    uv.instance = r.u32();
    uv.mesh_triangle = r.u32();
    uv.page = r.u32();
    for (Vec2& c : uv.uv) c = r.vec2();
  }
}

void decodeBackUvs(ByteReader& r, BakeData& d) {
  const uint32_t n = r.u32();
  if (!r.needArray(n, kBackUvBytes)) return;
  d.back_uvs.resize(n);
  for (BakeBackUv& uv : d.back_uvs) {
    uv.triangle = r.u32();
    uv.page = r.u32();
    for (Vec2& c : uv.uv) c = r.vec2();
  }
}

void decodePatches(ByteReader& r, BakeData& d) {
  const uint32_t n = r.u32();
  if (!r.needArray(n, kPatchBytes)) return;
  d.patches.resize(n);
  for (BakePatch& p : d.patches) {
    p.centroid = r.vec3();
    p.normal = r.vec3();
    p.area_m2 = r.f32();
    p.albedo = r.rgb();
    p.emission = r.rgb();
    p.radiosity = r.rgb();
    p.first_element = r.u32();
    p.element_count = r.u32();
  }
}

void decodeU32s(ByteReader& r, std::vector<uint32_t>& values) {
  const uint32_t n = r.u32();
  if (!r.needArray(n, 4)) return;
  values.resize(n);
  for (uint32_t& v : values) v = r.u32();
}

void decodeClusters(ByteReader& r, BakeData& d) {
  const uint32_t n = r.u32();
  if (!r.needArray(n, kClusterBytes)) return;
  d.clusters.resize(n);
  for (BakeClusterNode& c : d.clusters) {
    c.parent = r.i32();
    c.child[0] = r.i32();
    c.child[1] = r.i32();
    c.patch = r.i32();
    c.bounds.min = r.vec3();
    c.bounds.max = r.vec3();
    c.area_m2 = r.f32();
  }
}

void decodeEmitters(ByteReader& r, BakeData& d) {
  const uint32_t n = r.u32();
  if (!r.needArray(n, kEmitterMinBytes)) return;
  d.emitters.resize(n);
  for (BakeEmitter& e : d.emitters) {
    e.kind = BakeEmitter::Kind(r.u32());  // range-checked by validateBakeData()
    e.index = r.u32();
    e.flux = r.rgb();
    const uint32_t lit = r.u32();
    if (!r.needArray(lit, 8)) return;
    e.patches.resize(lit);
    e.factors.resize(lit);
    for (uint32_t& p : e.patches) p = r.u32();
    for (float& f : e.factors) f = r.f32();
  }
}

void decodeProxy(ByteReader& r, BakeData& d) {
  const uint32_t n = r.u32();
  if (!r.needArray(n, 12)) return;
  d.proxy.positions.resize(n);
  for (Vec3& p : d.proxy.positions) p = r.vec3();
  decodeU32s(r, d.proxy.indices);
  decodeU32s(r, d.proxy.face_patch);
}

void decodeProbes(ByteReader& r, BakeData& d) {
  d.probes.origin = r.vec3();
  d.probes.spacing = r.vec3();
  for (uint32_t& dim : d.probes.dims) dim = r.u32();
  const uint32_t n = r.u32();
  if (!r.needArray(n, 4)) return;
  d.probes.sh.resize(n);
  for (float& v : d.probes.sh) v = r.f32();
}

void decodeShadowMasks(ByteReader& r, BakeData& d) {
  const uint32_t lights = r.u32();
  if (!r.needArray(lights, kMaskedLightBytes)) return;
  d.masks.lights.resize(lights);
  for (BakeMaskedLight& light : d.masks.lights) {
    light.emitter = r.u32();
    light.channel = r.u32();
    light.owner = r.u32();
  }
  d.masks.channels = r.u32();
  const uint32_t pages = r.u32();
  if (!r.needArray(pages, kMaskPageMinBytes)) return;
  d.masks.pages.resize(pages);
  for (std::vector<uint16_t>& page : d.masks.pages) {
    const uint64_t values = r.u64();
    if (!r.needArray(values, 2)) return;
    page.resize(size_t(values));
    r.u16s(page.data(), page.size());
  }
}

struct SectionRef {
  uint32_t tag = 0;
  size_t offset = 0;  // of the payload, in the file
  size_t size = 0;
};

std::string osError(int error) { return std::generic_category().message(error); }

constexpr int kKnownSectionCount = 11;
constexpr int kRequiredSectionCount = 3;  // HEAD, PAGE, TUVS
constexpr int kRuntimeSectionEnd = 9;     // the 6 runtime sections follow them
constexpr int kBackUvSection = 9;         // then the optional ones, in kKnown order
constexpr int kShadowMaskSection = 10;
constexpr uint32_t kKnown[kKnownSectionCount] = {kHead, kPage, kTuvs, kPtch, kPelm, kClst,
                                                 kEmit, kPrxy, kProb, kBuvs, kSmsk};

// A short prefix of the magic is a cut file; anything else is not ours.
Status checkMagic(const uint8_t* bytes, size_t size, const std::string& path) {
  const size_t magic_bytes = std::min(size, sizeof kMagic);
  if (magic_bytes > 0 && std::memcmp(bytes, kMagic, magic_bytes) != 0) {
    std::string seen;
    for (size_t i = 0; i < magic_bytes; ++i)
      seen += (bytes[i] >= 0x20 && bytes[i] <= 0x7e) ? char(bytes[i]) : '?';
    return invalid(path, "not a bake file: magic \"" + seen + "\", expected \"SVITBAKE\"");
  }
  if (size < kHeaderBytes + kChecksumBytes) {
    return invalid(path, truncatedText("the smallest bake file (header and checksum)",
                                       kHeaderBytes + kChecksumBytes, size));
  }
  return Status();
}

Status readHeader(const uint8_t* bytes, const std::string& path, uint32_t& version,
                  uint32_t& section_count) {
  ByteReader header(bytes + sizeof kMagic, kHeaderBytes - sizeof kMagic);
  version = header.u32();
  section_count = header.u32();
  if (version != kBakeFileVersion) {
    return invalid(path, "bake file version " + num(version) + ", this build reads version " +
                             num(kBakeFileVersion));
  }
  return Status();
}

// Walks the section table within [header, checksum) before trusting any
// size: a cut file shows up here as a section longer than what is left.
// Then checks the checksum, and that nothing follows the last section.
Status readSectionTable(const uint8_t* bytes, size_t size, uint32_t section_count,
                        const std::string& path, std::vector<SectionRef>& sections) {
  const size_t body_end = size - kChecksumBytes;
  ByteReader body(bytes + kHeaderBytes, body_end - kHeaderBytes);
  for (uint32_t i = 0; i < section_count; ++i) {
    if (!body.need(kSectionHeaderBytes)) {
      return invalid(path,
                     truncatedText("section table entry " + num(i) + " of " + num(section_count),
                                   body.failedNeed(), body.failedLeft()));
    }
    SectionRef ref;
    ref.tag = body.u32();
    const uint64_t payload = body.u64();
    if (!body.need(payload)) {
      return invalid(
          path, truncatedText("section " + tagName(ref.tag), body.failedNeed(), body.failedLeft()));
    }
    ref.offset = kHeaderBytes + body.offset();
    ref.size = size_t(payload);
    body.skip(payload);
    sections.push_back(ref);
  }
  uint64_t stored = 0;
  for (size_t i = 0; i < kChecksumBytes; ++i) stored |= uint64_t(bytes[body_end + i]) << (8 * i);
  if (stored != fnv1a64(bytes, body_end))
    return invalid(path, "checksum mismatch: file is corrupt");
  if (body.remaining() != 0) {
    return invalid(path, num(uint64_t(body.remaining())) + " unexpected bytes after the last of " +
                             num(section_count) + " sections");
  }
  return Status();
}

// found[k]: the section of tag kKnown[k], or null. Each known tag at most
// once, the required ones present, the runtime ones all or none.
Status findKnownSections(const std::vector<SectionRef>& sections, const std::string& path,
                         const SectionRef* (&found)[kKnownSectionCount],
                         bool& has_runtime_sections) {
  for (const SectionRef& ref : sections) {
    for (int k = 0; k < kKnownSectionCount; ++k) {
      if (ref.tag != kKnown[k]) continue;
      if (found[k]) return invalid(path, "section " + tagName(ref.tag) + " appears twice");
      found[k] = &ref;
    }
    // Unknown tags: a later writer of this version added them; skip.
  }
  for (int k = 0; k < kRequiredSectionCount; ++k) {
    if (!found[k]) return invalid(path, "missing required section " + tagName(kKnown[k]));
  }
  int runtime_present = 0;
  for (int k = kRequiredSectionCount; k < kRuntimeSectionEnd; ++k)
    runtime_present += found[k] != nullptr;
  if (runtime_present != 0 && runtime_present != 6) {
    for (int k = kRequiredSectionCount; k < kRuntimeSectionEnd; ++k) {
      if (!found[k]) {
        return invalid(path, "runtime sections incomplete: " + num(int32_t(runtime_present)) +
                                 " of 6 present, " + tagName(kKnown[k]) + " missing");
      }
    }
  }
  has_runtime_sections = runtime_present == 6;
  return Status();
}

// Decodes one section's payload; it must fill the payload exactly.
template <typename Decoder>
Status parseSection(const uint8_t* bytes, const SectionRef& ref, const std::string& path,
                    Decoder decoder, BakeData& data) {
  ByteReader r(bytes + ref.offset, ref.size);
  decoder(r, data);
  if (r.failed())
    return invalid(path,
                   truncatedText("section " + tagName(ref.tag), r.failedNeed(), r.failedLeft()));
  if (r.remaining() != 0) {
    return invalid(path, "section " + tagName(ref.tag) + ": " + num(uint64_t(r.remaining())) +
                             " unexpected bytes after its data");
  }
  return Status();
}

Status parseSections(const uint8_t* bytes, const SectionRef* const (&found)[kKnownSectionCount],
                     const std::string& path, BakeData& data) {
  auto parse = [&](int k, auto decoder) {
    return parseSection(bytes, *found[k], path, decoder, data);
  };
  if (Status s = parse(0, decodeHead); !s.ok()) return s;
  if (Status s = parse(1, decodePages); !s.ok()) return s;
  if (Status s = parse(2, decodeTriangleUvs); !s.ok()) return s;
  if (found[kBackUvSection]) {
    if (Status s = parse(kBackUvSection, decodeBackUvs); !s.ok()) return s;
  }
  if (data.has_runtime_sections) {
    if (Status s = parse(3, decodePatches); !s.ok()) return s;
    if (Status s = parse(4, [](ByteReader& r, BakeData& d) { decodeU32s(r, d.patch_elements); });
        !s.ok())
      return s;
    if (Status s = parse(5, decodeClusters); !s.ok()) return s;
    if (Status s = parse(6, decodeEmitters); !s.ok()) return s;
    if (Status s = parse(7, decodeProxy); !s.ok()) return s;
    if (Status s = parse(8, decodeProbes); !s.ok()) return s;
  }
  // Parsed even without the runtime sections, so that validateBakeData()
  // refuses such a file by name rather than the reader dropping the masks.
  if (found[kShadowMaskSection]) {
    if (Status s = parse(kShadowMaskSection, decodeShadowMasks); !s.ok()) return s;
  }
  return Status();
}

}  // namespace

namespace bakeio {

Expected<BakeData> decodeBakeFile(const uint8_t* bytes, size_t size, const std::string& path) {
  if (Status s = checkMagic(bytes, size, path); !s.ok()) return s;
  uint32_t version = 0, section_count = 0;
  if (Status s = readHeader(bytes, path, version, section_count); !s.ok()) return s;
  std::vector<SectionRef> sections;
  if (Status s = readSectionTable(bytes, size, section_count, path, sections); !s.ok()) return s;
  const SectionRef* found[kKnownSectionCount] = {};
  BakeData data;
  data.version = version;
  if (Status s = findKnownSections(sections, path, found, data.has_runtime_sections); !s.ok())
    return s;
  if (Status s = parseSections(bytes, found, path, data); !s.ok()) return s;
  if (Status s = validateBakeData(data, path); !s.ok()) return s;
  return data;
}

}  // namespace bakeio

const BakeBackUv* findBackUv(const BakeData& data, uint32_t triangle) {
  const auto it =
      std::lower_bound(data.back_uvs.begin(), data.back_uvs.end(), triangle,
                       [](const BakeBackUv& uv, uint32_t t) { return uv.triangle < t; });
  return it != data.back_uvs.end() && it->triangle == triangle ? &*it : nullptr;
}

uint64_t fnv1a64(const void* data, size_t bytes, uint64_t seed) {
  constexpr uint64_t kPrime = 0x100000001b3ull;  // FNV-1a 64 prime
  const auto* p = static_cast<const uint8_t*>(data);
  uint64_t h = seed;
  for (size_t i = 0; i < bytes; ++i) {
    h ^= p[i];
    h *= kPrime;
  }
  return h;
}

Status writeBakeFile(const BakeData& data, const std::string& path) {
  if (data.version != kBakeFileVersion) {
    return invalid(path, "bake data version " + num(data.version) + ", this build writes version " +
                             num(kBakeFileVersion));
  }
  // Everything is checked and encoded before the file system is touched.
  if (Status s = validateBakeData(data, path); !s.ok()) return s;
  const std::vector<uint8_t> bytes = encode(data);

  return writeFileReplacing(path, bytes.data(), bytes.size());
}

std::vector<BakeSectionSize> bakeSectionSizes(const BakeData& data) {
  const std::vector<uint8_t> bytes = encode(data);
  ByteReader header(bytes.data() + sizeof kMagic, kHeaderBytes - sizeof kMagic);
  header.u32();  // version
  const uint32_t count = header.u32();
  ByteReader body(bytes.data() + kHeaderBytes, bytes.size() - kHeaderBytes - kChecksumBytes);
  std::vector<BakeSectionSize> out;
  for (uint32_t i = 0; i < count; ++i) {
    const uint32_t tag = body.u32();
    const uint64_t size = body.u64();
    out.push_back({tagName(tag), size});
    body.skip(size_t(size));
  }
  return out;
}

Expected<BakeData> readBakeFile(const std::string& path) {
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (status.type() == fs::file_type::not_found)
    return Status(StatusCode::kNotFound, path + ": file not found");
  if (ec) return Status(StatusCode::kIoError, path + ": cannot stat: " + ec.message());
  if (status.type() == fs::file_type::directory) {
    return Status(StatusCode::kIoError, path + ": is a directory, not a bake file");
  }
  errno = 0;
  std::ifstream in(path, std::ios::binary);
  if (!in) return Status(StatusCode::kIoError, path + ": cannot open: " + osError(errno));
  std::vector<uint8_t> bytes;
  // Read in chunks rather than trusting file_size(): the file may change
  // under us, and special files report no size.
  char chunk[1 << 16];
  while (in) {
    in.read(chunk, sizeof chunk);
    bytes.insert(bytes.end(), reinterpret_cast<const uint8_t*>(chunk),
                 reinterpret_cast<const uint8_t*>(chunk) + in.gcount());
  }
  if (in.bad()) return Status(StatusCode::kIoError, path + ": read failed: " + osError(errno));
  return bakeio::decodeBakeFile(bytes.data(), bytes.size(), path);
}

}  // namespace svit
