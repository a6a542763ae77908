#!/usr/bin/env bash
# Sponza's lightmap-lit views (issue 22 item 7): an arcade in shadow (glTF
# camera CameraAlcove), a column base on the arcade floor (a scripted
# camera) and the atrium floor under the sun (CameraAlternate), rendered
# headless from the baked view of each bake given, at one fixed exposure
# per view (so bakes compare in radiance), as OUT/VIEW-LABEL.png.
# Needs ../shared/scenes/sponza.
# usage: tests/bench/sponza_views.sh BUILD_DIR OUT LABEL=BAKE_DIR [LABEL=BAKE_DIR ...]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="$1" out="$2"
shift 2
level="$root/samples/levels/sponza/level.json"
if [[ ! -f "$root/../shared/scenes/sponza/Sponza.gltf" ]]; then
  echo "sponza_views.sh: ../shared/scenes/sponza is absent; nothing rendered" >&2
  exit 0
fi
mkdir -p "$out"
column_script="$out/column-camera.json"
echo '{"camera": [{"t_s": 0, "position": [-8.5, 5.6, -7.5], "look_at": [-6.2, 4.3, -4.2], "yfov_rad": 0.8}]}' \
  >"$column_script"
render() {  # VIEW EXPOSURE BAKE LABEL svit-walk-options...
  local view="$1" exposure="$2" bake="$3" label="$4"
  shift 4
  xvfb-run -a -s "-screen 0 1280x720x24" "$build/samples/walk/svit-walk" "$level" --bake "$bake" \
    --headless --frames 1 --view baked --width 384 --height 216 --frames-out "$out/frames" \
    --exposure "$exposure" "$@" >/dev/null
  mv "$out/frames/frame-0000.png" "$out/$view-$label.png"
}
for pair in "$@"; do
  label="${pair%%=*}" bake="${pair#*=}"
  render arcade 0.008 "$bake" "$label" --camera CameraAlcove
  render column 0.003 "$bake" "$label" --script "$column_script"
  render sunlit-floor 0.002 "$bake" "$label" --camera CameraAlternate
done
rm -rf "$out/frames" "$column_script"
ls "$out"
