#pragma once
// Shared by the libFuzzer targets of tests/fuzz: how a target reports a
// broken promise, and a private scratch directory for the APIs that take
// paths. Header-only; each target is one translation unit.

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <signal.h>
#include <unistd.h>

#ifndef SVIT_TEST_DATA_DIR
#error "SVIT_TEST_DATA_DIR must name tests/data (a string literal, no trailing slash)"
#endif

namespace svit::fuzz {

/// Prints `what` and aborts, which libFuzzer records as a crash with the input.
[[noreturn]] inline void fail(const std::string& what) {
  std::fprintf(stderr, "svit fuzz oracle: %s\n", what.c_str());
  std::fflush(stderr);
  std::abort();
}

/// A directory of this process's own, removed at exit. Placed in /dev/shm
/// when there is one (no disk I/O per input), else in the temp directory.
/// Not thread-safe (libFuzzer runs one input at a time per process).
class ScratchDir {
 public:
  ScratchDir() {
    std::error_code ec;
    std::filesystem::path base = "/dev/shm";
    if (!std::filesystem::is_directory(base, ec) || ::access(base.c_str(), W_OK) != 0) {
      base = std::filesystem::temp_directory_path();
    }
    removeAbandoned(base);
    std::string pattern = (base / ("svit_fuzz_" + std::to_string(::getpid()) + "_XXXXXX")).string();
    if (::mkdtemp(pattern.data()) == nullptr)
      fail("cannot create a scratch directory under " + base.string());
    dir_ = pattern;
  }
  ~ScratchDir() {
    std::error_code ignored;
    std::filesystem::remove_all(dir_, ignored);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;

  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  /// Writes `size` bytes to `name` in the directory; returns its path.
  std::string write(const std::string& name, const uint8_t* data, size_t size) const {
    const std::string file = path(name);
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
    out.close();
    if (!out) fail("cannot write " + file);
    return file;
  }

  /// Copies every file of tests/data whose name ends in `suffix` into the
  /// directory (so a fuzzed level.json can name a real glTF beside it).
  void copyTestData(const std::string& suffix) const {
    for (const auto& entry : std::filesystem::directory_iterator(SVIT_TEST_DATA_DIR)) {
      const std::string name = entry.path().filename().string();
      if (name.size() >= suffix.size() &&
          name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0) {
        std::filesystem::copy_file(entry.path(), dir_ / name,
                                   std::filesystem::copy_options::overwrite_existing);
      }
    }
  }

 private:
  // A crash ends the process without destructors, leaving its directory;
  // the next run removes those whose process (the pid in the name) is gone.
  static void removeAbandoned(const std::filesystem::path& base) {
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(base, ec)) {
      const std::string name = entry.path().filename().string();
      if (name.rfind("svit_fuzz_", 0) != 0) continue;
      const long pid = std::strtol(name.c_str() + 10, nullptr, 10);
      if (pid > 0 && ::kill(pid_t(pid), 0) != 0 && errno == ESRCH) {
        std::error_code ignored;
        std::filesystem::remove_all(entry.path(), ignored);
      }
    }
  }

  std::filesystem::path dir_;
};

}  // namespace svit::fuzz
