#!/usr/bin/env bash
# Importance caching benchmark (issue 7): generates the house at 2 x 2 and
# 8 x 8 rooms (samples/levels/house/make_house.py), bakes each, and runs
# bench_importance on both under Xvfb, writing OUT/house-RxR.json: a walk
# through four rooms whose tables slide (the same dynamic activity in both
# houses), refresh-all against importance caching at BUDGET_SAMPLES and at
# 40, 36, 32, 24, 16 and 12 samples per frame (cost against error, so the
# houses compare at equal accuracy: importance_growth.sh), then the door
# and lamp cases.
# usage: tests/bench/importance_bench.sh [BUILD_DIR] [OUT_DIR] [BUDGET_SAMPLES]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${1:-$root/build/bench}"
out="${2:-$root/out/bench-importance}"
budget="${3:-48}"
mkdir -p "$out"
for n in 2 8; do
  dir="$out/house-${n}x${n}"
  mkdir -p "$dir"
  python3 "$root/samples/levels/house/make_house.py" --rooms-x "$n" --rooms-z "$n" --out "$dir"
  if [[ ! -f "$dir/bake/bake.svit" ]]; then
    "$build/baker/svit-bake" "$dir/level.json" -o "$dir/bake" --quality 0.2 --quiet
  fi
  xvfb-run -a -s "-screen 0 640x480x24" "$build/tests/bench/bench_importance" "$dir/level.json" "$dir/bake" \
    --budget "$budget" --stop-frames 2 --moving walk --also-budgets 40,36,32,24,16,12 --json "$out/house-${n}x${n}.json"
done
