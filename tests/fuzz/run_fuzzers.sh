#!/usr/bin/env bash
# Builds the libFuzzer targets (if needed) and runs each for a bounded time.
# Not part of CI or scripts/test; see docs/fuzzing.md.
#
#   tests/fuzz/run_fuzzers.sh [SECONDS_PER_TARGET] [TARGET...]
#
# SECONDS_PER_TARGET defaults to 60; TARGET defaults to all of them
# (fuzz_gltf fuzz_glb fuzz_level_json fuzz_bake_file fuzz_lightmap_exr).
# Each target runs niced as a single process, seeded from
# tests/fuzz/corpus/<target>/ (read only); what it learns goes to
# out/fuzz/<target>/corpus/, crashes, leaks, timeouts and out-of-memory
# inputs to out/fuzz/<target>/ (crash-*, leak-*, timeout-*, oom-*), the log to
# out/fuzz/<target>.log. A target stops at its first finding; the table says
# how long each really ran. Exits 1 when any target found something.
# Environment: SVIT_FUZZ_BUILD_DIR (default build/fuzz), SVIT_FUZZ_OUT_DIR
# (default out/fuzz), SVIT_JOBS (build parallelism, default 1),
# SVIT_FUZZ_ARGS (extra libFuzzer flags, e.g. "-max_len=65536").
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${SVIT_FUZZ_BUILD_DIR:-$root/build/fuzz}"
out="${SVIT_FUZZ_OUT_DIR:-$root/out/fuzz}"
jobs="${SVIT_JOBS:-1}"
seconds="${1:-60}"
if ! [[ "$seconds" =~ ^[0-9]+$ ]] || ((seconds == 0)); then
  echo "usage: $0 [SECONDS_PER_TARGET] [TARGET...]" >&2
  exit 2
fi
shift || true
targets=("$@")
if ((${#targets[@]} == 0)); then
  targets=(fuzz_gltf fuzz_glb fuzz_level_json fuzz_bake_file fuzz_lightmap_exr)
fi

if ! command -v clang++ >/dev/null; then
  echo "run_fuzzers: clang++ not found; run scripts/setup --fuzz" >&2
  exit 2
fi
if [[ ! -f "$build/CMakeCache.txt" ]]; then
  # Only what the fuzz targets need; CMAKE_PROJECT_svit_INCLUDE adds
  # tests/fuzz even where the top-level CMakeLists.txt has no hook for it.
  CC=clang CXX=clang++ cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DSVIT_BUILD_FUZZ=ON -DSVIT_BUILD_TESTS=OFF -DSVIT_BUILD_SAMPLES=OFF -DSVIT_BUILD_RUNTIME_GL=OFF \
    -DCMAKE_PROJECT_svit_INCLUDE="$root/tests/fuzz/attach.cmake"
fi
nice -n 10 cmake --build "$build" --target svit_fuzzers -j "$jobs"

found=0
printf '%-18s %8s %12s %10s %8s %s\n' target seconds executions exec/s corpus findings
for target in "${targets[@]}"; do
  binary="$build/tests/fuzz/$target"
  seeds="$root/tests/fuzz/corpus/$target"
  if [[ ! -x "$binary" || ! -d "$seeds" ]]; then
    echo "run_fuzzers: unknown target '$target' (no $binary or no $seeds)" >&2
    exit 2
  fi
  mkdir -p "$out/$target/corpus"
  log="$out/$target.log"
  # JSON keys and magic strings the formats use (libFuzzer dictionaries).
  dict=()
  case "$target" in
    fuzz_gltf | fuzz_glb) dict=(-dict="$root/tests/fuzz/gltf.dict") ;;
    fuzz_level_json) dict=(-dict="$root/tests/fuzz/level_json.dict") ;;
  esac
  # One in-process run (no -jobs/-fork: those add a child process and write
  # its log to fuzz-0.log in the working directory). -timeout: one input
  # taking 10 s is a hang; -rss_limit_mb/-malloc_limit_mb:
  # an input that makes the loader ask for 2 GB is a finding, not a slow run.
  start=$(date +%s)
  stamp="$out/$target/.started"
  touch "$stamp"
  # shellcheck disable=SC2086
  nice -n 10 "$binary" "$out/$target/corpus" "$seeds" "${dict[@]}" \
    -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=2048 \
    -print_final_stats=1 -artifact_prefix="$out/$target/" ${SVIT_FUZZ_ARGS:-} >"$log" 2>&1 || true
  elapsed=$(($(date +%s) - start))
  executions="$(grep -Eo 'stat::number_of_executed_units: *[0-9]+' "$log" | grep -Eo '[0-9]+$' | tail -n1 || true)"
  rate="$(grep -Eo 'stat::average_exec_per_sec: *[0-9]+' "$log" | grep -Eo '[0-9]+$' | tail -n1 || true)"
  corpus="$(find "$out/$target/corpus" -type f | wc -l)"
  # Findings of this run only (older ones stay until deleted).
  mapfile -t new_findings < <(find "$out/$target" -maxdepth 1 -type f -newer "$stamp" \( -name 'crash-*' \
    -o -name 'leak-*' -o -name 'timeout-*' -o -name 'oom-*' -o -name 'slow-unit-*' \))
  printf '%-18s %8s %12s %10s %8s %s\n' "$target" "$elapsed" "${executions:-?}" "${rate:-?}" "$corpus" \
    "${#new_findings[@]}"
  if ((${#new_findings[@]} > 0)); then
    found=1
    printf '  %s\n' "${new_findings[@]}"
  fi
done
exit $found
