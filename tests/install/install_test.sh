#!/usr/bin/env bash
# Installs svit from BUILD_DIR into a temporary prefix, builds the consumer
# project against it with find_package(svit), and runs it on the Cornell box.
# usage: install_test.sh BUILD_DIR CONSUMER_SOURCE_DIR LEVEL
set -euo pipefail
build="$1" consumer="$2" level="$3"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cmake --install "$build" --prefix "$work/prefix" >/dev/null
test -f "$work/prefix/lib/cmake/svit/svitConfig.cmake"
test -f "$work/prefix/include/svit/level.h"
cmake -S "$consumer" -B "$work/build" -G Ninja -DCMAKE_PREFIX_PATH="$work/prefix" >/dev/null
cmake --build "$work/build" >/dev/null
out="$("$work/build/consumer" "$level")"
echo "$out"
grep -q '^triangles 36$' <<<"$out"
echo "installed package works"
