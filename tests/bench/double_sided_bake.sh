#!/usr/bin/env bash
# The double-sided Cornell box of issue 46 (tests/reference/levels), baked by
# two builds side by side, alternated, on the same machine: for each budget
# BEFORE, AFTER, BEFORE, AFTER with `--time T --texels-per-m 64`, seeds 7
# then 8 (one seed twice is the same bake when the pass count repeats),
# each bake's RMS irradiance error at the probe points against the Mitsuba 3
# reference (tests/reference/check_probes.py), its lighting passes, covered
# and back texels, and the wall seconds it used. Writes WORK/double_sided.md
# and puts the table into docs/bench/double_sided.md between its
# double_sided_bake.sh markers. About 4 x (sum of budgets) seconds.
# usage: tests/bench/double_sided_bake.sh BEFORE_BUILD AFTER_BUILD WORK [BUDGETS...]
#   BUILD: a build folder holding baker/svit-bake and baker/svit-probe;
#   BUDGETS: seconds (default: 10 30)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
usage="usage: double_sided_bake.sh BEFORE_BUILD AFTER_BUILD WORK [BUDGETS...]"
before="${1:?$usage}" after="${2:?$usage}" work="${3:?$usage}"
shift 3
budgets=("$@")
((${#budgets[@]})) || budgets=(10 30)
results="$root/tests/reference/results/cornell_double_sided.json"
mkdir -p "$work"
runs="$work/runs.jsonl"
: >"$runs"
for budget in "${budgets[@]}"; do
  for round in 1 2; do
    for side in before after; do
      build="$before"
      [[ $side == after ]] && build="$after"
      dir="$work/$side-$budget-$round"
      rm -rf "$dir"
      python3 "$root/tests/reference/check_probes.py" "$build" "$results" "$dir" \
        --time "$budget" --texels-per-m 64 --seed $((6 + round)) --json "$dir/check.json" \
        >"$dir.log" || true
      python3 - "$dir" "$side" "$budget" "$build" >>"$runs" <<'PY'
import json, sys
d, side, budget, build = sys.argv[1:]
check = json.load(open(d + "/check.json"))
lm = json.load(open(d + "/bake/report.json"))["lightmap"]
print(json.dumps({"side": side, "build": build, "budget": float(budget),
                  "rms": check["rms_error"], "estimate": check["estimate"],
                  "passes": lm["lighting_passes"], "covered": lm["covered_texels"],
                  "back": lm.get("back_texels", 0), "seconds": check["seconds"]}))
PY
    done
  done
done
python3 - "$runs" "$work/double_sided.md" <<'PY'
import json, sys
runs = [json.loads(l) for l in open(sys.argv[1])]
out = open(sys.argv[2], "w")
out.write("`--time T --texels-per-m 64 --seed S`, alternated, S = 7 then 8.\n\n")
out.write("| budget | build | RMS error vs Mitsuba | estimate | lighting passes | covered texels "
          "| back texels | seconds used |\n|---:|---|---:|---:|---:|---:|---:|---:|\n")
for budget in sorted({r["budget"] for r in runs}):
    for side in ("before", "after"):
        rs = [r for r in runs if r["budget"] == budget and r["side"] == side]
        cell = lambda key, fmt: ", ".join(fmt(r[key]) for r in rs)
        out.write(f"| {budget:g} s | {side} | {cell('rms', lambda v: f'{100 * v:.2f} %')} "
                  f"| {cell('estimate', lambda v: f'{100 * v:.2f} %')} | {cell('passes', str)} "
                  f"| {rs[0]['covered']:,} | {rs[0]['back']:,} | {cell('seconds', lambda v: f'{v:.1f}')} |\n")
out.close()
print(open(sys.argv[2]).read())
PY
python3 "$root/tests/bench/doc_section.py" "$root/docs/bench/double_sided.md" double_sided_bake.sh \
  "$work/double_sided.md"
