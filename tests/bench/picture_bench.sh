#!/usr/bin/env bash
# Picture error against time along the demo walk (Cornell box), the house's
# walk and, when ../shared/scenes is there, a Sponza walk: bench_picture per level, then
# the tables of docs/bench/picture_bench.md (between its picture_report.py
# markers) and docs/images/picture_error.svg regenerated from the JSON
# (picture_report.py). Headless: under xvfb-run
# without a display. Bakes are kept in WORK and reused.
# usage: tests/bench/picture_bench.sh BUILD_BENCH_DIR WORK [sponza-seconds]
#   BUILD_BENCH_DIR: a build with -DSVIT_BUILD_BENCH=ON (its tests/bench/bench_picture)
#   sponza-seconds: bake time of each Sponza bake (default 200; 0 skips Sponza)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${1:?usage: picture_bench.sh BUILD_BENCH_DIR WORK [sponza-seconds]}"
work="${2:?usage: picture_bench.sh BUILD_BENCH_DIR WORK [sponza-seconds]}"
sponza_s="${3:-200}"
bench="$build/tests/bench/bench_picture"
[[ -x "$bench" ]] || { echo "picture_bench.sh: no $bench (configure with -DSVIT_BUILD_BENCH=ON)" >&2; exit 1; }
xvfb=()
[[ -z "${DISPLAY:-}" ]] && xvfb=(xvfb-run -a -s "-screen 0 1280x720x24")
mkdir -p "$work"
runs=()
"${xvfb[@]}" "$bench" --level "$root/samples/levels/cornell/level.json" --work "$work/cornell" \
  --json "$work/cornell.json" --frames 90 --reference-frames 0,2,5,10,20,30,45,60,89 --png-prefix "$work/cornell"
runs+=("$work/cornell.json")
"${xvfb[@]}" "$bench" --level "$root/samples/levels/house/level.json" --work "$work/house" \
  --json "$work/house.json" --frames 90 --reference-frames 0,30,60,89 --quality 1 --time 60 --exposure 0.05 \
  --png-prefix "$work/house"
runs+=("$work/house.json")
if [[ "$sponza_s" != 0 && -f "$root/../shared/scenes/sponza/Sponza.gltf" ]]; then
  "${xvfb[@]}" "$bench" --level "$root/samples/levels/sponza/level.json" --work "$work/sponza" \
    --json "$work/sponza.json" --frames 60 --reference-frames 0,45 --quality 1 --time "$sponza_s" \
    --exposure 0.0002 --png-prefix "$work/sponza"
  runs+=("$work/sponza.json")
else
  echo "picture_bench.sh: Sponza skipped (no ../shared/scenes/sponza, or sponza-seconds 0)"
fi
python3 "$root/tests/bench/picture_report.py" "$root/docs/bench/picture_bench.md" "$root/docs/images/picture_error.svg" "${runs[@]}"
echo "picture_bench.sh: wrote docs/bench/picture_bench.md (its tables) and docs/images/picture_error.svg"
