#pragma once
// Where a bake is written and how it replaces the previous one (bake.h):
// the bake goes into OUT.tmp-<pid> beside OUT and is swapped in whole, so
// OUT is at every moment either the previous bake or the new one, even when
// the process is killed (SIGKILL, power cut aside: nothing is fsync'ed).

#include <filesystem>
#include <string>

#include "svit/status.h"

namespace svit::baker {

/// OUT as a path with a file name: "bake/" and "bake/." become "bake".
std::filesystem::path bakeOutputPath(const std::string& out_dir);

/// Ok when `out` is missing, an empty directory or a directory holding a
/// bake.svit (a previous bake); else kInvalidInput naming `out`, so that a
/// bake never replaces (deletes) a file or a directory it did not make.
Status checkBakeOutput(const std::filesystem::path& out);

/// OUT.tmp-<this process's pid>, beside `out`.
std::filesystem::path stagingDirectory(const std::filesystem::path& out);

/// Puts the complete bake in `staging` at `out`: one renameat2 exchange
/// when `out` exists (then removes the previous bake), a rename when not.
/// On failure kIoError naming the path and the reason; `out` unchanged.
Status swapIntoPlace(const std::filesystem::path& staging, const std::filesystem::path& out);

}  // namespace svit::baker
