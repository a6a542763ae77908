// Checked whole-file output (file_output.h). POSIX open/write/close rather
// than iostreams or stdio: their buffering defers the failing write to a
// close whose result callers (tinyexr, stb_image_write) do not check, and
// errno after a failed stream operation is not specified.

#include "file_output.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <system_error>

namespace svit {
namespace {

std::string osError(int error) { return std::generic_category().message(error); }

// Writes all `size` bytes, resuming after partial writes and signals; the
// errno of the write that failed, 0 when all were written.
int writeAll(int fd, const uint8_t* bytes, size_t size) {
  while (size > 0) {
    const ssize_t n = ::write(fd, bytes, size);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return errno;
    if (n == 0) return EIO;  // a regular file never takes zero bytes without an error
    bytes += n;
    size -= size_t(n);
  }
  return 0;
}

}  // namespace

Status writeFileReplacing(const std::string& path, const void* data, size_t size) {
  const std::string temporary = path + ".tmp";
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd < 0) {
    // Not created by us (e.g. a directory of that name): nothing to remove.
    return Status(StatusCode::kIoError, temporary + ": cannot create: " + osError(errno));
  }
  const int write_error = writeAll(fd, static_cast<const uint8_t*>(data), size);
  // close(2) reports deferred write errors on some file systems (NFS).
  const int close_error = ::close(fd) == 0 ? 0 : errno;
  if (write_error != 0 || close_error != 0) {
    ::unlink(temporary.c_str());
    return Status(StatusCode::kIoError,
                  temporary + (write_error != 0 ? ": cannot write " + std::to_string(size) +
                                                      " bytes: " + osError(write_error)
                                                : ": cannot close: " + osError(close_error)));
  }
  if (::rename(temporary.c_str(), path.c_str()) != 0) {
    const int error = errno;
    ::unlink(temporary.c_str());
    return Status(StatusCode::kIoError,
                  path + ": cannot replace it with " + temporary + ": " + osError(error));
  }
  return Status();
}

Status checkWritableDirectory(const std::string& dir) {
  const std::filesystem::path probe = std::filesystem::path(dir.empty() ? "." : dir) /
                                      (".svit-write-check-" + std::to_string(::getpid()));
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
  if (fd < 0) {
    return Status(StatusCode::kIoError,
                  (dir.empty() ? "." : dir) + ": cannot create a file there: " + osError(errno));
  }
  ::close(fd);
  ::unlink(probe.c_str());
  return Status();
}

}  // namespace svit
