#pragma once
// The bake-file parser behind readBakeFile(), on bytes already in memory, so
// the fuzz target (tests/fuzz) can drive it without the file system.
// Internal to svit::scene; not installed.

#include <cstddef>
#include <cstdint>
#include <string>

#include "svit/bake_file.h"
#include "svit/status.h"

namespace svit::bakeio {

/// Parses and validates a whole bake file (`size` bytes at `bytes`, the
/// layout at the top of bake_file.cpp): the same checks and messages as
/// readBakeFile(), which reads the file and calls this. `path` only prefixes
/// the messages. Any byte sequence is acceptable input: the result is the
/// data or kInvalidInput naming the section, element and value; allocations
/// are bounded by `size`. `bytes` may be null when `size` is 0.
/// Thread-safe: yes (no shared state).
Expected<BakeData> decodeBakeFile(const uint8_t* bytes, size_t size, const std::string& path);

}  // namespace svit::bakeio
