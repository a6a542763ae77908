#pragma once
// Little-endian byte encoding for bake files and the level hash. Every field
// is written byte by byte (floats as their IEEE-754 bits), never as a struct
// memcpy, so the format does not depend on the host's endianness, padding or
// alignment. The one bulk copy, of u16 arrays (u16s), happens only on
// little-endian hosts, where it yields the same bytes. Internal to
// svit::scene; not installed.

#include <bit>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "svit/math_types.h"

namespace svit::bakeio {

/// The field encodings shared by everything that serializes: `Sink` (CRTP)
/// provides `put(const uint8_t*, size_t)`; the bytes are the same whether
/// they go to a file (ByteWriter) or into a hash (level_hash.cpp).
template <typename Sink>
class LittleEndianEncoder {
 public:
  void u8(uint8_t v) { sink().put(&v, 1); }
  void u16(uint16_t v) {
    const uint8_t b[2] = {uint8_t(v), uint8_t(v >> 8)};
    sink().put(b, 2);
  }
  /// `count` u16 values in order. Shadow masks hold 4 values per texel and layer,
  /// millions on a large level, so a little-endian host hands the array over in
  /// one put(): its bytes already are the encoding. Other hosts go value by
  /// value.
  void u16s(const uint16_t* values, size_t count) {
    if constexpr (std::endian::native == std::endian::little) {
      sink().put(reinterpret_cast<const uint8_t*>(values), count * sizeof(uint16_t));
    } else {
      for (size_t i = 0; i < count; ++i) u16(values[i]);
    }
  }
  void u32(uint32_t v) {
    const uint8_t b[4] = {uint8_t(v), uint8_t(v >> 8), uint8_t(v >> 16), uint8_t(v >> 24)};
    sink().put(b, 4);
  }
  void u64(uint64_t v) {
    u32(uint32_t(v));
    u32(uint32_t(v >> 32));
  }
  void i32(int32_t v) { u32(uint32_t(v)); }  // two's complement bits
  void f32(float v) { u32(std::bit_cast<uint32_t>(v)); }
  void vec2(const Vec2& v) {
    f32(v.x);
    f32(v.y);
  }
  void vec3(const Vec3& v) {
    f32(v.x);
    f32(v.y);
    f32(v.z);
  }
  void rgb(const Rgb& c) {
    f32(c.r);
    f32(c.g);
    f32(c.b);
  }
  void raw(const void* data, size_t size) { sink().put(static_cast<const uint8_t*>(data), size); }

 private:
  Sink& sink() { return static_cast<Sink&>(*this); }
};

/// Appends little-endian fields to a growing byte vector.
class ByteWriter : public LittleEndianEncoder<ByteWriter> {
 public:
  void put(const uint8_t* p, size_t size) { bytes_.insert(bytes_.end(), p, p + size); }
  /// Overwrites 8 bytes at `offset` (a size field reserved earlier).
  void patchU64(size_t offset, uint64_t v) {
    for (int i = 0; i < 8; ++i) bytes_[offset + size_t(i)] = uint8_t(v >> (8 * i));
  }
  size_t size() const { return bytes_.size(); }
  const std::vector<uint8_t>& bytes() const { return bytes_; }
  std::vector<uint8_t>& bytes() { return bytes_; }

 private:
  std::vector<uint8_t> bytes_;
};

/// Reads little-endian fields from a byte range it does not own. Every read
/// is bounds-checked: the first one past the end makes the reader fail
/// (sticky) and returns zeros from then on; `failedNeed()`/`failedLeft()`
/// say how many bytes that read wanted and how many there were, for the
/// caller's "truncated" message. Callers check `need()` before allocating
/// for a count read from the data, so a corrupt count cannot cause a huge
/// allocation.
class ByteReader {
 public:
  ByteReader(const uint8_t* data, size_t size) : data_(data), size_(size) {}

  /// True when `bytes` more bytes are available; otherwise fails the reader.
  bool need(uint64_t bytes) {
    if (failed_) return false;
    if (bytes > remaining()) {
      failed_ = true;
      failed_need_ = bytes;
      failed_left_ = remaining();
      return false;
    }
    return true;
  }
  /// need(count * element_bytes) without overflowing.
  bool needArray(uint64_t count, uint64_t element_bytes) {
    if (element_bytes != 0 && count > UINT64_MAX / element_bytes) return need(UINT64_MAX);
    return need(count * element_bytes);
  }

  uint8_t u8() { return need(1) ? data_[offset_++] : 0; }
  uint16_t u16() {
    if (!need(2)) return 0;
    const uint16_t v = uint16_t(data_[offset_] | data_[offset_ + 1] << 8);
    offset_ += 2;
    return v;
  }
  /// Fills `values[0, count)`, or fails the reader (values untouched) when
  /// fewer than 2 * count bytes are left. One memcpy on a little-endian host,
  /// as the encoder's u16s().
  void u16s(uint16_t* values, size_t count) {
    if (!needArray(count, sizeof(uint16_t))) return;
    if constexpr (std::endian::native == std::endian::little) {
      if (count != 0) std::memcpy(values, data_ + offset_, count * sizeof(uint16_t));
      offset_ += count * sizeof(uint16_t);
    } else {
      for (size_t i = 0; i < count; ++i) values[i] = u16();
    }
  }
  uint32_t u32() {
    if (!need(4)) return 0;
    uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v |= uint32_t(data_[offset_ + size_t(i)]) << (8 * i);
    offset_ += 4;
    return v;
  }
  uint64_t u64() {
    if (!need(8)) return 0;
    uint64_t v = 0;
    for (int i = 0; i < 8; ++i) v |= uint64_t(data_[offset_ + size_t(i)]) << (8 * i);
    offset_ += 8;
    return v;
  }
  int32_t i32() { return int32_t(u32()); }
  float f32() { return std::bit_cast<float>(u32()); }
  Vec2 vec2() {
    Vec2 v;
    v.x = f32();
    v.y = f32();
    return v;
  }
  Vec3 vec3() {
    Vec3 v;
    v.x = f32();
    v.y = f32();
    v.z = f32();
    return v;
  }
  Rgb rgb() {
    Rgb c;
    c.r = f32();
    c.g = f32();
    c.b = f32();
    return c;
  }
  /// `size` raw bytes as a string (empty on failure).
  std::string string(uint64_t size) {
    if (!need(size)) return {};
    std::string s(reinterpret_cast<const char*>(data_ + offset_), size_t(size));
    offset_ += size_t(size);
    return s;
  }
  /// Advances without reading (unknown sections).
  void skip(uint64_t bytes) {
    if (need(bytes)) offset_ += size_t(bytes);
  }

  bool failed() const { return failed_; }
  uint64_t failedNeed() const { return failed_need_; }
  uint64_t failedLeft() const { return failed_left_; }
  size_t offset() const { return offset_; }
  size_t remaining() const { return size_ - offset_; }
  const uint8_t* cursor() const { return data_ + offset_; }

 private:
  const uint8_t* data_;
  size_t size_;
  size_t offset_ = 0;
  bool failed_ = false;
  uint64_t failed_need_ = 0;
  uint64_t failed_left_ = 0;
};

}  // namespace svit::bakeio
