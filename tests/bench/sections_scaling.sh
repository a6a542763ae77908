#!/usr/bin/env bash
# The runtime-sections stage against static triangles (issue 22 item 3):
# the synthetic scaling level (tests/bench/scaling.py level: 64 UV spheres
# in a room, one dynamic crate) at 10k..1M triangles, baked by this build's
# svit-bake and by another one (OTHER_SVIT_BAKE, e.g. an older checkout's),
# one after the other per size, with the scaling bench's settings. Prints
# one line per bake and the least-squares growth exponent of each.
# usage: tests/bench/sections_scaling.sh BUILD_DIR OTHER_SVIT_BAKE [SCRATCH]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="$1" other="$2" scratch="${3:-$(mktemp -d)}"
mkdir -p "$scratch"
for segments in 14 24 40 70 126; do
  level="$scratch/level-$segments"
  [[ -f "$level/level.json" ]] || python3 "$root/tests/bench/scaling.py" level --segments "$segments" "$level" >/dev/null
  for pair in "this=$build/baker/svit-bake" "other=$other"; do
    label="${pair%%=*}" bake="${pair#*=}"
    "$bake" "$level/level.json" -o "$scratch/out-$label-$segments" --quality 0.1 --seed 1 --texels-per-m 25 >/dev/null 2>&1
    python3 - "$scratch/out-$label-$segments/report.json" "$label" "$segments" <<'PY'
import json, sys
report = json.load(open(sys.argv[1]))
triangles = 12 + 64 * (int(sys.argv[3]) ** 2 - 2 * int(sys.argv[3]))
print(f"{sys.argv[2]} {triangles} runtime_s {report['stage_seconds']['runtime']:.3f} total_s {report['total_seconds']:.1f}")
PY
  done
done | tee "$scratch/sections.txt"
python3 - "$scratch/sections.txt" <<'PY'
import math, sys
rows = [line.split() for line in open(sys.argv[1])]
for label in ("this", "other"):
    points = [(math.log(float(r[1])), math.log(float(r[3]))) for r in rows if r[0] == label]
    for name, chosen in (("all", points), ("top 3", points[-3:])):
        mx = sum(x for x, _ in chosen) / len(chosen)
        my = sum(y for _, y in chosen) / len(chosen)
        slope = sum((x - mx) * (y - my) for x, y in chosen) / sum((x - mx) ** 2 for x, _ in chosen)
        print(f"{label}: runtime-sections exponent ({name}) {slope:.2f}")
PY
