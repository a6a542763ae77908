#!/usr/bin/env bash
# The lightmap's error against time on the real levels of issue 22 (items 1
# and 2): each level baked for BUDGET seconds with the filter and without
# it (--no-filter), one bake after the other, against an unfiltered
# reference of another seed baked for REF_S seconds: its true error (the
# reference's own noise, its split-half estimate, taken out in quadrature),
# the bake's estimate, and their ratio. Unfiltered, so the reference counts
# what a filter shifts; time-budgeted like the bakes, so its radiosity
# solution is at least as fine as theirs (a --passes reference gets the
# quality plan's coarser solver, whose subdivision error is the
# reference's, not the bake's, and which no split-half sees).
# Writes WORK/estimate_honesty.md (and WORK/LEVEL/{reference,filtered,
# unfiltered}/) and puts the table into docs/bench/estimate_honesty.md
# between its estimate_honesty.sh markers. A reference already in WORK is kept (its
# time is no part of the results; delete WORK/LEVEL/reference to bake it
# again). About 5 minutes a level on the 2-core machine, plus REF_S for a
# reference; levels whose glTF is absent (../shared) are skipped and said
# so. Rows of levels not rerun are kept from WORK/runs.jsonl.
# usage: tests/bench/estimate_honesty.sh BUILD_DIR WORK [BUDGET_S] [REF_S] [LEVELS...]
#   REF_S: the reference's --time (480); LEVELS: sponza city vinc3r house
#   (the default: all four)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
usage="usage: estimate_honesty.sh BUILD_DIR WORK [BUDGET_S] [REF_S] [LEVELS...]"
build="${1:?$usage}"
work="${2:?$usage}"
budget="${3:-120}" reference_s="${4:-480}"
shift $(($# < 4 ? $# : 4))
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

touch "$work/runs.jsonl"
for name in "${levels[@]}"; do
  level="$(level_file "$name")"
  if [[ ! -e "$(needed_gltf "$name")" ]]; then
    echo "estimate_honesty.sh: $name skipped ($(needed_gltf "$name") is absent)"
    continue
  fi
  dir="$work/$name"
  mkdir -p "$dir"
  if [[ ! -f "$dir/reference/report.json" ]]; then
    "$bake" "$level" -o "$dir/reference" --seed 1 --time "$reference_s" --no-filter --quiet
  fi
  # This level's rows are replaced by the runs below.
  python3 -c "import json, sys; rows = [l for l in open(sys.argv[1]) if json.loads(l)['level'] != sys.argv[2]]; open(sys.argv[1], 'w').writelines(rows)" \
    "$work/runs.jsonl" "$name"
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
lines = [f"| level | reference | filter | wall s | passes | true | true, reference noise removed | estimated | estimated / true |",
         "|---|---|---|---:|---:|---:|---:|---:|---:|"]
for run in runs:
    bake = report(f"{run['dir']}/{run['variant']}")
    ref = report(f"{run['dir']}/reference")
    noise = ref["error_vs_time"][-1]["est_rel_error"]  # its split-half
    last = bake["error_vs_time"][-1]
    true = last["ref_rel_error"]
    removed = math.sqrt(max(0.0, true * true - noise * noise))
    budget_s = ref["time_budget_s"]
    made = f"{budget_s:g} s" if budget_s else f"{ref['lightmap']['lighting_passes']} passes"
    made += f", {ref['radiosity']['leaves']:,} leaves"
    k = bake["lightmap"].get("filter_noise_sigmas")
    filt = f"k = {k:g}" if k else "none"
    lines.append(f"| {run['level']} | {made} | {filt} | {run['wall_s']:.0f} | {bake['lightmap']['lighting_passes']} | "
                 f"{100 * true:.2f}% | {100 * removed:.2f}% | {100 * last['est_rel_error']:.2f}% | "
                 f"{last['est_rel_error'] / removed if removed > 0 else float('nan'):.2f} |")
text = "\n".join(lines) + "\n\n" + \
    (f"svit-bake --seed 7 --time {budget} --reference (seed 1, unfiltered, its --time or --passes "
     f"and its radiosity leaves in the table), the two variants one after the other per level; "
     f"the reference's noise is its own split-half estimate. Load after the last run: "
     f"{load.split('load average:')[-1].strip()}.\n")
open(out, "w").write(text)
print(text)
PY
python3 "$root/tests/bench/doc_section.py" "$root/docs/bench/estimate_honesty.md" estimate_honesty.sh \
  "$work/estimate_honesty.md"
