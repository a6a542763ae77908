#!/usr/bin/env bash
# tests/bench/cycles_compare.sh [OUT_DIR]   (default build/bench/cycles)
#
# svit against Blender Cycles on cornell_box_original: both bake the same
# lightmap UVs (Blender's Lightmap Pack, TEXCOORD_1) at the same page size; a
# long Cycles bake with another seed is the reference; prints the time each
# needs to reach 5%, 2% and 1% RMS relative error and writes results.json,
# results.md, error_vs_time.png and previews/ under OUT_DIR. About 18 minutes
# on the 2-core development machine when it is otherwise idle. See tests/bench/README.md.
#
# Knobs (environment): SVIT_CYCLES_SIZE (page texels per side, 256),
# SVIT_CYCLES_SAMPLES (Cycles series, 1,2,4,...,1024),
# SVIT_CYCLES_REFERENCE_SAMPLES (6144), SVIT_CYCLES_SVIT_BUDGETS (svit --time
# values, seconds), SVIT_CYCLES_REUSE=1 (keep the Cycles reference already in
# OUT_DIR when scene and settings match; its time is no part of the results,
# so a rerun of the timed bakes takes 7 minutes instead of 18), SVIT_BAKE (a
# built svit-bake to use instead of building build/release).
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
out="${1:-$root/build/bench/cycles}"
mkdir -p "$out"
out="$(cd "$out" && pwd)"
size="${SVIT_CYCLES_SIZE:-256}"
samples="${SVIT_CYCLES_SAMPLES:-1,2,4,8,16,32,64,128,256,512,1024}"
reference_samples="${SVIT_CYCLES_REFERENCE_SAMPLES:-6144}"
budgets="${SVIT_CYCLES_SVIT_BUDGETS:-0.25 0.5 0.75 1 1.5 2 3 4 6 8 12 16 24 32 48}"
scene_in="$root/samples/levels/cornell/CornellBox-Original.gltf"
script="$root/tests/bench/cycles_lightmap.py"
python=/usr/bin/python3  # Debian's, with python3-numpy and python3-matplotlib
start_all=$(date +%s)

cd "$root"
scripts/setup --bench
mkdir -p "$out/scene" "$out/logs" "$out/svit"
load() { echo "$1 $(cut -d' ' -f1-3 /proc/loadavg)" >>"$out/load.txt"; }  # 1/5/15-minute load averages
{ echo "cpus $(nproc)"; grep -m1 'model name' /proc/cpuinfo | sed 's/.*: /cpu /'; } >"$out/load.txt"
load start

blender_run() {  # blender_run LOG ARGS...: the Blender script, its chatter into LOG
  local log="$1"
  shift
  if ! blender -b --factory-startup -P "$script" -- "$@" >"$log" 2>&1; then
    tail -n 30 "$log" >&2
    echo "cycles_compare: Blender failed; log in $log" >&2
    exit 1
  fi
  grep -E '^(prepare|bake|texels|to-npy):' "$log" || true
}

# 1. The shared scene: lightmap UVs from Blender's Lightmap Pack.
scene="$out/scene/cornell_lightmap.gltf"
echo "== lightmap UVs (Blender Lightmap Pack, ${size}x${size}, margin 1.5 texels per side)"
blender_run "$out/logs/prepare.log" prepare "$scene_in" "$scene" --size "$size" --margin-texels 1.5
scene_hash="$(cat "$scene" "$out/scene/cornell_lightmap.bin" | sha256sum | cut -c1-16)"
blender_run "$out/logs/texels.log" texels "$scene" "$out/scene/texels.npz" --size "$size"

# 2. Cycles: the series (seed 1) and the reference (seed 2).
cycles_stage() {  # cycles_stage DIR SAMPLES SEED [REUSABLE]
  local dir="$1" list="$2" seed="$3" reusable="${4:-}"
  local stamp="scene $scene_hash size $size samples $list seed $seed"
  if [[ -n "$reusable" && "${SVIT_CYCLES_REUSE:-0}" == 1 && -f "$dir/stamp" && "$(cat "$dir/stamp")" == "$stamp" ]]; then
    echo "   reusing $dir ($stamp)"
    return
  fi
  rm -rf "$dir"
  mkdir -p "$dir"
  blender_run "$out/logs/$(basename "$dir").log" bake "$scene" "$dir" --size "$size" --samples "$list" --seed "$seed"
  echo "$stamp" >"$dir/stamp"
}
echo "== Cycles series: $samples samples (CPU, all threads)"
cycles_stage "$out/cycles" "$samples" 1
echo "== Cycles reference: $reference_samples samples, other seed"
cycles_stage "$out/reference" "$reference_samples" 2 reusable

load after-cycles
# 3. svit: find the texel density that gives a size x size page, then bake at
# increasing time budgets (wall time of the whole process is what counts).
if [[ -n "${SVIT_BAKE:-}" ]]; then
  bake="$SVIT_BAKE"
else
  if [[ ! -f build/release/build.ninja ]]; then
    cmake -S . -B build/release -G Ninja -DCMAKE_BUILD_TYPE=Release
  fi
  cmake --build build/release -j2 --target svit-bake svit-info
  bake="$root/build/release/baker/svit-bake"
fi
page_width() { "$python" -c 'import json,sys; l=json.load(open(sys.argv[1]))["lightmap"]; print(l["page_width"], l["page_height"], l["atlas"])' "$1/report.json"; }
echo "== svit: texel density for a ${size}x${size} page"
density=100
found=""
for attempt in 1 2 3 4 5 6 7 8; do
  rm -rf "$out/svit/probe"
  "$bake" "$scene" -o "$out/svit/probe" --time 1 --texels-per-m "$density" --quiet
  read -r width height atlas < <(page_width "$out/svit/probe")
  echo "   --texels-per-m $density -> page ${width}x${height} ($atlas)"
  if [[ "$atlas" != TEXCOORD_1 ]]; then
    echo "cycles_compare: svit did not use the TEXCOORD_1 lightmap UVs" >&2
    exit 1
  fi
  if [[ "$width" == "$size" && "$height" == "$size" ]]; then found=1; break; fi
  density="$("$python" -c "import sys; d,w,s,a=float(sys.argv[1]),int(sys.argv[2]),int(sys.argv[3]),int(sys.argv[4]); n=d*s/w; print(repr(n if abs(n-d)>1e-9*d else d*(1+(0.5 if w<s else -0.5)/s)))" "$density" "$width" "$size" "$attempt")"
done
if [[ -z "$found" ]]; then
  echo "cycles_compare: no --texels-per-m gives a ${size}x${size} svit page" >&2
  exit 1
fi
rm -rf "$out/svit/probe"
echo "== svit bakes (--texels-per-m $density, all threads), budgets: $budgets"
printf '# budget_s\twall_s\tdir\n' >"$out/svit/runs.tsv"
for budget in $budgets; do
  dir="$out/svit/t$budget"
  rm -rf "$dir"
  t0=$(date +%s.%N)
  "$bake" "$scene" -o "$dir" --seed 1 --time "$budget" --texels-per-m "$density" --quiet
  t1=$(date +%s.%N)
  wall="$("$python" -c "import sys; print('%.4f' % (float(sys.argv[2]) - float(sys.argv[1])))" "$t0" "$t1")"
  printf '%s\t%s\t%s\n' "$budget" "$wall" "$dir" >>"$out/svit/runs.tsv"
  echo "   --time $budget: $wall s"
done

load after-svit
# 4. EXR -> .npy (Blender reads both bakers' EXRs), then the comparison.
echo "== comparing"
rm -rf "$out/npy"
inputs=("reference=$out/reference/$(printf 'cycles-s%05d.exr' "$reference_samples")")
for exr in "$out"/cycles/cycles-s*.exr; do inputs+=("$exr"); done
for budget in $budgets; do inputs+=("svit-t$("$python" -c "import sys; print('%g' % float(sys.argv[1]))" "$budget")=$out/svit/t$budget/lightmap-0.exr"); done
blender_run "$out/logs/to-npy.log" to-npy "$out/npy" "${inputs[@]}" >/dev/null
"$python" "$root/tests/bench/cycles_compare.py" "$out"
echo "wrote $out/results.md, $out/results.json, $out/error_vs_time.png, $out/previews/ ($(($(date +%s) - start_all)) s in all)"
