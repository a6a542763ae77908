#!/usr/bin/env bash
# The game-integration example (samples/integration) against the installed
# package: install svit from BUILD_DIR into a temporary prefix, configure and
# build the example with find_package(svit), bake the Cornell level quickly,
# run a few frames and check the last frame's PNG. Needs a display (CTest
# label gl: scripts/test runs it under xvfb-run).
# usage: integration_test.sh BUILD_DIR EXAMPLE_SOURCE_DIR SVIT_BAKE SOURCE_DIR CORNELL_GLTF
set -euo pipefail
build="$1" example="$2" bake="$3" src="$4" cornell_gltf="$5"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
level="$src/samples/levels/cornell/level.json"

cmake --install "$build" --prefix "$work/prefix" >/dev/null
test -f "$work/prefix/lib/cmake/svit/svitConfig.cmake"
test -f "$work/prefix/include/svit/runtime.h"
cmake -S "$example" -B "$work/build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_PREFIX_PATH="$work/prefix" >/dev/null
cmake --build "$work/build" >/dev/null
echo "built the example against the installed package"

"$bake" "$level" -o "$work/cornell" --quality 0.1 --time 10 --texels-per-m 16 --quiet
out="$("$work/build/svit-integration-example" "$level" "$work/cornell" "$work/last.png" 3)"
echo "$out"
grep -q "^moving 'tallBox'" <<<"$out"
grep -q "^frame 2: runtime" <<<"$out"
grep -q "wrote $work/last.png" <<<"$out"
# A PNG of 640 x 360 (IHDR width and height, big-endian at bytes 16..23).
[[ "$(head -c 8 "$work/last.png" | od -An -tx1 | tr -d ' \n')" == "89504e470d0a1a0a" ]]
[[ "$(od -An -tu1 -j16 -N8 "$work/last.png" | tr -s ' ' | sed 's/^ //')" == "0 0 2 128 0 0 1 104" ]]
[[ $(stat -c %s "$work/last.png") -gt 5000 ]]
# A bake of another level is refused with a message, not a crash.
"$bake" "$cornell_gltf" -o "$work/other" \
  --quality 0.05 --time 5 --texels-per-m 8 --quiet
if "$work/build/svit-integration-example" "$level" "$work/other" "$work/x.png" 1 2>"$work/err.txt"; then
  echo "a bake of another level was accepted"; exit 1
fi
grep -q "another level" "$work/err.txt"
echo "integration example works"
