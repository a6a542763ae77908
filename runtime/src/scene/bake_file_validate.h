#pragma once
// The invariants of BakeData that bake files guarantee. Internal to
// svit::scene; not installed.

#include <string>

#include "svit/bake_file.h"
#include "svit/status.h"

namespace svit::bakeio {

/// Checks what every bake file holds: counts within the format's u32 limit;
/// pages non-empty with a relative file name inside the bake directory;
/// triangle pages < page count; without runtime sections, no runtime data
/// (it would not be written); patch element ranges within patch_elements
/// and elements naming existing triangles; clusters in pre-order with
/// agreeing parent/child links and patches in range; emitter kinds known,
/// lit patches ascending and in range, one factor each; proxy indices and
/// face patches in range; 12 SH floats per probe; shadow masks only with
/// runtime sections, each masked light a light or sun emitter masked once,
/// channel < channels <= 256, owner 1..255 unique per channel, one mask
/// page per lightmap page of layers x w x h x 4 values whose owners are 0
/// or a light of their channel; every float finite.
/// `path` only prefixes the message, which names the section (by its tag),
/// the element and the value. Returns kInvalidInput on the first violation.
/// Thread-safe: yes.
Status validateBakeData(const BakeData& data, const std::string& path);

}  // namespace svit::bakeio
