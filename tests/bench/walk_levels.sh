#!/usr/bin/env bash
# Time to the first frame and mean frame time of every sample level, as a
# user gets them: svit-bake, then svit-walk headless at its defaults (the
# deterministic sample budget, 640 x 360), once for 1 frame (process start
# to exit: loading, the runtime and renderer made, the first update and
# frame) and once for FRAMES frames (the mean per-frame time from --stats).
# Writes WORK/walk_levels.json and WORK/walk_levels.md, prints a Markdown
# table and puts it in docs/bench/walk_levels.md (between its
# walk_levels.sh markers, tests/bench/doc_section.py). Levels whose
# scenes (../shared/scenes) are absent are skipped and say so.
# usage: tests/bench/walk_levels.sh BUILD_DIR WORK [FRAMES] [BAKE_SECONDS]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${1:?usage: walk_levels.sh BUILD_DIR WORK [FRAMES] [BAKE_SECONDS]}"
work="${2:?usage: walk_levels.sh BUILD_DIR WORK [FRAMES] [BAKE_SECONDS]}"
frames="${3:-90}"
bake_s="${4:-120}"
walk="$build/samples/walk/svit-walk" bake="$build/baker/svit-bake"
xvfb=()
[[ -z "${DISPLAY:-}" ]] && xvfb=(xvfb-run -a -s "-screen 0 1280x720x24")
mkdir -p "$work"
rows=()
for name in cornell house sponza city; do
  level="$root/samples/levels/$name/level.json"
  gltf="$(python3 -c "import json,os,sys; l=json.load(open(sys.argv[1])); print(os.path.normpath(os.path.join(os.path.dirname(sys.argv[1]), l['gltf'])))" "$level")"
  if [[ ! -f "$gltf" ]]; then
    echo "walk_levels.sh: $name skipped ($gltf absent)"
    continue
  fi
  [[ -f "$work/$name/bake.svit" ]] || "$bake" "$level" -o "$work/$name" --time "$bake_s" --quiet
  start=$(date +%s%N)
  "${xvfb[@]}" "$walk" "$level" --bake "$work/$name" --headless --frames 1 >/dev/null
  first_ms=$(( ($(date +%s%N) - start) / 1000000 ))
  start=$(date +%s%N)
  "${xvfb[@]}" "$walk" "$level" --bake "$work/$name" --headless --frames "$frames" --stats "$work/$name-stats.json" >/dev/null
  walk_s=$(( ($(date +%s%N) - start) / 1000000000 ))
  rows+=("$(python3 - "$work/$name-stats.json" "$name" "$first_ms" "$walk_s" "$frames" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
frames = s["frames"]
mean = sum(f["frame_ms"] for f in frames) / len(frames)
runtime = sum(f["runtime_ms"] for f in frames) / len(frames)
pending = max(f.get("emitters_pending", 0) for f in frames)
print(json.dumps({"level": sys.argv[2], "first_frame_ms": int(sys.argv[3]), "walk_s": int(sys.argv[4]),
                  "frames": int(sys.argv[5]), "mean_frame_ms": mean, "mean_runtime_ms": runtime,
                  "max_pending": pending, "renderer": s.get("renderer", "")}))
PY
)")
done
printf '%s\n' "${rows[@]}" >"$work/walk_levels.rows"
python3 - "$work/walk_levels.json" "$work/walk_levels.md" "$frames" "$work/walk_levels.rows" <<'PY'
import json, sys
rows = [json.loads(l) for l in open(sys.argv[4]) if l.strip()]
json.dump(rows, open(sys.argv[1], "w"), indent=1)
lines = ["| level | first frame (process start to exit) | frames | wall time of the walk | mean frame | of it runtime update |",
         "|---|---:|---:|---:|---:|---:|"]
for r in rows:
    lines.append(f"| {r['level']} | {r['first_frame_ms'] / 1000:.1f} s | {r['frames']} | {r['walk_s']} s | "
                 f"{r['mean_frame_ms']:.0f} ms | {r['mean_runtime_ms']:.0f} ms |")
table = "\n".join(lines)
print(table)
renderer = rows[0]["renderer"] if rows else ""
section = (f"`svit-walk LEVEL --bake OUT --headless` at its defaults (32 samples a frame, 640 x 360) on {renderer}: "
           f"the first frame is the wall time of a 1-frame run from process start to exit (loading the level and "
           f"bake, making the runtime and renderer, the first update and frame); the mean is over a "
           f"{sys.argv[3]}-frame walk.\n\n{table}\n")
open(sys.argv[2], "w").write(section)
PY
python3 "$root/tests/bench/doc_section.py" "$root/docs/bench/walk_levels.md" walk_levels.sh "$work/walk_levels.md"
