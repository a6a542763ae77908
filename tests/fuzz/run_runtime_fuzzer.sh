#!/usr/bin/env bash
# Builds and runs fuzz_runtime_api, the runtime API abuse driver fed by
# libFuzzer (tests/fuzz/fuzz_runtime_api.cpp), for SECONDS under Xvfb on
# whatever GL is there (Mesa llvmpipe here). Not part of CI or scripts/test;
# see docs/fuzzing.md.
#
#   tests/fuzz/run_runtime_fuzzer.sh [SECONDS]
#
# Its own build tree (default build/fuzz-runtime: clang, ASan + UBSan +
# libFuzzer on svit's scene and runtime code, the GL runtime on, no tests),
# the Cornell box baked by that tree's svit-bake into out/fuzz/fuzz_runtime_api/bake,
# seeds from tests/fuzz/corpus/fuzz_runtime_api/ (read only), what it learns
# in out/fuzz/fuzz_runtime_api/corpus/, findings as
# out/fuzz/fuzz_runtime_api/crash-* (and leak-, timeout-, oom-), the log in
# out/fuzz/fuzz_runtime_api.log. Prints executions, calls issued and findings;
# exits 1 when it found something.
# Environment: SVIT_FUZZ_RUNTIME_BUILD_DIR, SVIT_FUZZ_OUT_DIR (default
# out/fuzz), SVIT_JOBS (build parallelism, default 2).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${SVIT_FUZZ_RUNTIME_BUILD_DIR:-$root/build/fuzz-runtime}"
out="${SVIT_FUZZ_OUT_DIR:-$root/out/fuzz}/fuzz_runtime_api"
seconds="${1:-600}"
if ! [[ "$seconds" =~ ^[0-9]+$ ]] || ((seconds == 0)); then
  echo "usage: $0 [SECONDS]" >&2
  exit 2
fi
for tool in clang++ xvfb-run; do
  command -v "$tool" >/dev/null || { echo "run_runtime_fuzzer: $tool not found; run scripts/setup --fuzz" >&2; exit 2; }
done
if [[ ! -f "$build/CMakeCache.txt" ]]; then
  CC=clang CXX=clang++ cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DSVIT_BUILD_FUZZ=ON -DSVIT_BUILD_TESTS=OFF -DSVIT_BUILD_SAMPLES=OFF -DSVIT_BUILD_RUNTIME_GL=ON \
    -DCMAKE_PROJECT_svit_INCLUDE="$root/tests/fuzz/attach.cmake"
fi
nice -n 10 cmake --build "$build" --target fuzz_runtime_api svit-bake -j "${SVIT_JOBS:-2}"

mkdir -p "$out/corpus"
if [[ ! -f "$out/bake/bake.svit" ]]; then
  "$build/baker/svit-bake" "$root/samples/levels/cornell/level.json" -o "$out/bake" \
    --quality 0.3 --seed 7 --quiet
fi
log="$out.log"
stamp="$out/.started"
touch "$stamp"
# Mesa's llvmpipe is not instrumented and keeps allocations until exit:
# LeakSanitizer would report them, not svit's leaks (the soak measures those).
export ASAN_OPTIONS="detect_leaks=0:${ASAN_OPTIONS:-}"
SVIT_FUZZ_BAKE_DIR="$out/bake" xvfb-run -a -s "-screen 0 640x480x24" \
  nice -n 10 "$build/tests/fuzz/fuzz_runtime_api" "$out/corpus" "$root/tests/fuzz/corpus/fuzz_runtime_api" \
  -max_total_time="$seconds" -timeout=60 -rss_limit_mb=4096 -print_final_stats=1 \
  -artifact_prefix="$out/" >"$log" 2>&1 || true
executions="$(grep -Eo 'stat::number_of_executed_units: *[0-9]+' "$log" | grep -Eo '[0-9]+$' | tail -n1 || true)"
calls="$(grep -Eo 'svit fuzz: [0-9]+ runtime API calls' "$log" | grep -Eo '[0-9]+' | tail -n1 || true)"
mapfile -t findings < <(find "$out" -maxdepth 1 -type f -newer "$stamp" \( -name 'crash-*' \
  -o -name 'leak-*' -o -name 'timeout-*' -o -name 'oom-*' \))
echo "fuzz_runtime_api: ${seconds} s, ${executions:-?} inputs, ${calls:-<10000} calls issued, corpus $(find "$out/corpus" -type f | wc -l), findings ${#findings[@]}"
printf '  %s\n' "${findings[@]+"${findings[@]}"}"
((${#findings[@]} == 0))
