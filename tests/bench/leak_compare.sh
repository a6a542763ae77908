#!/usr/bin/env bash
# Leaks before and after (issue 22 item 5): runs baker_leak_tests of BUILD_DIR
# (which bakes every generated leak level and leaves it, its bake and its
# probe points in a scratch directory), bakes the same levels with the same
# options by OTHER_SVIT_BAKE (an older build's svit-bake), probes both bakes
# with BUILD_DIR's svit-probe and prints a markdown table: per level the
# brightest dark probe and the brightest probe 2 cm from a wall, as shares
# of the lit probes' mean, for the other build and this one.
# usage: tests/bench/leak_compare.sh BUILD_DIR OTHER_SVIT_BAKE [SCRATCH]
set -euo pipefail
build="$(cd "$1" && pwd)" other="$2" scratch="${3:-$(mktemp -d)}"
probe="$build/baker/svit-probe"
mkdir -p "$scratch"
TEST_TMPDIR="$scratch/" "$build/tests/baker_leak_tests" >"$scratch/leak_tests.log" 2>&1 || {
  echo "leak_compare.sh: baker_leak_tests failed (log: $scratch/leak_tests.log)" >&2
  exit 1
}
echo "| level | dark, other build | dark, this build | 2 cm from a wall, other | this |"
echo "|---|---:|---:|---:|---:|"
for dir in "$scratch"/svit_leak_*/; do
  dir="${dir%/}"
  # The level as baked: OUT/level.json when the test gave a sun or a sky.
  level="$dir/out/level.json"
  [[ -f "$level" ]] || level="$dir/level.gltf"
  # The leak test's options (leak_test.cpp bakeAndProbe).
  "$other" "$level" -o "$dir/other" --seed 7 --quality 0.5 --passes 4 --texels-per-m 10 --quiet
  python3 - "$probe" "$dir" <<'PY'
import os, subprocess, sys
probe, d = sys.argv[1], sys.argv[2]
def lux(bake, points):
    if os.path.getsize(f"{d}/{points}.txt") == 0:
        return []
    out = subprocess.run([probe, f"{d}/{bake}", f"{d}/{points}.txt"], check=True,
                         capture_output=True, text=True).stdout.split("\n")
    return [0.2126 * float(r) + 0.7152 * float(g) + 0.0722 * float(b)
            for r, g, b in (line.split() for line in out if line.strip())]
def shares(bake):
    lit = lux(bake, "lit")
    mean = sum(lit) / len(lit)
    return [max(lux(bake, kind), default=0) / mean for kind in ("dark", "edge")]
other, this = shares("other"), shares("out")
name = os.path.basename(d)[len("svit_leak_"):].replace("_", " ")
print(f"| {name} | {other[0]:.3g} | {this[0]:.3g} | {other[1]:.3g} | {this[1]:.3g} |")
PY
done
