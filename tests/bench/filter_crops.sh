#!/usr/bin/env bash
# What the bake's edge-aware filter of the gathered (indirect) light does
# to contact shadows on Sponza (issue 22 item 1). Four bakes of
# samples/levels/sponza/level.json: PASSES lighting passes of seed 7 with
# the filter and without it (--no-filter; the same rays, so the filter is
# the only difference), and REF_PASSES passes of seed 1 both ways, the
# unfiltered one the reference. Each is rendered from the lightmap alone
# (svit-walk --view baked, 768 x 432, fixed exposure) from the arcade
# (glTF camera CameraAlcove) and the atrium floor under the sun
# (CameraAlternate), as linear EXR and PNG; crops around contact shadows
# are compared in linear luminance against the reference (RMS of the
# difference over the reference's mean, bench_frame_compare) and cut out
# 3x as PNGs into docs/images/filter-CROP-BAKE.png. The table goes into
# docs/bench/filter_crops.md between its filter_crops.sh markers.
# The reference's own noise is estimated from the unfiltered bakes: the
# two differ by e^2 = n^2 (1 + PASSES / REF_PASSES) for per-bake noise n
# at PASSES, so the reference carries n^2 PASSES / REF_PASSES.
# Needs ../shared/scenes/sponza; bakes are kept in WORK and reused.
# usage: tests/bench/filter_crops.sh BUILD_DIR WORK [PASSES] [REF_PASSES]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${1:?usage: filter_crops.sh BUILD_DIR WORK [PASSES] [REF_PASSES]}"
work="${2:?usage: filter_crops.sh BUILD_DIR WORK [PASSES] [REF_PASSES]}"
passes="${3:-24}" ref_passes="${4:-128}"
level="$root/samples/levels/sponza/level.json"
if [[ ! -f "$root/../shared/scenes/sponza/Sponza.gltf" ]]; then
  echo "filter_crops.sh: ../shared/scenes/sponza is absent; nothing baked" >&2
  exit 0
fi
compare="$build/tests/bench/bench_frame_compare"
mkdir -p "$work/frames"

# name:options of each bake.
bakes=("filtered:--passes $passes --seed 7"
  "unfiltered:--passes $passes --seed 7 --no-filter"
  "reference:--passes $ref_passes --seed 1 --no-filter"
  "reference-filtered:--passes $ref_passes --seed 1")
# view:glTF camera:exposure
views=("arcade:CameraAlcove:0.008" "sunlit:CameraAlternate:0.002")
# crop:view:x y w h (pixels of the 768 x 432 frame)
crops=("plant-base:arcade:160 280 128 96"
  "vault-wall:arcade:480 40 128 96"
  "wall-floor:arcade:540 300 128 96"
  "fountain:arcade:400 180 128 80"
  "vase-base:sunlit:320 240 128 96"
  "sun-edge:sunlit:400 300 128 96")

for entry in "${bakes[@]}"; do
  name="${entry%%:*}" options="${entry#*:}"
  # shellcheck disable=SC2086  # the options are words
  [[ -f "$work/$name/bake.svit" ]] || "$build/baker/svit-bake" "$level" -o "$work/$name" $options --quiet
  for view in "${views[@]}"; do
    IFS=: read -r view_name camera exposure <<<"$view"
    for format in exr png; do
      xvfb-run -a -s "-screen 0 1280x720x24" "$build/samples/walk/svit-walk" "$level" \
        --bake "$work/$name" --headless --frames 1 --view baked --width 768 --height 432 \
        --camera "$camera" --exposure "$exposure" --frames-format "$format" \
        --frames-out "$work/frames/tmp" >/dev/null
      mv "$work/frames/tmp/frame-0000.$format" "$work/frames/$view_name-$name.$format"
    done
  done
done

table="$work/filter_crops.md"
{
  echo "| crop | unfiltered, $passes passes | filtered, $passes passes | filtered, $ref_passes passes | the reference's own noise (estimated) |"
  echo "|---|---:|---:|---:|---:|"
} >"$table"
for crop in "${crops[@]}"; do
  IFS=: read -r crop_name view_name rect <<<"$crop"
  declare -A error=()
  for name in unfiltered filtered reference-filtered; do
    # shellcheck disable=SC2086  # the rectangle is four words
    error[$name]=$("$compare" compare "$work/frames/$view_name-$name.exr" \
      "$work/frames/$view_name-reference.exr" $rect | sed 's/^rel_rms=\([^ ]*\).*/\1/')
  done
  for name in unfiltered filtered reference; do
    # shellcheck disable=SC2086
    "$compare" crop "$work/frames/$view_name-$name.png" "$root/docs/images/filter-$crop_name-$name.png" $rect 3
  done
  noise=$(python3 -c "import math; e = ${error[unfiltered]}; print(f'{e * math.sqrt(($passes / $ref_passes) / (1 + $passes / $ref_passes)):.4f}')")
  echo "| $crop_name ($view_name) | ${error[unfiltered]} | ${error[filtered]} | ${error[reference-filtered]} | $noise |" >>"$table"
  unset error
done
cat "$table"
python3 "$root/tests/bench/doc_section.py" "$root/docs/bench/filter_crops.md" filter_crops.sh "$table"
