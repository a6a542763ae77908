#pragma once
// Writing output files so that nothing is lost: whole files through a
// `.tmp` and a rename, every write checked (a full disk or `ulimit -f` is an
// error naming the file, never a silently short file), and output
// directories checked before any work is done. Internal to svit (the scene
// library, the baker, the runtime's frame writers, svit-walk); not installed.

#include <cstddef>
#include <string>

#include "svit/status.h"

namespace svit {

/// Writes `size` bytes at `data` to `path` via `path`.tmp and a rename, so a
/// reader sees the old file or the whole new one. Every write(2) and the
/// close(2) are checked: a short write (ENOSPC, EFBIG under `ulimit -f`
/// when SIGXFSZ is ignored) returns kIoError naming the `.tmp` file, the
/// byte count and the reason ("File too large"); the `.tmp` is removed and
/// `path` left as it was on any failure. Thread-safe for distinct paths.
Status writeFileReplacing(const std::string& path, const void* data, size_t size);

/// Ok when a file can be created in the directory `dir` ("" means the
/// current directory): tries it, with a probe file that is removed again,
/// because access(2) says yes to root whatever the permissions and knows
/// nothing of read-only mounts. Else kIoError "`dir`: cannot create a file
/// there: <reason>" (No such file or directory, Not a directory, ...).
Status checkWritableDirectory(const std::string& dir);

}  // namespace svit
