// The bake's output directory: staging beside OUT, the atomic swap, and the
// clean-up of what killed bakes left (bake_output.h, bake.h).

#include "bake_output.h"

#include <fcntl.h>
#include <signal.h>
#include <stdio.h>  // renameat2 (glibc 2.28+, _GNU_SOURCE)
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <system_error>

#include "scene/file_output.h"
#include "svit/baker/bake.h"

namespace svit::baker {
namespace {

namespace fs = std::filesystem;

std::string osError(int error) { return std::generic_category().message(error); }

// The pid in "OUT.tmp-<pid>" or "OUT.old-<pid>", 0 when `name` is neither.
pid_t stagingPid(const std::string& name, const std::string& out_name) {
  for (const char* kind : {".tmp-", ".old-"}) {
    const std::string prefix = out_name + kind;
    if (name.size() <= prefix.size() || name.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string digits = name.substr(prefix.size());
    if (digits.find_first_not_of("0123456789") != std::string::npos || digits.size() > 9) return 0;
    return pid_t(std::atoi(digits.c_str()));
  }
  return 0;
}

// Only ESRCH proves the process gone; EPERM is someone else's live process.
bool processIsGone(pid_t pid) { return ::kill(pid, 0) == -1 && errno == ESRCH; }

// For file systems without RENAME_EXCHANGE (NFS, some FUSE): the previous
// bake moves aside first, so a kill between the two renames leaves no OUT,
// only OUT.old-<pid> (which the next bake would remove: rescue it by hand).
Status swapInTwoRenames(const fs::path& staging, const fs::path& out) {
  const fs::path old =
      out.parent_path() / (out.filename().string() + ".old-" + std::to_string(::getpid()));
  std::error_code ec;
  const bool had_previous = fs::exists(out, ec);
  if (had_previous) fs::rename(out, old, ec);
  if (ec) {
    return Status(StatusCode::kIoError,
                  out.string() + ": cannot move the previous bake aside: " + ec.message());
  }
  fs::rename(staging, out, ec);
  if (ec) {
    std::error_code ignored;
    if (had_previous) fs::rename(old, out, ignored);
    return Status(StatusCode::kIoError,
                  out.string() + ": cannot move the new bake in place: " + ec.message());
  }
  if (had_previous) fs::remove_all(old, ec);
  return Status();
}

}  // namespace

fs::path bakeOutputPath(const std::string& out_dir) {
  fs::path out = fs::path(out_dir).lexically_normal();
  if (!out.has_filename()) out = out.parent_path();  // "bake/" -> "bake"
  return out;
}

Status checkBakeOutput(const fs::path& out) {
  // The staging directory is made beside OUT, with any missing parents, in
  // the nearest directory that exists.
  std::error_code ec;
  fs::path existing = out.parent_path();
  while (!existing.empty() && !fs::exists(existing, ec)) existing = existing.parent_path();
  if (Status s = checkWritableDirectory(existing.string()); !s.ok())
    return Status(s.code(), out.string() + ": " + s.message());
  const fs::file_status status = fs::symlink_status(out, ec);
  if (status.type() == fs::file_type::not_found) return Status();
  if (status.type() != fs::file_type::directory) {
    return Status(StatusCode::kInvalidInput,
                  out.string() +
                      ": is not a directory (a file or a symbolic link); not replacing it with a "
                      "bake");
  }
  if (fs::is_empty(out, ec) || fs::exists(out / "bake.svit", ec)) return Status();
  return Status(StatusCode::kInvalidInput,
                out.string() +
                    ": a directory that holds no bake.svit; not replacing it with a bake "
                    "(remove it or choose another -o)");
}

fs::path stagingDirectory(const fs::path& out) {
  return out.parent_path() / (out.filename().string() + ".tmp-" + std::to_string(::getpid()));
}

Status swapIntoPlace(const fs::path& staging, const fs::path& out) {
  // The exchange leaves OUT a whole bake at every instant, and the previous
  // bake at `staging`, to be removed.
  if (::renameat2(AT_FDCWD, staging.c_str(), AT_FDCWD, out.c_str(), RENAME_EXCHANGE) == 0) {
    std::error_code ec;
    fs::remove_all(staging, ec);
    return Status();
  }
  const int error = errno;
  if (error == EINVAL || error == ENOSYS) return swapInTwoRenames(staging, out);
  if (error != ENOENT) {
    return Status(StatusCode::kIoError, out.string() + ": cannot swap in the new bake from " +
                                            staging.string() + ": " + osError(error));
  }
  // No previous bake (`staging` exists: we made it). rename(2) refuses a
  // non-empty OUT that appeared meanwhile.
  if (::rename(staging.c_str(), out.c_str()) != 0) {
    return Status(StatusCode::kIoError, out.string() + ": cannot move the new bake in place from " +
                                            staging.string() + ": " + osError(errno));
  }
  return Status();
}

Expected<std::vector<std::string>> removeAbandonedBakeDirectories(const std::string& out_dir) {
  const fs::path out = bakeOutputPath(out_dir);
  const fs::path parent = out.parent_path().empty() ? fs::path(".") : out.parent_path();
  // Listed first, removed after: the listing does not see its own removals.
  std::vector<fs::path> abandoned;
  std::error_code ec;
  for (fs::directory_iterator it(parent, ec), end; !ec && it != end; it.increment(ec)) {
    const pid_t pid = stagingPid(it->path().filename().string(), out.filename().string());
    if (pid > 0 && pid != ::getpid() && processIsGone(pid))
      abandoned.push_back(out.parent_path() / it->path().filename());
  }
  std::vector<std::string> removed;
  for (const fs::path& path : abandoned) {
    fs::remove_all(path, ec);
    if (ec) {
      return Status(StatusCode::kIoError,
                    path.string() + ": cannot remove what a killed bake left: " + ec.message());
    }
    removed.push_back(path.string());
  }
  return removed;
}

}  // namespace svit::baker
