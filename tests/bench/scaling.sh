#!/usr/bin/env bash
# Scaling benchmark (issue 8 item 3): configures and builds svit-bake,
# svit-info and bench_scaling_runtime, then runs tests/bench/scaling.py:
# baker time per stage and peak RSS against triangles (synthetic 10k..1M and
# the real levels), emitters (1..10,000 quads) and texels; runtime frame time
# against static triangles (full geometry and LOD proxies), dynamic objects
# (1..64) and emitters, under xvfb-run. Writes OUT_DIR/results.{json,md} and
# OUT_DIR/scaling-{baker,runtime}.png. About an hour on the 2-core machine.
# usage: tests/bench/scaling.sh [OUT_DIR]      (default build/bench/scaling)
# env:   SVIT_BENCH_BUILD  build directory (default build/bench)
#        SVIT_SCALING_SERIES  comma list (default: all; see scaling.py run --help)
#        SVIT_SCALING_MAX_SEGMENTS  largest sphere tessellation (126 = 1M triangles)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${SVIT_BENCH_BUILD:-$root/build/bench}"
[[ "$build" = /* ]] || build="$root/$build"
out="${1:-$build/scaling}"
series="${SVIT_SCALING_SERIES:-triangles,real,emitters,lights,texels,rt_triangles,rt_objects,rt_emitters,rt_lights}"
jobs="${SVIT_BUILD_JOBS:-1}"

if [[ ! -f "$build/CMakeCache.txt" ]]; then
  cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSVIT_BUILD_BENCH=ON
fi
cmake -S "$root" -B "$build" -DSVIT_BUILD_BENCH=ON -DSVIT_BUILD_RUNTIME_GL=ON >/dev/null
cmake --build "$build" -j "$jobs" --target svit-bake svit-info bench_scaling_runtime

mkdir -p "$out"
{ date; uptime; } > "$out/load.txt"
/usr/bin/python3 "$root/tests/bench/scaling.py" run --build "$build" --out "$out" --series "$series" \
  ${SVIT_SCALING_MAX_SEGMENTS:+--max-segments "$SVIT_SCALING_MAX_SEGMENTS"}
{ date; uptime; } >> "$out/load.txt"
