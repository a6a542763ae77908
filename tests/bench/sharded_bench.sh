#!/usr/bin/env bash
# A whole bake against plan + shards + merge on Sponza (with sun and sky;
# skipped with a note when ../shared/scenes is absent) and a generated
# 16 x 16-room house (issue 23 item 4): per-shard wall time and peak memory,
# the total work of the shards against one bake, the balance, and byte
# identity. Rewrites the table of docs/bench/sharded_bench.md (between its
# sharded_bench.sh markers, sharded_report.py).
# usage: tests/bench/sharded_bench.sh BUILD_DIR OUT_DIR [SHARDS]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="$1" out="$2" shards="${3:-4}"
bake="$build/baker/svit-bake"
mkdir -p "$out"
results="$out/sharded_results.jsonl"
: >"$results"
python3 "$root/samples/levels/house/make_house.py" --rooms-x 16 --rooms-z 16 --out "$out/house16" >/dev/null
# 24 passes: a lighting stage of a few minutes on 2 cores.
python3 "$root/tests/bench/sharded_bench.py" "$bake" "$out" house16x16 "$out/house16/level.json" "$shards" \
  --seed 1 --passes 24 --quality 0.3 >>"$results"
sponza="$root/samples/levels/sponza/level.json"
if [[ -f "$root/../shared/scenes/sponza/Sponza.gltf" ]]; then
  python3 "$root/tests/bench/sharded_bench.py" "$bake" "$out" sponza "$sponza" "$shards" \
    --seed 1 --passes 8 --quality 0.3 >>"$results"
else
  echo "sharded_bench.sh: ../shared/scenes/sponza is absent; Sponza skipped" >&2
fi
python3 "$root/tests/bench/sharded_report.py" "$root/docs/bench/sharded_bench.md" "$results"
echo "sharded_bench.sh: wrote docs/bench/sharded_bench.md (its table); figures in $results"
