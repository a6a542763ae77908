#!/usr/bin/env bash
# What shadow masks cost, side by side in one run: each level baked with
# and without them (--no-shadow-masks), then svit-walk headless over its
# walk in the runtime view for FRAMES frames, alternating the two bakes:
# bake seconds, mask bytes and channels, the renderer's shadow map and mask
# memory, and the mean shading time per frame (caster maps plus the
# masked lights' per-pixel shading against the lightmap alone). Writes
# WORK/shadow_mask_cost.json, prints a Markdown table and puts it in
# docs/bench/shadow_mask_cost.md between its shadow_mask_cost.sh markers. Sponza is
# skipped (and says so) without ../shared/scenes.
# Levels: the Cornell box (its lamp masked as area lights), the house, Sponza.
# usage: tests/bench/shadow_mask_cost.sh BUILD_DIR WORK [FRAMES] [BAKE_PASSES]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${1:?usage: shadow_mask_cost.sh BUILD_DIR WORK [FRAMES] [BAKE_PASSES]}"
work="${2:?usage: shadow_mask_cost.sh BUILD_DIR WORK [FRAMES] [BAKE_PASSES]}"
frames="${3:-30}"
passes="${4:-2}"
walk="$build/samples/walk/svit-walk" bake="$build/baker/svit-bake"
xvfb=()
[[ -z "${DISPLAY:-}" ]] && xvfb=(xvfb-run -a -s "-screen 0 1280x720x24")
mkdir -p "$work"
# SVIT_MASK_COST_LEVELS: the levels to run (default cornell house sponza).
levels=()
for name in ${SVIT_MASK_COST_LEVELS:-cornell house sponza}; do
  if [[ "$name" == sponza && ! -f "$root/../shared/scenes/sponza/Sponza.gltf" ]]; then
    echo "shadow_mask_cost.sh: sponza skipped (no ../shared/scenes/sponza)"
  else
    levels+=("$name")
  fi
done
for name in "${levels[@]}"; do
  level="$root/samples/levels/$name/level.json"
  [[ -f "$work/$name-masks/bake.svit" ]] || "$bake" "$level" -o "$work/$name-masks" --passes "$passes" --quiet
  [[ -f "$work/$name-plain/bake.svit" ]] ||
    "$bake" "$level" -o "$work/$name-plain" --passes "$passes" --no-shadow-masks --quiet
  for variant in masks plain masks plain; do
    "${xvfb[@]}" "$walk" "$level" --bake "$work/$name-$variant" --headless --frames "$frames" \
      --stats "$work/$name-$variant-stats.json" >/dev/null
    cp "$work/$name-$variant-stats.json" "$work/$name-$variant-stats-$(date +%s%N).json"
  done
done
python3 - "$work" "$frames" "${levels[@]}" <<'PY'
import glob, json, sys
work, frames, levels = sys.argv[1], int(sys.argv[2]), sys.argv[3:]
rows = []
for name in levels:
    row = {"level": name}
    for variant in ("masks", "plain"):
        runs = [json.load(open(p)) for p in sorted(glob.glob(f"{work}/{name}-{variant}-stats-*.json"))[-2:]]
        report = json.load(open(f"{work}/{name}-{variant}/report.json"))
        renderer = {r["name"]: r for r in runs[-1]["resources"]["renderer"]}
        row[variant] = {
            "shading_ms": sum(r["summary"]["mean"]["shading_ms"] for r in runs) / len(runs),
            "frame_ms": sum(r["summary"]["mean"]["frame_ms"] for r in runs) / len(runs),
            "bake_s": sum(report["stage_seconds"].values()),
            "mask_bytes": report["shadow_masks"].get("bytes", 0),
            "masked_lights": len(report["shadow_masks"]["lights"]),
            "channels": report["shadow_masks"].get("channels", 0),
            "mask_seconds": report["shadow_masks"].get("seconds", 0),
            "shadow_map_bytes": renderer["light shadow maps"]["gpu_bytes"],
            "mask_texture_bytes": renderer["shadow mask textures"]["gpu_bytes"],
            "renderer": runs[-1]["renderer"],
        }
    rows.append(row)
json.dump(rows, open(f"{work}/shadow_mask_cost.json", "w"), indent=1)
mb = lambda b: f"{b / 2**20:.1f} MiB"
lines = ["| level | masked lights (channels) | mask bytes, tracing | bake with / without | shadow maps with / without | mean shading a frame with / without |",
         "|---|---:|---:|---:|---:|---:|"]
for r in rows:
    m, p = r["masks"], r["plain"]
    lines.append(f"| {r['level']} | {m['masked_lights']} ({m['channels']}) | {mb(m['mask_bytes'])}, {m['mask_seconds']:.1f} s | "
                 f"{m['bake_s']:.1f} s / {p['bake_s']:.1f} s | {mb(m['shadow_map_bytes'])} / {mb(p['shadow_map_bytes'])} | "
                 f"{m['shading_ms']:.0f} ms / {p['shading_ms']:.0f} ms ({m['shading_ms'] / p['shading_ms']:.2f}×) |")
table = "\n".join(lines) + f"\n\n{frames} frames of each level's walk per run, two runs of each bake alternated, on {rows[0]['masks']['renderer']}.\n"
print(table)
open(f"{work}/shadow_mask_cost.md", "w").write(table)
PY
python3 "$root/tests/bench/doc_section.py" "$root/docs/bench/shadow_mask_cost.md" shadow_mask_cost.sh "$work/shadow_mask_cost.md"
