#include "svit/lightmap_image.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <vector>

#include <tinyexr.h>

#include "file_output.h"

namespace svit {

Rgb LightmapImage::sampleBilinear(Vec2 uv) const {
  if (width <= 0 || height <= 0) return {0, 0, 0};
  const float x = uv.x * float(width) - 0.5f, y = uv.y * float(height) - 0.5f;
  const float fx = std::floor(x), fy = std::floor(y);
  const float tx = x - fx, ty = y - fy;
  const int x0 = std::clamp(int(fx), 0, width - 1), x1 = std::clamp(int(fx) + 1, 0, width - 1);
  const int y0 = std::clamp(int(fy), 0, height - 1), y1 = std::clamp(int(fy) + 1, 0, height - 1);
  const Rgb a = texel(x0, y0), b = texel(x1, y0), c = texel(x0, y1), d = texel(x1, y1);
  auto mix = [&](float p, float q, float r, float s) {
    return (p * (1 - tx) + q * tx) * (1 - ty) + (r * (1 - tx) + s * tx) * ty;
  };
  return {mix(a.r, b.r, c.r, d.r), mix(a.g, b.g, c.g, d.g), mix(a.b, b.b, c.b, d.b)};
}

Status writeLightmapExr(const LightmapImage& image, const std::string& path) {
  const size_t texels = size_t(image.width) * size_t(image.height);
  if (image.width <= 0 || image.height <= 0 || image.rgb.size() != texels * 3) {
    return Status(StatusCode::kInvalidInput, path + ": lightmap image has inconsistent size");
  }
  for (size_t i = 0; i < image.rgb.size(); ++i) {
    if (!std::isfinite(image.rgb[i])) {
      return Status(StatusCode::kInvalidInput,
                    path + ": texel (" + std::to_string((i / 3) % size_t(image.width)) + ", " +
                        std::to_string((i / 3) / size_t(image.width)) + ") is not finite");
    }
  }
  // EXR stores channels as planes, conventionally sorted by name: B, G, R.
  std::vector<float> planes[3];
  for (int c = 0; c < 3; ++c) planes[c].resize(texels);
  for (size_t i = 0; i < texels; ++i) {
    planes[0][i] = image.rgb[i * 3 + 2];
    planes[1][i] = image.rgb[i * 3 + 1];
    planes[2][i] = image.rgb[i * 3 + 0];
  }
  float* plane_pointers[3] = {planes[0].data(), planes[1].data(), planes[2].data()};
  EXRHeader header;
  InitEXRHeader(&header);
  EXRImage exr;
  InitEXRImage(&exr);
  exr.num_channels = 3;
  exr.images = reinterpret_cast<unsigned char**>(plane_pointers);
  exr.width = image.width;
  exr.height = image.height;
  header.num_channels = 3;
  EXRChannelInfo channels[3];
  std::memset(channels, 0, sizeof channels);
  std::strcpy(channels[0].name, "B");
  std::strcpy(channels[1].name, "G");
  std::strcpy(channels[2].name, "R");
  header.channels = channels;
  int pixel_types[3] = {TINYEXR_PIXELTYPE_FLOAT, TINYEXR_PIXELTYPE_FLOAT, TINYEXR_PIXELTYPE_FLOAT};
  int requested[3] = {TINYEXR_PIXELTYPE_FLOAT, TINYEXR_PIXELTYPE_FLOAT, TINYEXR_PIXELTYPE_FLOAT};
  header.pixel_types = pixel_types;
  // fp32, not half: direct sunlight (1e5 lux) overflows half's 65504.
  header.requested_pixel_types = requested;
  header.compression_type = TINYEXR_COMPRESSIONTYPE_ZIP;
  EXRAttribute comments;
  if (!image.comments.empty()) {
    std::strcpy(comments.name, "comments");
    std::strcpy(comments.type, "string");
    comments.value = reinterpret_cast<unsigned char*>(const_cast<char*>(image.comments.data()));
    comments.size = int(image.comments.size());
    header.num_custom_attributes = 1;
    header.custom_attributes = &comments;
  }
  // Encoded in memory and written by writeFileReplacing: SaveEXRImageToFile
  // does not check fclose, so a write that fails at the last buffered block
  // (a full disk, `ulimit -f`) would pass as a whole file.
  unsigned char* encoded = nullptr;
  const char* error = nullptr;
  const size_t encoded_size = SaveEXRImageToMemory(&exr, &header, &encoded, &error);
  if (encoded_size == 0) {
    const std::string message = error ? error : "unknown error";
    FreeEXRErrorMessage(error);
    std::free(encoded);
    return Status(StatusCode::kIoError, path + ": cannot encode EXR: " + message);
  }
  const Status written = writeFileReplacing(path, encoded, encoded_size);
  std::free(encoded);
  return written;
}

namespace {

// Largest page side read, texels: 8x the baker's default max_page_size
// (2048), far above any page svit-bake writes, so a corrupt header cannot
// make the reader allocate gigabytes.
constexpr int64_t kMaxLightmapSide = 16384;
// Decoded bytes (as floats) allowed per file byte. zlib (EXR's ZIP)
// expands at most ~1032:1 and RLE 64:1; half channels double that as
// floats. The most compressible page writeLightmapExr writes, an all-black
// 4096^2 one, expands about 1000:1, so 4096 leaves 4x margin and still
// refuses a 1 KB file that claims gigabytes of pixels before they are
// allocated.
constexpr int64_t kMaxExpansion = 4096;

std::string exrMessage(const char* error) {
  std::string message = error ? error : "unknown error";
  FreeEXRErrorMessage(error);
  while (!message.empty() && (message.back() == '\n' || message.back() == ' ')) message.pop_back();
  return message;
}

// Frees what tinyexr allocated, on every path out of the reader.
struct ExrHeaderGuard {
  EXRHeader header;
  ExrHeaderGuard() { InitEXRHeader(&header); }
  ~ExrHeaderGuard() { FreeEXRHeader(&header); }
};
struct ExrImageGuard {
  EXRImage image;
  ExrImageGuard() { InitEXRImage(&image); }
  ~ExrImageGuard() { FreeEXRImage(&image); }
};

// The values of every header attribute called `name` in a single-part EXR,
// in file order. Layout (OpenEXR file layout, "Header"): 4-byte magic,
// 4-byte version, then attributes {name\0, type\0, int32 size, size bytes}
// up to an empty name. Returns false when the list runs past the data.
bool headerAttributes(const std::vector<unsigned char>& bytes, const std::string& name,
                      std::vector<std::string>& values) {
  size_t at = 8;
  auto cString = [&](std::string& out) {
    const size_t start = at;
    while (at < bytes.size() && bytes[at] != 0) ++at;
    if (at >= bytes.size()) return false;
    out.assign(reinterpret_cast<const char*>(bytes.data()) + start, at - start);
    ++at;
    return true;
  };
  values.clear();
  for (;;) {
    std::string attribute, type;
    if (!cString(attribute)) return false;
    if (attribute.empty()) return true;
    if (!cString(type) || bytes.size() - at < 4) return false;
    const uint32_t size = uint32_t(bytes[at]) | uint32_t(bytes[at + 1]) << 8 |
                          uint32_t(bytes[at + 2]) << 16 | uint32_t(bytes[at + 3]) << 24;
    at += 4;
    if (size > bytes.size() - at) return false;
    if (attribute == name)
      values.emplace_back(reinterpret_cast<const char*>(bytes.data()) + at, size);
    at += size;
  }
}

Status invalidExr(const std::string& path, const std::string& what) {
  return Status(StatusCode::kInvalidInput, path + ": " + what);
}

Expected<std::vector<unsigned char>> readFileBytes(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec))
    return Status(StatusCode::kNotFound, path + ": file not found");
  if (std::filesystem::is_directory(path, ec))
    return Status(StatusCode::kIoError, path + ": is a directory, not an EXR");
  std::ifstream in(path, std::ios::binary);
  if (!in) return Status(StatusCode::kIoError, path + ": cannot open");
  std::vector<unsigned char> bytes;
  char chunk[1 << 16];
  while (in) {
    in.read(chunk, sizeof chunk);
    bytes.insert(bytes.end(), chunk, chunk + in.gcount());
  }
  if (in.bad()) return Status(StatusCode::kIoError, path + ": read failed");
  return bytes;
}

Status checkVersion(const std::vector<unsigned char>& bytes, const std::string& path,
                    EXRVersion& version) {
  if (ParseEXRVersionFromMemory(&version, bytes.data(), bytes.size()) != TINYEXR_SUCCESS) {
    return invalidExr(path, "not a readable EXR: no OpenEXR magic number and version 2");
  }
  if (version.multipart || version.non_image || version.tiled) {
    return Status(StatusCode::kUnsupported,
                  path + ": " +
                      (version.multipart   ? "multi-part"
                       : version.non_image ? "deep"
                                           : "tiled") +
                      " EXR; lightmap pages are single-part scanline images");
  }
  return Status();
}

// Debian's tinyexr keeps assert() on: a part type other than the four it
// knows aborts the process inside ParseEXRHeaderFromMemory (found by
// fuzz_lightmap_exr). A lightmap is a scanline image; say so first.
// Every 'type' attribute counts (tinyexr keeps whichever it parsed last
// with data), read as tinyexr reads it: up to the first NUL.
Status checkPartTypes(const std::vector<unsigned char>& bytes, const std::string& path) {
  std::vector<std::string> part_types;
  if (!headerAttributes(bytes, "type", part_types))
    return invalidExr(path, "not a readable EXR: header runs past the file");
  for (const std::string& value : part_types) {
    const std::string part_type = value.substr(0, value.find('\0'));
    if (part_type.empty() || part_type == "scanlineimage") continue;
    std::string printable;
    for (char c : part_type.substr(0, 32)) printable += (c >= 0x20 && c <= 0x7e) ? c : '?';
    return Status(StatusCode::kUnsupported,
                  path + ": part type '" + printable + "'; lightmap pages are scanline images");
  }
  return Status();
}

Status parseHeader(const std::vector<unsigned char>& bytes, const EXRVersion& version,
                   const std::string& path, EXRHeader& h) {
  const char* error = nullptr;
  if (ParseEXRHeaderFromMemory(&h, &version, bytes.data(), bytes.size(), &error) !=
      TINYEXR_SUCCESS) {
    return invalidExr(path, "not a readable EXR: " + exrMessage(error));
  }
  if (h.tiled || h.multipart || h.non_image) {
    return invalidExr(path, "header disagrees with the version field (tiled, deep or multi-part)");
  }
  return Status();
}

// svit-bake writes ZIP; uncompressed, RLE and single-line ZIP are as
// simple. PIZ is refused: tinyexr 1.0.1's Huffman decoder reads its table
// header past the end of a short chunk (heap overread, found by
// fuzz_lightmap_exr), and svit writes none of the other compressions.
Status checkCompression(const EXRHeader& h, const std::string& path) {
  if (h.compression_type != TINYEXR_COMPRESSIONTYPE_NONE &&
      h.compression_type != TINYEXR_COMPRESSIONTYPE_RLE &&
      h.compression_type != TINYEXR_COMPRESSIONTYPE_ZIPS &&
      h.compression_type != TINYEXR_COMPRESSIONTYPE_ZIP) {
    return Status(StatusCode::kUnsupported,
                  path + ": compression " + std::to_string(h.compression_type) +
                      " (lightmap pages are uncompressed, RLE or ZIP; PIZ is not read)");
  }
  return Status();
}

// Finds the R, G and B channels and asks tinyexr for every channel as float.
Status selectChannels(EXRHeader& h, const std::string& path, int rgb_channel[3]) {
  for (int c = 0; c < h.num_channels; ++c) {
    const EXRChannelInfo& channel = h.channels[c];
    for (int k = 0; k < 3; ++k) {
      if (std::strcmp(channel.name, k == 0 ? "R" : k == 1 ? "G" : "B") == 0) rgb_channel[k] = c;
    }
    if (h.pixel_types[c] != TINYEXR_PIXELTYPE_HALF && h.pixel_types[c] != TINYEXR_PIXELTYPE_FLOAT &&
        h.pixel_types[c] != TINYEXR_PIXELTYPE_UINT) {
      return invalidExr(path, "channel " + std::to_string(c) + " has unknown pixel type " +
                                  std::to_string(h.pixel_types[c]));
    }
    if (channel.x_sampling != 1 || channel.y_sampling != 1) {
      return Status(StatusCode::kUnsupported, path + ": channel " + std::to_string(c) +
                                                  " is subsampled (" +
                                                  std::to_string(channel.x_sampling) + " x " +
                                                  std::to_string(channel.y_sampling) + ")");
    }
    // Everything is decoded as float (HALF widened); UINT channels other than
    // R, G, B are read and ignored.
    if (h.pixel_types[c] == TINYEXR_PIXELTYPE_HALF)
      h.requested_pixel_types[c] = TINYEXR_PIXELTYPE_FLOAT;
  }
  for (int k = 0; k < 3; ++k) {
    if (rgb_channel[k] < 0)
      return invalidExr(
          path, std::string("no ") + "RGB"[k] + " channel (a lightmap page has R, G and B)");
    if (h.pixel_types[rgb_channel[k]] == TINYEXR_PIXELTYPE_UINT) {
      return invalidExr(
          path, std::string("channel ") + "RGB"[k] + " holds unsigned integers, not half or float");
    }
  }
  return Status();
}

// Refuses sizes that a file of this length cannot hold before any pixel is allocated.
Status checkImageSize(const EXRHeader& h, size_t file_bytes, const std::string& path,
                      int64_t& width, int64_t& height) {
  width = int64_t(h.data_window.max_x) - h.data_window.min_x + 1;
  height = int64_t(h.data_window.max_y) - h.data_window.min_y + 1;
  if (width < 1 || height < 1 || width > kMaxLightmapSide || height > kMaxLightmapSide) {
    return invalidExr(path, "data window " + std::to_string(width) + " x " +
                                std::to_string(height) + " texels is empty or larger than " +
                                std::to_string(kMaxLightmapSide) + " on a side");
  }
  // The offset table holds one 8-byte offset per chunk of at least one
  // scanline; tinyexr sizes it from a chunkCount attribute if there is one
  // (825 million for 9 scanlines would ask for 6.6 GB: found by
  // fuzz_lightmap_exr).
  if (h.chunk_count < 0 || h.chunk_count > height ||
      int64_t(h.chunk_count) * 8 > int64_t(file_bytes)) {
    return invalidExr(path, "chunkCount " + std::to_string(h.chunk_count) + " does not fit " +
                                std::to_string(height) + " scanlines in a file of " +
                                std::to_string(file_bytes) + " bytes");
  }
  const int64_t decoded_bytes = width * height * int64_t(h.num_channels) * 4;
  if (decoded_bytes > kMaxExpansion * int64_t(file_bytes)) {
    return invalidExr(path, std::to_string(width) + " x " + std::to_string(height) + " texels of " +
                                std::to_string(h.num_channels) +
                                " channels cannot be stored in a file of " +
                                std::to_string(file_bytes) + " bytes");
  }
  return Status();
}

Status decodeImage(const std::vector<unsigned char>& bytes, EXRHeader& h, int64_t width,
                   int64_t height, const std::string& path, EXRImage& exr) {
  // tinyexr 1.0.1 sets num_channels only once decoding succeeds, so when a
  // corrupt chunk fails the decode its own cleanup frees no channel planes
  // (a leak per bad file, found by fuzz_lightmap_exr). Set it up front: the
  // cleanup then frees them. Nothing else reads it before it is set.
  exr.num_channels = h.num_channels;
  const char* error = nullptr;
  if (LoadEXRImageFromMemory(&exr, &h, bytes.data(), bytes.size(), &error) != TINYEXR_SUCCESS) {
    // tinyexr has already released what it could (FreeEXRImage without
    // resetting the pointers): forget them, or the guard frees them twice.
    InitEXRImage(&exr);
    return invalidExr(path, "not a readable EXR: " + exrMessage(error));
  }
  if (exr.images == nullptr || exr.width != width || exr.height != height ||
      exr.num_channels != h.num_channels) {
    return invalidExr(path, "decoded image does not match its header");
  }
  return Status();
}

Expected<LightmapImage> copyRgbPlanes(const EXRImage& exr, const int rgb_channel[3], int64_t width,
                                      int64_t height, const std::string& path) {
  LightmapImage out;
  out.width = int(width);
  out.height = int(height);
  const size_t texels = size_t(width) * size_t(height);
  out.rgb.resize(texels * 3);
  for (int k = 0; k < 3; ++k) {
    const float* plane = reinterpret_cast<const float*>(exr.images[rgb_channel[k]]);
    for (size_t i = 0; i < texels; ++i) {
      // NaN or Inf would spread through every bilinear lookup that touches
      // the texel (found by fuzz_lightmap_exr).
      if (!std::isfinite(plane[i])) {
        return invalidExr(path, "texel (" + std::to_string(i % size_t(width)) + ", " +
                                    std::to_string(i / size_t(width)) + ") channel " + "RGB"[k] +
                                    " is not finite");
      }
      out.rgb[i * 3 + size_t(k)] = plane[i];
    }
  }
  return out;
}

}  // namespace

// The reader takes what writeLightmapExr writes and what other tools write
// for the same job: one scanline part with R, G and B channels of half or
// float. tinyexr's whole-file LoadEXR() is avoided on purpose: it also takes
// tiled and deep files through less-tested paths, and the lower-level calls
// let every header field be checked before the pixels are allocated
// (docs/fuzzing.md).
Expected<LightmapImage> readLightmapExr(const std::string& path) {
  Expected<std::vector<unsigned char>> read = readFileBytes(path);
  if (!read.ok()) return read.status();
  const std::vector<unsigned char>& bytes = read.value();
  EXRVersion version;
  if (Status s = checkVersion(bytes, path, version); !s.ok()) return s;
  if (Status s = checkPartTypes(bytes, path); !s.ok()) return s;
  ExrHeaderGuard header;
  EXRHeader& h = header.header;
  if (Status s = parseHeader(bytes, version, path, h); !s.ok()) return s;
  if (Status s = checkCompression(h, path); !s.ok()) return s;
  int rgb_channel[3] = {-1, -1, -1};
  if (Status s = selectChannels(h, path, rgb_channel); !s.ok()) return s;
  int64_t width = 0, height = 0;
  if (Status s = checkImageSize(h, bytes.size(), path, width, height); !s.ok()) return s;
  ExrImageGuard image;
  if (Status s = decodeImage(bytes, h, width, height, path, image.image); !s.ok()) return s;
  Expected<LightmapImage> out = copyRgbPlanes(image.image, rgb_channel, width, height, path);
  std::vector<std::string> comments;
  if (out.ok() && headerAttributes(bytes, "comments", comments) && !comments.empty())
    out->comments = comments.front();
  return out;
}

}  // namespace svit
