// Work files of a sharded bake (work_file.h).

#include "work_file.h"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>

#include "scene/file_output.h"
#include "svit/bake_file.h"
#include "util/byte_stream.h"

namespace svit::baker {
namespace {

constexpr char kMagic[8] = {'S', 'V', 'I', 'T', 'W', 'O', 'R', 'K'};
// Bumped whenever any payload's layout changes: a work file is read only by
// the build that wrote it (shards and merge run the plan's svit-bake).
// 2: the odd passes' sums and solution; 3: the backs of double-sided triangles;
// 4: the sums of quarters 2 and 3 (the filter's guides)
constexpr uint32_t kWorkFormatVersion = 4;
// magic, version, kind, plan id, payload bytes, payload checksum
constexpr size_t kHeaderBytes = 8 + 4 + 4 + 8 + 8 + 8;

const char* kindName(WorkFileKind kind) {
  switch (kind) {
    case WorkFileKind::kPlan: return "plan";
    case WorkFileKind::kSolution: return "radiosity solution";
    case WorkFileKind::kTexels: return "atlas and texels";
    case WorkFileKind::kShard: return "shard";
  }
  return "unknown";
}

Status bad(const std::string& path, const std::string& what) {
  return Status(StatusCode::kInvalidInput, path + ": " + what);
}

}  // namespace

uint64_t payloadChecksum(const std::vector<uint8_t>& payload) {
  return fnv1a64(payload.data(), payload.size());
}

std::vector<uint8_t> encodeWorkFile(WorkFileKind kind, uint64_t plan_id,
                                    const std::vector<uint8_t>& payload) {
  ByteWriter header;
  for (char c : kMagic) header.put(c);
  header.put(kWorkFormatVersion);
  header.put(uint32_t(kind));
  header.put(plan_id);
  header.put(uint64_t(payload.size()));
  header.put(payloadChecksum(payload));
  std::vector<uint8_t> bytes = header.take();
  bytes.insert(bytes.end(), payload.begin(), payload.end());
  return bytes;
}

Status writeWorkFile(const std::string& path, WorkFileKind kind, uint64_t plan_id,
                     const std::vector<uint8_t>& payload) {
  const std::vector<uint8_t> bytes = encodeWorkFile(kind, plan_id, payload);
  return writeFileReplacing(path, bytes.data(), bytes.size());
}

Expected<WorkFile> readWorkFile(const std::string& path, WorkFileKind kind) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return bad(path, std::string("missing (") + std::strerror(errno) + ")");
  std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                             std::istreambuf_iterator<char>());
  if (in.bad()) return Status(StatusCode::kIoError, path + ": cannot be read");
  ByteReader header(bytes.data(), std::min(bytes.size(), kHeaderBytes));
  char magic[8];
  for (char& c : magic) c = header.get<char>();
  if (!header.ok() || std::memcmp(magic, kMagic, sizeof magic) != 0)
    return bad(path, "not a svit-bake work file");
  const uint32_t version = header.get<uint32_t>();
  const uint32_t found_kind = header.get<uint32_t>();
  WorkFile file;
  file.plan_id = header.get<uint64_t>();
  const uint64_t payload_bytes = header.get<uint64_t>();
  const uint64_t checksum = header.get<uint64_t>();
  if (!header.ok()) return bad(path, "truncated inside its header");
  if (version != kWorkFormatVersion) {
    return bad(path, "work format version " + std::to_string(version) + ", this svit-bake reads " +
                         std::to_string(kWorkFormatVersion) + "; run every step with one build");
  }
  if (found_kind != uint32_t(kind)) {
    return bad(path, std::string("holds a ") + kindName(WorkFileKind(found_kind)) + ", not a " +
                         kindName(kind));
  }
  if (bytes.size() - kHeaderBytes != payload_bytes) {
    return bad(path, "truncated or padded: " + std::to_string(bytes.size()) + " bytes, " +
                         std::to_string(kHeaderBytes + payload_bytes) + " expected");
  }
  file.payload.assign(bytes.begin() + std::ptrdiff_t(kHeaderBytes), bytes.end());
  if (payloadChecksum(file.payload) != checksum) return bad(path, "damaged (checksum mismatch)");
  return file;
}

}  // namespace svit::baker
