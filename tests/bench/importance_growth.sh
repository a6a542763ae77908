#!/usr/bin/env bash
# Importance caching's cost growth from 4 to 64 rooms (issue 7): the caching
# runtime alone (no refresh-all reference) on the 2 x 2 and 8 x 8 houses of
# importance_bench.sh (run that first: it generates and bakes them), the two
# sizes alternating REPEATS times in this one script so that both see the
# same machine; per house the fastest and the median run, per stage, and
# the ratio of the fastest runs. Frame times on a shared machine vary by up
# to a third from run to run; the fastest run is the least disturbed.
# usage: tests/bench/importance_growth.sh [BUILD_DIR] [OUT_DIR] [REPEATS] [BUDGET_SAMPLES]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${1:-$root/build/bench}"
out="${2:-$root/out/bench-importance}"
repeats="${3:-3}"
budget="${4:-48}"
for n in 2 8; do
  [[ -f "$out/house-${n}x${n}/bake/bake.svit" ]] || { echo "no $out/house-${n}x${n}/bake: run importance_bench.sh first" >&2; exit 1; }
done
for ((r = 1; r <= repeats; ++r)); do
  for n in 2 8; do
    xvfb-run -a -s "-screen 0 640x480x24" "$build/tests/bench/bench_importance" "$out/house-${n}x${n}/level.json" \
      "$out/house-${n}x${n}/bake" --budget "$budget" --stop-frames 2 --moving walk --no-reference \
      --json "$out/growth-${n}x${n}-run${r}.json" > /dev/null
  done
done
python3 - "$out" "$repeats" <<'EOF'
import json, statistics, sys
out, repeats = sys.argv[1], int(sys.argv[2])
best = {}
for n in (2, 8):
    runs = [json.load(open(f"{out}/growth-{n}x{n}-run{r}.json")) for r in range(1, repeats + 1)]
    runs.sort(key=lambda d: d["caching_ms"])
    fast, median = runs[0], statistics.median(d["caching_ms"] for d in runs)
    best[n] = fast["caching_ms"]
    s = fast["caching_stages"]
    print(f"house {n}x{n}: fastest {fast['caching_ms']:.1f} ms/frame (median {median:.1f}, {fast['caching_samples']:.0f} samples), "
          f"maps {s['maps_ms']:.1f} ms ({s['map_triangles']:.0f} triangles), reduction {s['reduction_ms']:.1f}, "
          f"bounce {s['bounce_ms']:.1f}, upload {s['upload_ms']:.1f}, view {s['view_ms']:.1f}")
print(f"growth 4 -> 64 rooms (fastest runs): {best[8] / best[2]:.2f}x")
EOF
