#!/usr/bin/env bash
# Two builds of svit, the same work: each sample level baked with a fixed seed
# and pass count, walked headless in the runtime and the baked view (linear
# EXR frames, with the level's dynamic objects moving along their paths and
# a probe after the last frame), and probed with svit-probe. Every bake file,
# lightmap page, frame and probe value must be the same bytes in both; the
# report's timings (and nothing else in it) may differ. A refactor that
# claims to change nothing is checked with it (issue 44: the tree's layout).
#
# usage: byte_identity.sh BUILD_A BUILD_B [LEVEL ...]
#   BUILD_A, BUILD_B  CMake build directories holding baker/svit-bake,
#                     baker/svit-probe and samples/walk/svit-walk
#   LEVEL             sample level names (default: cornell house; sponza and
#                     city read ../shared/scenes and are skipped when absent)
# Needs a display for svit-walk: run under `xvfb-run -a` without one.
# Prints one line per compared file set and "N identical, M different";
# exits 1 on any difference or failed run.
set -euo pipefail
src="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build_a="$(cd "$1" && pwd)" build_b="$(cd "$2" && pwd)"
shift 2
levels=("$@")
((${#levels[@]})) || levels=(cornell house)
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

# Points on the levels' floors, walls and ceilings; one off every surface
# (its value is nan, which must match too).
cat >"$work/points.txt" <<'POINTS'
0 0 0 0 1 0
0.4 0 0.3 0 1 0
-0.99 1 0 1 0 0
0.99 1 0 -1 0 0
0 1.98 0 0 -1 0
0 1 -1.04 0 0 1
2 0.01 2 0 1 0
50 50 50 0 1 0
POINTS

# run BUILD TAG LEVEL: bake, walk twice, probe, into $work/TAG/LEVEL.
run() {
  local build="$1" tag="$2" name="$3"
  local level="$src/samples/levels/$name/level.json" out="$work/$tag/$name"
  mkdir -p "$out"
  "$build/baker/svit-bake" "$level" -o "$out/bake" --seed 7 --passes 4 --quiet
  for view in runtime baked; do
    "$build/samples/walk/svit-walk" "$level" --bake "$out/bake" --headless --frames 8 \
      --width 320 --height 180 --view "$view" --frames-format exr --frames-out "$out/$view" \
      --probe "$work/points.txt" --probe-out "$out/$view-probe.txt" >/dev/null
  done
  "$build/baker/svit-probe" "$out/bake" "$work/points.txt" >"$out/svit-probe.txt"
  # The report without its timings (seconds, rates and the times table).
  python3 - "$out/bake/report.json" >"$out/report-figures.json" <<'PY'
import json, re, sys
def strip(v):
    if isinstance(v, dict):
        return {k: strip(x) for k, x in v.items() if not re.search(r"(_s|_ms|seconds|time|timing|rate)", k)}
    if isinstance(v, list):
        return [strip(x) for x in v]
    return v
print(json.dumps(strip(json.load(open(sys.argv[1]))), indent=1, sort_keys=True))
PY
  rm "$out/bake/report.json"
}

same=0 different=0
for name in "${levels[@]}"; do
  level="$src/samples/levels/$name/level.json"
  gltf="$(python3 -c 'import json, os, sys; print(os.path.normpath(os.path.join(os.path.dirname(sys.argv[1]), json.load(open(sys.argv[1]))["gltf"])))' "$level")"
  if [[ ! -f "$gltf" ]]; then
    echo "skip $name: $gltf is missing"
    continue
  fi
  run "$build_a" a "$name"
  run "$build_b" b "$name"
  files_a=$(cd "$work/a/$name" && find . -type f | sort)
  files_b=$(cd "$work/b/$name" && find . -type f | sort)
  while IFS= read -r file; do
    if cmp -s "$work/a/$name/$file" "$work/b/$name/$file"; then
      same=$((same + 1))
    else
      different=$((different + 1))
      echo "DIFFERENT $name/$file"
    fi
  done <<<"$files_a"
  missing=$(diff <(echo "$files_a") <(echo "$files_b") || true)
  if [[ -n $missing ]]; then
    different=$((different + 1))
    echo "DIFFERENT $name: file sets differ: $missing"
  fi
  echo "$name: $(wc -l <<<"$files_a") files compared"
done
echo "byte identity: $same identical, $different different"
((different == 0))
