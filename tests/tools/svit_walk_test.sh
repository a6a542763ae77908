#!/usr/bin/env bash
# svit-walk as users script it (docs/architecture.md "Command-line contracts"): a
# headless scripted walk of the Cornell level writes frames, stats and probe
# irradiance; bad inputs exit 1 naming what is wrong, bad usage exits 2.
# Needs a display (CTest label gl: scripts/test runs it under xvfb-run).
# usage: svit_walk_test.sh SVIT_WALK SVIT_BAKE SOURCE_DIR CORNELL_GLTF
set -u
walk="$1" bake="$2" src="$3" cornell_gltf="$4"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
level="$src/samples/levels/cornell/level.json"
failures=0
fail() { echo "FAIL $*"; failures=$((failures + 1)); }
ok() { echo "ok   $*"; }
expect_exit() {  # NAME WANT -- command...
  local name="$1" want="$2"; shift 3
  "$@" >"$work/out.txt" 2>"$work/err.txt"
  local rc=$?
  if [[ $rc -eq $want ]]; then ok "$name"; else fail "$name: exit $rc, expected $want"; cat "$work/err.txt"; fi
}
expect_err() {  # NAME TEXT: the last command's stderr contains TEXT
  grep -qF -- "$2" "$work/err.txt" && ok "$1" || { fail "$1: stderr lacks '$2'"; cat "$work/err.txt"; }
}

# A quick bake of the level (a few seconds; quality is not the point here).
"$bake" "$level" -o "$work/cornell" --quality 0.1 --time 10 --texels-per-m 16 --quiet \
  || { echo "FAIL bake"; exit 1; }

# A script: the box moves (and leaves its path), the lamp dims, the view changes.
cat >"$work/script.json" <<'JSON'
{"fps": 30, "frames": 5,
 "camera": [{"t_s": 0, "position": [0, 1, 3.4], "look_at": [0, 1, 0], "yfov_rad": 0.69},
            {"t_s": 1, "position": [0.3, 1.1, 3.0], "look_at": [0, 0.9, 0]}],
 "events": [{"frame": 1, "move": {"node": "tallBox", "translation": [0.2, 0, 0.1],
                                 "rotation": [0, 0.2588190, 0, 0.9659258]}},
            {"frame": 2, "baked_emitter": {"index": 0, "scale": 0.5}},
            {"frame": 3, "view": "delta"}]}
JSON
printf '%s' '{"camera": [{"t_s": 0, "position": [0, 1, 3.4], "look_at": [0, 1, 0]}]}' >"$work/script_camera.json"
printf '0 0 0 0 1 0\n# a comment\n0 1.98 0 0 -1 0\n-0.99 1 0 1 0 0\n0.99 1 0 -1 0 0\n' >"$work/points.txt"
expect_exit walk 0 -- "$walk" "$level" --bake "$work/cornell" --headless --script "$work/script.json" \
  --frames-out "$work/frames" --stats "$work/stats.json" --probe "$work/points.txt" --probe-out "$work/probe.txt" \
  --width 160 --height 90
grep -q "maps_ms" "$work/out.txt" && ok "prints the stage table" || fail "no stage table on stdout"

# A PNG reader (standard library only) the checks below share.
python3 - "$work" "$(dirname "$0")" <<'PY' && ok "frames, stats and probes" || fail "frames, stats and probes"
import json, math, sys
sys.path.insert(0, sys.argv[2])
from pngread import png_pixels

work = sys.argv[1]
for i in range(5):
    w, h, ch, rows = png_pixels(f"{work}/frames/frame-{i:04d}.png")
    assert (w, h) == (160, 90), (w, h)
    values = [v for row in rows for v in row]
    mean = sum(values) / len(values)
    spread = math.sqrt(sum((v - mean) ** 2 for v in values) / len(values))
    assert 5 < mean < 250 and spread > 10, f"frame {i}: mean {mean:.1f}, spread {spread:.1f}: blank"

s = json.load(open(f"{work}/stats.json"))
assert s["level"].endswith("level.json") and s["renderer"], s.keys()
assert [f["frame"] for f in s["frames"]] == list(range(5)), s["frames"]
stages = ("t_s", "maps_ms", "reduction_ms", "bounce_ms", "upload_ms", "runtime_ms", "shading_ms", "frame_ms")
for f in s["frames"]:
    for k in stages + ("emitters_refreshed", "samples", "faces"):
        assert isinstance(f[k], (int, float)) and math.isfinite(f[k]) and f[k] >= 0, (f["frame"], k, f.get(k))
assert abs(s["frames"][3]["t_s"] - 0.1) < 1e-6
assert [f["view"] for f in s["frames"]] == ["runtime"] * 3 + ["delta"] * 2
assert s["frames"][1]["emitters_refreshed"] > 0, "the box moved: emitters must be refreshed"
for k in stages[1:]:
    assert math.isfinite(s["summary"]["mean"][k]) and math.isfinite(s["summary"]["max"][k]), k

lines = open(f"{work}/probe.txt").read().splitlines()
assert len(lines) == 4, lines
for line in lines:
    rgb = [float(x) for x in line.split()]
    assert len(rgb) == 3 and all(math.isfinite(v) and v >= 0 for v in rgb), line
PY

# The statistics overlay (--overlay): the same baked-view frame with and
# without it (480 x 270, text at 1 pixel per font unit) differs only in the
# top-left corner, which is darkened (the box) and carries light pixels
# (the text).
for variant in plain overlay; do
  extra=()
  [[ $variant == overlay ]] && extra=(--overlay)
  expect_exit "walk_$variant" 0 -- "$walk" "$level" --bake "$work/cornell" --headless --frames 1 --view baked \
    --frames-out "$work/$variant" --width 480 --height 270 "${extra[@]}"
done
python3 - "$work" "$(dirname "$0")" <<'PY' && ok "overlay drawn top left" || fail "overlay drawn top left"
import sys
sys.path.insert(0, sys.argv[2])
from pngread import png_pixels

work = sys.argv[1]
w, h, ch, plain = png_pixels(f"{work}/plain/frame-0000.png")
_, _, _, over = png_pixels(f"{work}/overlay/frame-0000.png")
def px(rows, x, y):
    return tuple(rows[y][x * ch:x * ch + 3])
changed = [(x, y) for y in range(h) for x in range(w) if px(plain, x, y) != px(over, x, y)]
assert changed, "--overlay changed nothing"
x1, y1 = max(x for x, _ in changed), max(y for _, y in changed)
assert x1 < w * 3 // 4 and y1 < h * 3 // 4, f"changes reach ({x1}, {y1}) of {w} x {h}: not a corner overlay"
box = [(x, y) for y in range(4, y1 - 4) for x in range(4, x1 - 4)]
text = [p for p in box if min(px(over, *p)) >= 200 and px(over, *p) != px(plain, *p)]
dimmed = [p for p in box if sum(px(over, *p)) < sum(px(plain, *p))]
assert len(text) > 300, f"only {len(text)} light text pixels in the overlay box"
assert len(dimmed) > len(box) // 2, f"the box darkens only {len(dimmed)} of {len(box)} pixels"
print(f"overlay: box {x1 + 1} x {y1 + 1} px, {len(text)} text pixels")
PY

# Bad usage: exit 2 with the usage text.
expect_exit no_arguments 2 -- "$walk"
expect_exit no_bake_option 2 -- "$walk" "$level" --headless
expect_exit unknown_option 2 -- "$walk" "$level" --bake "$work/cornell" --frobnicate
expect_err unknown_option_message "unknown option '--frobnicate'"
expect_exit bad_frames 2 -- "$walk" "$level" --bake "$work/cornell" --headless --frames 0
expect_exit bad_view 2 -- "$walk" "$level" --bake "$work/cornell" --headless --view sideways
expect_exit probe_without_out 2 -- "$walk" "$level" --bake "$work/cornell" --headless --probe "$work/points.txt"
# --exposure must be finite and > 0, --frames-format png or exr; the message
# names the option and the value.
for bad in 0 nan -1; do
  expect_exit "exposure_$bad" 2 -- "$walk" "$level" --bake "$work/cornell" --headless --exposure "$bad"
  expect_err "exposure_${bad}_message" "--exposure needs a finite number > 0 (got '$bad')"
done
expect_exit frames_format_tiff 2 -- "$walk" "$level" --bake "$work/cornell" --headless --frames-format tiff
expect_err frames_format_tiff_message "--frames-format needs png or exr (got 'tiff')"
for bad in -1 x; do
  expect_exit "samples_per_frame_$bad" 2 -- "$walk" "$level" --bake "$work/cornell" --headless --samples-per-frame "$bad"
  expect_err "samples_per_frame_${bad}_message" "--samples-per-frame needs an integer in [0, 1000000] (got '$bad')"
done

# --frames-format exr: the frame is an OpenEXR file (magic 76 2f 31 01) of
# the linear radiance, none beside it as PNG. The radiance does not depend
# on --exposure (the same file at 2 and 8), the PNG does.
for e in 2 8; do
  for format in exr png; do
    expect_exit "walk_${format}_exposure_$e" 0 -- "$walk" "$level" --bake "$work/cornell" --headless --frames 1 \
      --view baked --frames-out "$work/$format$e" --frames-format $format --exposure $e --width 64 --height 36
  done
done
[[ -f "$work/exr2/frame-0000.exr" && ! -e "$work/exr2/frame-0000.png" ]] && \
  [[ "$(head -c 4 "$work/exr2/frame-0000.exr" | od -An -tx1 | tr -d ' \n')" == 762f3101 ]] \
  && ok "exr frame written" || fail "exr frame written"
cmp -s "$work/exr2/frame-0000.exr" "$work/exr8/frame-0000.exr" && ok "exr frame independent of --exposure" \
  || fail "exr frame changed with --exposure"
cmp -s "$work/png2/frame-0000.png" "$work/png8/frame-0000.png" && fail "png frame ignored --exposure" \
  || ok "png frame follows --exposure"

# Bad input: exit 1, the message names the file and element.
expect_exit missing_bake 1 -- "$walk" "$level" --bake "$work/nothing" --headless --frames 1
expect_err missing_bake_message "bake.svit"
"$bake" "$cornell_gltf" -o "$work/gltf_bake" --quality 0.05 --time 5 \
  --texels-per-m 8 --quiet || fail "bake of the bare glTF"
expect_exit other_level_bake 1 -- "$walk" "$level" --bake "$work/gltf_bake" --headless --frames 1
expect_err other_level_bake_message "another level"
# glTF cameras as viewpoints: the Cornell glTF with two cameras (the bake of
# the bare glTF serves: cameras are not in the level hash). With no camera
# path the first camera is the default; --camera picks one by name; an
# unknown name, or --camera with a script's own camera keys, is exit 1.
python3 - "$cornell_gltf" "$work/cameras.gltf" <<'PY' || fail "write the glTF with cameras"
import json, os, shutil, sys
gltf = json.load(open(sys.argv[1]))
for b in gltf["buffers"]:  # beside the copy: the loader reads buffers from the glTF's directory
    shutil.copy(os.path.join(os.path.dirname(sys.argv[1]), b["uri"]), os.path.dirname(sys.argv[2]))
gltf["cameras"] = [{"name": "Front", "type": "perspective", "perspective": {"yfov": 0.7, "znear": 0.05}},
                   {"name": "Corner", "type": "perspective", "perspective": {"yfov": 0.9, "znear": 0.05, "zfar": 20}}]
gltf["nodes"] += [{"name": "front eye", "camera": 0, "translation": [0, 1, 3.4]},
                  {"name": "corner eye", "camera": 1, "translation": [0.8, 1.7, 0.8],
                   "rotation": [-0.2391, 0.3696, 0.0990, 0.8924]}]
gltf["scenes"][0]["nodes"] += [len(gltf["nodes"]) - 2, len(gltf["nodes"]) - 1]
json.dump(gltf, open(sys.argv[2], "w"))
PY
for view in default Front Corner; do
  extra=()
  [[ $view != default ]] && extra=(--camera "$view")
  expect_exit "camera_$view" 0 -- "$walk" "$work/cameras.gltf" --bake "$work/gltf_bake" --headless --frames 1 \
    --view baked --frames-out "$work/camera_$view" --width 64 --height 36 "${extra[@]}"
done
cmp -s "$work/camera_default/frame-0000.png" "$work/camera_Front/frame-0000.png" \
  && ok "the first glTF camera is the default" || fail "the default view is not the first glTF camera"
cmp -s "$work/camera_Front/frame-0000.png" "$work/camera_Corner/frame-0000.png" \
  && fail "--camera Corner showed what Front shows" || ok "--camera picks the named camera"
expect_exit camera_unknown 1 -- "$walk" "$work/cameras.gltf" --bake "$work/gltf_bake" --headless --frames 1 \
  --camera Back
expect_err camera_unknown_message "--camera 'Back': $work/cameras.gltf has no camera called that (its cameras: 'Front', 'Corner')"
expect_exit camera_with_script 1 -- "$walk" "$work/cameras.gltf" --bake "$work/gltf_bake" --headless \
  --camera Front --script "$work/script_camera.json"
expect_err camera_with_script_message "--camera 'Front': the script's camera keys place the camera too"
expect_exit camera_empty 2 -- "$walk" "$work/cameras.gltf" --bake "$work/gltf_bake" --headless --camera ""
expect_err camera_empty_message "--camera needs a camera name"

# A bare glTF baked with --sun/--sky walks as the OUT/level.json the bake
# wrote (the same level hash); the bare glTF is another level to that bake.
"$bake" "$src/tests/data/good_quad.gltf" -o "$work/sunlit" --passes 1 --quiet \
  --sun '{"direction_to_sun": [0.3, 1, 0.2], "illuminance_lux": 100000}' || fail "bake with --sun"
expect_exit sunlit_level_json 0 -- "$walk" "$work/sunlit/level.json" --bake "$work/sunlit" --headless --frames 1 \
  --width 64 --height 36
expect_exit sunlit_bare_gltf 1 -- "$walk" "$src/tests/data/good_quad.gltf" --bake "$work/sunlit" --headless \
  --frames 1
expect_err sunlit_bare_gltf_message "another level"

bad_script() {  # NAME JSON EXPECTED-MESSAGE
  printf '%s' "$2" >"$work/bad.json"
  expect_exit "$1" 1 -- "$walk" "$level" --bake "$work/cornell" --headless --frames 3 --script "$work/bad.json"
  expect_err "$1 message" "$3"
}
bad_script unknown_light '{"events": [{"frame": 0, "light": {"name": "lamp9", "enabled": false}}]}' \
  "bad.json: events[0].light.name: no light 'lamp9'"
bad_script unknown_node '{"events": [{"frame": 0, "move": {"node": "tallbox"}}]}' "events[0].move.node: no node 'tallbox'"
bad_script static_node '{"events": [{"frame": 0, "move": {"node": "shortBox", "translation": [0, 0, 0]}}]}' \
  "events[0].move.node: node 'shortBox' is static"
bad_script unknown_field '{"events": [{"frame": 0, "view": "delta", "colour": 1}]}' "events[0].colour: unknown field"
bad_script frame_out_of_range '{"events": [{"frame": 3, "view": "delta"}]}' "events[0].frame: 3 is past the last frame 2"
bad_script bad_emitter '{"events": [{"frame": 0, "baked_emitter": {"index": 99999, "scale": 1}}]}' \
  "events[0].baked_emitter.index: 99999 >= emitter count"
bad_script bad_view '{"events": [{"frame": 0, "view": "sideways"}]}' "events[0].view"
bad_script bad_camera '{"camera": [{"t_s": 0, "position": [0, 1], "look_at": [0, 0, 0]}]}' "camera[0].position"
bad_script not_json '{"events": [' "not valid JSON"
printf '0 0 0 0 1 0\n1 2 three 0 1 0\n' >"$work/bad_points.txt"
expect_exit bad_points 1 -- "$walk" "$level" --bake "$work/cornell" --headless --frames 1 \
  --probe "$work/bad_points.txt" --probe-out "$work/p.txt"
expect_err bad_points_message "bad_points.txt:2:"

# Outputs that cannot be written: exit 1 naming the option, the path and
# the reason, before the level is loaded (with a missing bake too, the
# output is what is named) and before anything is rendered (no frame). A
# path under a regular file is unwritable even for root.
echo "not a directory" >"$work/file"
unwritable() {  # NAME EXPECTED-MESSAGE -- output options...
  local name="$1" message="$2"; shift 3
  local started=$SECONDS
  expect_exit "$name" 1 -- "$walk" "$level" --bake "$work/cornell" --headless --frames 2 --width 160 --height 90 "$@"
  expect_err "${name}_message" "$message"
  echo "     (failed after $((SECONDS - started)) s)"
  expect_exit "${name}_before_loading" 1 -- "$walk" "$level" --bake "$work/nothing" --headless --frames 2 "$@"
  expect_err "${name}_before_loading_message" "$message"
}
unwritable frames_out_under_file "--frames-out $work/file/frames: $work/file: cannot create a file there: Not a directory" \
  -- --frames-out "$work/file/frames"
[[ ! -e "$work/file/frames" ]] && ok "no frames written" || fail "frames written under a file"
unwritable stats_under_file "--stats $work/file/stats.json: $work/file: cannot create a file there: Not a directory" \
  -- --frames-out "$work/unwritten" --stats "$work/file/stats.json"
[[ ! -e "$work/unwritten" ]] && ok "no frames directory made" || fail "frames written though --stats cannot be"
unwritable stats_missing_dir "--stats $work/nodir/stats.json: $work/nodir: cannot create a file there: No such file or directory" \
  -- --stats "$work/nodir/stats.json"
unwritable stats_is_dir "--stats $work: is a directory" -- --stats "$work"
unwritable probe_out_under_file "--probe-out $work/file/p.txt: $work/file: cannot create a file there: Not a directory" \
  -- --probe "$work/points.txt" --probe-out "$work/file/p.txt"
[[ -z $(ls -A "$work" | grep -F .svit-write-check) ]] && ok "no write-check file left" || fail "write-check file left"

# A file-size limit (ulimit -f, KiB) while writing: exit 1, the message names
# the file and the reason, no cut file is left.
(ulimit -f 1; exec "$walk" "$level" --bake "$work/cornell" --headless --frames 2 --width 160 --height 90 \
  --frames-out "$work/limited") >"$work/out.txt" 2>"$work/err.txt"
rc=$?
[[ $rc -eq 1 ]] && ok "frames_ulimit exit 1" || { fail "frames_ulimit: exit $rc"; cat "$work/err.txt"; }
expect_err frames_ulimit_message "frame 0: $work/limited/frame-0000.png.tmp: cannot write"
expect_err frames_ulimit_reason "File too large"
[[ -z $(ls -A "$work/limited") ]] && ok "no cut frame left" || fail "left $(ls -A "$work/limited")"
(ulimit -f 1; exec "$walk" "$level" --bake "$work/cornell" --headless --frames 2 --width 160 --height 90 \
  --stats "$work/limited/stats.json") >"$work/out.txt" 2>"$work/err.txt"
rc=$?
[[ $rc -eq 1 ]] && ok "stats_ulimit exit 1" || { fail "stats_ulimit: exit $rc"; cat "$work/err.txt"; }
expect_err stats_ulimit_message "$work/limited/stats.json.tmp: cannot write"
expect_err stats_ulimit_reason "File too large"
[[ -z $(ls -A "$work/limited") ]] && ok "no cut stats left" || fail "left $(ls -A "$work/limited")"

if [[ $failures -ne 0 ]]; then
  echo "$failures failure(s)"
  exit 1
fi
echo "svit-walk: all checks passed"
