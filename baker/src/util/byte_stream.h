#pragma once
// Little byte streams for the sharded bake's work files (work_file.h): plain
// values and vectors of plain values appended to, and read back from, a byte
// buffer in this machine's layout. A work file is read only by the build
// that wrote it (work_file.h checks the format version), so no byte
// swapping. Reads past the end set a sticky failure instead of reading
// garbage; the caller checks ok() once. Internal.

#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

namespace svit::baker {

class ByteWriter {
 public:
  template <typename T>
  void put(const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    const auto* p = reinterpret_cast<const uint8_t*>(&value);
    bytes_.insert(bytes_.end(), p, p + sizeof(T));
  }
  /// A length (uint64) and the elements.
  template <typename T>
  void putVector(const std::vector<T>& values) {
    static_assert(std::is_trivially_copyable_v<T>);
    put(uint64_t(values.size()));
    const auto* p = reinterpret_cast<const uint8_t*>(values.data());
    bytes_.insert(bytes_.end(), p, p + values.size() * sizeof(T));
  }
  void putString(const std::string& text) {
    put(uint64_t(text.size()));
    bytes_.insert(bytes_.end(), text.begin(), text.end());
  }
  const std::vector<uint8_t>& bytes() const { return bytes_; }
  std::vector<uint8_t> take() { return std::move(bytes_); }

 private:
  std::vector<uint8_t> bytes_;
};

class ByteReader {
 public:
  ByteReader(const uint8_t* data, size_t size) : data_(data), size_(size) {}
  explicit ByteReader(const std::vector<uint8_t>& bytes) : ByteReader(bytes.data(), bytes.size()) {}

  template <typename T>
  T get() {
    static_assert(std::is_trivially_copyable_v<T>);
    T value{};
    if (!take(&value, sizeof(T))) return T{};
    return value;
  }
  /// A vector written by putVector; empty (and failed) when its length runs past the end.
  template <typename T>
  std::vector<T> getVector() {
    const uint64_t count = get<uint64_t>();
    if (!ok_ || count > (size_ - offset_) / sizeof(T)) {
      ok_ = false;
      return {};
    }
    std::vector<T> values(count);
    take(values.data(), count * sizeof(T));
    return values;
  }
  std::string getString() {
    const uint64_t count = get<uint64_t>();
    if (!ok_ || count > size_ - offset_) {
      ok_ = false;
      return {};
    }
    std::string text(reinterpret_cast<const char*>(data_ + offset_), count);
    offset_ += count;
    return text;
  }
  /// No read ran past the end.
  bool ok() const { return ok_; }
  /// Everything was read, and nothing past it.
  bool atEnd() const { return ok_ && offset_ == size_; }

 private:
  bool take(void* out, size_t bytes) {
    if (!ok_ || bytes > size_ - offset_) {
      ok_ = false;
      return false;
    }
    std::memcpy(out, data_ + offset_, bytes);
    offset_ += bytes;
    return true;
  }

  const uint8_t* data_;
  size_t size_;
  size_t offset_ = 0;
  bool ok_ = true;
};

}  // namespace svit::baker
