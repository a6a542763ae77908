#!/usr/bin/env bash
# The lightmap's error against time on the real levels of issue 22 (items 1
# and 2): each level baked for BUDGET seconds with the filter and without
# it (--no-filter), one bake after the other, against an unfiltered
# reference of another seed: its true error (the reference's own noise, its
# split-half estimate, taken out in quadrature), the bake's estimate, and
# their ratio. Unfiltered, so the reference counts what a filter shifts.
# Writes WORK/estimate_honesty.md (and WORK/LEVEL/{reference,filtered,
# unfiltered}/) and puts the table into docs/performance.md between its
# estimate_honesty.sh markers. A reference already in WORK is kept (its
# time is no part of the results). About 10 minutes a level on the 2-core
# machine, more for a reference; levels whose glTF is absent (../shared)
# are skipped and said so.
# usage: tests/bench/estimate_honesty.sh BUILD_DIR WORK [BUDGET_S] [LEVELS...]
#   LEVELS: sponza city vinc3r house (the default: all four)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${1:?usage: estimate_honesty.sh BUILD_DIR WORK [BUDGET_S] [LEVELS...]}"
work="${2:?usage: estimate_honesty.sh BUILD_DIR WORK [BUDGET_S] [LEVELS...]}"
budget="${3:-120}"
shift $(($# < 3 ? $# : 3))
levels=("$@")
((${#levels[@]})) || levels=(sponza city vinc3r house)
bake="$build/baker/svit-bake"
shared="$root/../shared/scenes"
mkdir -p "$work"

# level name -> level file, the glTF it needs, reference passes
level_file() {
  case "$1" in
    sponza) echo "$root/samples/levels/sponza/level.json" ;;
    city) echo "$root/samples/levels/city/level.json" ;;
    vinc3r) echo "$shared/cornell_box_vinc3r/cornellBox-2.80-Eevee-gltf.gltf" ;;
    house) echo "$root/samples/levels/house/level.json" ;;
    *) echo "estimate_honesty.sh: unknown level $1" >&2 && exit 2 ;;
  esac
}
needed_gltf() {
  case "$1" in
    sponza) echo "$shared/sponza/Sponza.gltf" ;;
    city) echo "$shared/virtual_city/VC.gltf" ;;
    vinc3r) echo "$shared/cornell_box_vinc3r/cornellBox-2.80-Eevee-gltf.gltf" ;;
    house) echo "$root/samples/levels/house/house.gltf" ;;
  esac
}
reference_passes() { [[ "$1" == city ]] && echo 256 || echo 128; }

: >"$work/runs.jsonl"
for name in "${levels[@]}"; do
  level="$(level_file "$name")"
  if [[ ! -e "$(needed_gltf "$name")" ]]; then
    echo "estimate_honesty.sh: $name skipped ($(needed_gltf "$name") is absent)"
    continue
  fi
  dir="$work/$name"
  mkdir -p "$dir"
  if [[ ! -f "$dir/reference/report.json" ]]; then
    "$bake" "$level" -o "$dir/reference" --seed 1 --passes "$(reference_passes "$name")" \
      --no-filter --quiet
  fi
  for variant in filtered unfiltered; do
    flags=()
    [[ "$variant" == unfiltered ]] && flags=(--no-filter)
    start=$(date +%s.%N)
    "$bake" "$level" -o "$dir/$variant" --seed 7 --time "$budget" --reference "$dir/reference" \
      "${flags[@]}" --quiet
    wall=$(python3 -c "print($(date +%s.%N) - $start)")
    echo "{\"level\": \"$name\", \"variant\": \"$variant\", \"wall_s\": $wall, \"dir\": \"$dir\"}" >>"$work/runs.jsonl"
  done
done

python3 - "$work/runs.jsonl" "$work/estimate_honesty.md" "$budget" "$(uptime)" <<'PY'
import json, math, sys
runs = [json.loads(line) for line in open(sys.argv[1])]
out, budget, load = sys.argv[2], sys.argv[3], sys.argv[4]
def report(path):
    return json.load(open(path + "/report.json"))
lines = [f"| level | filter | wall s | passes | true | true, reference noise removed | estimated | estimated / true |",
         "|---|---|---:|---:|---:|---:|---:|---:|"]
for run in runs:
    bake = report(f"{run['dir']}/{run['variant']}")
    ref = report(f"{run['dir']}/reference")
    noise = ref["error_vs_time"][-1]["est_rel_error"]  # its split-half
    last = bake["error_vs_time"][-1]
    true = last["ref_rel_error"]
    removed = math.sqrt(max(0.0, true * true - noise * noise))
    k = bake["lightmap"].get("filter_noise_sigmas")
    filt = f"k = {k:g}" if k else "none"
    lines.append(f"| {run['level']} | {filt} | {run['wall_s']:.0f} | {bake['lightmap']['lighting_passes']} | "
                 f"{100 * true:.2f}% | {100 * removed:.2f}% | {100 * last['est_rel_error']:.2f}% | "
                 f"{last['est_rel_error'] / removed if removed > 0 else float('nan'):.2f} |")
text = "\n".join(lines) + "\n\n" + \
    (f"svit-bake --seed 7 --time {budget} --reference (seed 1, unfiltered, 128 passes, city 256), "
     f"the two variants one after the other per level; the reference's noise is its own "
     f"split-half estimate. Load after the run: {load.split('load average:')[-1].strip()}.\n")
open(out, "w").write(text)
print(text)
PY
python3 "$root/tests/bench/doc_section.py" "$root/docs/performance.md" estimate_honesty.sh \
  "$work/estimate_honesty.md"
