#!/usr/bin/env bash
# The atlas charted in pieces of at most K triangles an instance
# (AtlasSettings::chart_piece_triangles) against whole instances, side by
# side in one run: bench_atlas --piece-triangles 0 and K alternately on the
# synthetic triangle series of tests/bench/scaling.py (64 spheres, 10k to
# 1M triangles, 25 texels/m) and on Sponza (its default density, when
# ../shared/scenes is there): seconds, charts, page texels, and the growth
# exponent of the seconds against triangles (all points / top three).
# Writes WORK/atlas_pieces.md and puts it in docs/bench/atlas_pieces.md
# between its atlas_pieces.sh markers.
# usage: tests/bench/atlas_pieces.sh BUILD_DIR WORK [K] [THREADS]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${1:?usage: atlas_pieces.sh BUILD_DIR WORK [K] [THREADS]}"
work="${2:?usage: atlas_pieces.sh BUILD_DIR WORK [K] [THREADS]}"
pieces="${3:-1024}" threads="${4:-2}"
bench="$build/tests/bench/bench_atlas"
mkdir -p "$work"
levels=()
for segments in 14 24 40 70 126; do
  level="$work/spheres-$segments/level.json"
  [[ -f "$level" ]] || python3 "$root/tests/bench/scaling.py" level "$work/spheres-$segments" \
    --segments "$segments" >/dev/null
  levels+=("$level")
done
sponza="$root/samples/levels/sponza/level.json"
[[ -f "$root/../shared/scenes/sponza/Sponza.gltf" ]] && levels+=("$sponza") ||
  echo "atlas_pieces.sh: sponza skipped (no ../shared/scenes/sponza)"
: >"$work/runs.jsonl"
for level in "${levels[@]}"; do
  density=(--texels-per-m 25)
  [[ "$level" == "$sponza" ]] && density=()
  for k in 0 "$pieces"; do
    "$bench" "$level" "${density[@]}" --threads "$threads" --piece-triangles "$k" >>"$work/runs.jsonl"
  done
done
python3 - "$work/runs.jsonl" "$work/atlas_pieces.md" "$pieces" "$(uptime)" <<'PY'
import json, math, sys
runs = [json.loads(line) for line in open(sys.argv[1])]
out, pieces, load = sys.argv[2], int(sys.argv[3]), sys.argv[4]
def row(level, k):
    return next(r for r in runs if r["level"] == level and r["piece_triangles"] == k)
def slope(points):
    xs = [math.log(x) for x, _ in points]; ys = [math.log(y) for _, y in points]
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)
levels = list(dict.fromkeys(r["level"] for r in runs))
lines = [f"| level | triangles | whole instances s | pieces of {pieces} s | charts | page texels |",
         "|---|---:|---:|---:|---:|---:|"]
series = {0: [], pieces: []}
for level in levels:
    whole, cut = row(level, 0), row(level, pieces)
    name = "sponza" if "sponza" in level else level.split("/")[-2]
    lines.append(f"| {name} | {whole['triangles']:,} | {whole['atlas_s']:.2f} | {cut['atlas_s']:.2f} | "
                 f"{whole['charts']:,} → {cut['charts']:,} | {whole['page_texels']:,.0f} → {cut['page_texels']:,.0f} |")
    if "sponza" not in level:
        for k in series:
            series[k].append((row(level, k)["triangles"], row(level, k)["atlas_s"]))
fit = {k: (slope(v), slope(v[-3:])) for k, v in series.items()}
lines.append(f"| exponent (spheres), all / top 3 | | {fit[0][0]:.2f} / {fit[0][1]:.2f} | "
             f"{fit[pieces][0]:.2f} / {fit[pieces][1]:.2f} | | |")
lines.append("")
lines.append(f"bench_atlas --threads {runs[0]['threads']}, the two settings alternated per level; load: {load.split('load average:')[-1].strip()}.")
table = "\n".join(lines) + "\n"
open(out, "w").write(table)
print(table)
PY
python3 "$root/tests/bench/doc_section.py" "$root/docs/bench/atlas_pieces.md" atlas_pieces.sh "$work/atlas_pieces.md"
