#!/usr/bin/env bash
# "Leave out what a scene does not need", audited: bakes
# every sample level and the plain Cornell box glTF (a static level), walks
# each headless for a few frames, and tabulates the bake sections written
# (bytes) and left out (why) from report.json, and the runtime's and
# renderer's buffers allocated (bytes) and left out (why) from svit-walk's
# stats JSON (Runtime::resources(), SceneRenderer::resources()).
# Writes OUT/audit.md (with resource_audit_header.md it becomes
# docs/resource-audit.md, this bench's page), OUT/audit.json and per level
# OUT/LEVEL/{bake,stats.json}.
# usage: tests/bench/left_out_audit.sh [BUILD_DIR] [OUT_DIR]
# (SVIT_AUDIT_REUSE=1 keeps bakes already in OUT_DIR.)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${1:-$root/build/release}"
out="${2:-$root/out/left-out-audit}"
mkdir -p "$out"
levels=(
  "cornell-static=$root/samples/levels/cornell/CornellBox-Original.gltf"
  "cornell=$root/samples/levels/cornell/level.json"
  "house=$root/samples/levels/house/level.json"
  "city=$root/samples/levels/city/level.json"
  "sponza=$root/samples/levels/sponza/level.json"
)
for entry in "${levels[@]}"; do
  name="${entry%%=*}"
  level="${entry#*=}"
  mkdir -p "$out/$name"
  # What is written does not depend on quality; a quick bake suffices.
  if [[ "${SVIT_AUDIT_REUSE:-0}" != 1 || ! -f "$out/$name/bake/bake.svit" ]]; then
    "$build/baker/svit-bake" "$level" -o "$out/$name/bake" --quality 0.05 --time 10 --quiet
  fi
  xvfb-run -a -s "-screen 0 640x480x24" "$build/samples/walk/svit-walk" "$level" --bake "$out/$name/bake" \
    --headless --frames 3 --budget-ms 20 --stats "$out/$name/stats.json" >"$out/$name/walk.txt"
done
python3 "$root/tests/bench/left_out_audit.py" "$out" "${levels[@]%%=*}"
# docs/resource-audit.md: its fixed introduction, then the tables just measured.
cat "$root/tests/bench/resource_audit_header.md" "$out/audit.md" >"$root/docs/resource-audit.md"
