#!/usr/bin/env bash
# One sample level of samples/levels/ end to end: a
# quick bake (quality is not the point), then svit-walk headless for a few
# frames of the level's own camera path and paths, with the statistics
# overlay: exit 0 (no GL error, no runtime error), finite non-negative
# stats, frames that are not blank. Small frames and a per-frame update
# budget keep it to seconds (Sponza's bake, mostly its xatlas atlas, is the
# longest part). Needs a display (CTest label gl: scripts/test runs it under
# xvfb-run).
# A level whose glTF is missing (sponza and city read theirs from
# ../shared/scenes beside the checkout, which a clone may lack) exits SKIP_CODE.
# usage: svit_walk_levels_test.sh SVIT_WALK SVIT_BAKE SOURCE_DIR LEVEL_NAME SKIP_CODE
set -u
walk="$1" bake="$2" src="$3" name="$4" skip_code="$5"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
level="$src/samples/levels/$name/level.json"
gltf="$(python3 -c 'import json, os, sys; print(os.path.normpath(os.path.join(os.path.dirname(sys.argv[1]), json.load(open(sys.argv[1]))["gltf"])))' "$level")"
if [[ ! -f "$gltf" ]]; then
  echo "SKIP $name: needs $gltf, which is missing (the large scenes are optional: ../shared/scenes beside the checkout)"
  exit "$skip_code"
fi
frames=3

# Sponza's lightmap atlas grows slower, not faster, with fewer texels: keep its default density.
density=(--texels-per-m 4)
[[ $name == sponza ]] && density=()
start=$(date +%s%N)
if ! "$bake" "$level" -o "$work/bake" --quality 0.05 --time 4 "${density[@]}" --quiet 2>"$work/err.txt"; then
  echo "FAIL $name: bake"; cat "$work/err.txt"; exit 1
fi
baked=$(date +%s%N)
if ! "$walk" "$level" --bake "$work/bake" --headless --frames $frames --width 160 --height 90 --budget-ms 20 \
    --overlay --frames-out "$work/frames" --stats "$work/stats.json" >"$work/out.txt" 2>"$work/err.txt"; then
  echo "FAIL $name: svit-walk"; cat "$work/err.txt"; exit 1
fi
walked=$(date +%s%N)
echo "$name: bake $(( (baked - start) / 1000000 )) ms, $frames headless frames $(( (walked - baked) / 1000000 )) ms"
cat "$work/out.txt"

python3 - "$work" "$frames" "$(dirname "$0")" <<'PY' || { echo "FAIL $name: frames and stats"; exit 1; }
import json, math, sys

sys.path.insert(0, sys.argv[3])
from pngread import png_pixels


def png_values(path):
    """All channel bytes of a frame, and its size."""
    w, h, _, rows = png_pixels(path)
    return (w, h), [v for row in rows for v in row]


work, frames = sys.argv[1], int(sys.argv[2])
for i in range(frames):
    size, values = png_values(f"{work}/frames/frame-{i:04d}.png")
    assert size == (160, 90), size
    mean = sum(values) / len(values)
    spread = math.sqrt(sum((v - mean) ** 2 for v in values) / len(values))
    assert 2 < mean < 250 and spread > 5, f"frame {i}: mean {mean:.1f}, spread {spread:.1f}: blank"
s = json.load(open(f"{work}/stats.json"))
assert [f["frame"] for f in s["frames"]] == list(range(frames)), s["frames"]
for f in s["frames"]:
    for k in ("maps_ms", "reduction_ms", "bounce_ms", "upload_ms", "runtime_ms", "shading_ms", "frame_ms",
              "emitters_refreshed", "samples", "faces", "unshot_share"):
        assert isinstance(f[k], (int, float)) and math.isfinite(f[k]) and f[k] >= 0, (f["frame"], k, f.get(k))
PY
echo "ok   $name: baked, walked $frames frames headless"
