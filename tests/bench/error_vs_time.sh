#!/usr/bin/env bash
# tests/bench/error_vs_time.sh [OUT_DIR]   (default $SVIT_BENCH_BUILD/error-vs-time)
#
# Error against time for the baker and the runtime on the Cornell box, Sponza
# (sun, sky, lamps) and the house (issue 8). Writes results.json, results.md,
# error-vs-time-baker.png and error-vs-time-runtime.png (log-log), logs/ and
# load.txt under OUT_DIR. See tests/bench/README.md.
#
# Baker: per level, a long reference bake (seed 2), optionally a second one
# (seed 3, compared with the first: the references' own noise), then bakes
# at increasing --time (seed 1) with --reference; each timed end to end (the
# whole process); error_vs_time.py reads their report.json.
# Runtime: bench_runtime_error per level (xvfb-run; Mesa llvmpipe where there
# is no GPU): a dynamic object moved, the runtime's error against a bake with
# it static there, by per-frame budget and frame.
#
# Knobs (environment):
#   SVIT_BENCH_BUILD       build dir, configured and built here (build/bench)
#   SVIT_BENCH_JOBS        build jobs (nproc)
#   SVIT_EVT_LEVELS        "cornell house sponza"
#   SVIT_EVT_BUDGETS       baker --time series, seconds ("2 4 8 16 32 64")
#   SVIT_EVT_BUDGETS_<LEVEL>  the series for one level (e.g. SVIT_EVT_BUDGETS_SPONZA)
#   SVIT_EVT_REFERENCE     "cornell=120 house=180 sponza=360" (--time of the references)
#   SVIT_EVT_PAIR          levels that get the second reference ("cornell house sponza")
#   SVIT_EVT_RUNTIME_LEVELS  levels of the runtime part ("cornell house sponza")
#   SVIT_EVT_RUNTIME       "cornell=10,50,200,0:16 house=10,50,200,0:16 sponza=200,0:8"
#                          (budgets in ms, 0 = none : frames)
#   SVIT_EVT_RUNTIME_QUALITY  quality of the runtime part's bakes (0.2)
#   SVIT_EVT_RUNTIME_FLAGS_<LEVEL>  more bench_runtime_error flags for one level;
#                          Sponza's default settles once, in 20 s frames, with
#                          16,384 patches (its 0.3 m ball's shadow needs them),
#                          64-texel maps and at most 4 samples per emitter (about
#                          25 minutes on llvmpipe): "--one-settle --settle-budget 20000
#                          --target-patches 16384 --map-resolution 64 --max-samples 4"
#   SVIT_EVT_REUSE=1       keep references (and the runtime part's bakes) already in OUT_DIR
#   SVIT_EVT_SKIP=baker|runtime  leave one part out (the other's old results are kept)
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${SVIT_BENCH_BUILD:-build/bench}"
[[ "$build" = /* ]] || build="$root/$build"
out="${1:-$build/error-vs-time}"
mkdir -p "$out/logs"
out="$(cd "$out" && pwd)"
levels="${SVIT_EVT_LEVELS:-cornell house sponza}"
budgets="${SVIT_EVT_BUDGETS:-2 4 8 16 32 64}"
references="${SVIT_EVT_REFERENCE:-cornell=120 house=180 sponza=360}"
pair="${SVIT_EVT_PAIR:-cornell house sponza}"
runtime_levels="${SVIT_EVT_RUNTIME_LEVELS:-cornell house sponza}"
sponza_runtime_flags="--one-settle --settle-budget 20000 --target-patches 16384 --map-resolution 64 --max-samples 4"
runtime_grid="${SVIT_EVT_RUNTIME:-cornell=10,50,200,0:16 house=10,50,200,0:16 sponza=200,0:8}"
runtime_quality="${SVIT_EVT_RUNTIME_QUALITY:-0.2}"
skip="${SVIT_EVT_SKIP:-}"
python=/usr/bin/python3  # Debian's, with python3-matplotlib (scripts/setup --bench)
start_all=$(date +%s)

level_path() { echo "$root/samples/levels/$1/level.json"; }
lookup() {  # lookup KEY "k=v k=v": v
  local pair
  for pair in $2; do [[ "${pair%%=*}" == "$1" ]] && { echo "${pair#*=}"; return; }; done
  echo "error_vs_time: no entry for $1 in '$2'" >&2
  exit 2
}
load() { echo "$1 $(date +%T) $(cut -d' ' -f1-3 /proc/loadavg)" >>"$out/load.txt"; }  # 1/5/15-minute load averages
{ echo "run $(date -u +%FT%TZ) SVIT_EVT_SKIP=$skip"; echo "cpus $(nproc)"; grep -m1 'model name' /proc/cpuinfo | sed 's/.*: /cpu /'; } >>"$out/load.txt"
load start

# 1. Build svit-bake and bench_runtime_error.
cd "$root"
if [[ ! -f "$build/build.ninja" ]]; then
  cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DSVIT_BUILD_BENCH=ON >"$out/logs/configure.log"
elif ! grep -q '^SVIT_BUILD_BENCH:BOOL=ON' "$build/CMakeCache.txt"; then
  cmake -S . -B "$build" -DSVIT_BUILD_BENCH=ON >"$out/logs/configure.log"
fi
targets=(svit-bake)
[[ "$skip" == runtime ]] || targets+=(bench_runtime_error)
echo "== building ${targets[*]} in $build"
cmake --build "$build" -j "${SVIT_BENCH_JOBS:-$(nproc)}" --target "${targets[@]}" >"$out/logs/build.log"
bake="$build/baker/svit-bake"

timed_bake() {  # timed_bake DIR ARGS...: bakes into DIR, appends "NAME wall_s" to DIR/../runs.tsv
  local dir="$1"
  shift
  rm -rf "$dir"
  local t0 t1 wall
  t0=$(date +%s.%N)
  "$bake" "$@" -o "$dir" --quiet
  t1=$(date +%s.%N)
  wall="$("$python" -c "import sys; print('%.3f' % (float(sys.argv[2]) - float(sys.argv[1])))" "$t0" "$t1")"
  printf '%s\t%s\n' "$(basename "$dir")" "$wall" >>"$(dirname "$dir")/runs.tsv"
  echo "   $(basename "$dir"): $wall s"
}

# 2. Runtime curves (first: the shorter part).
if [[ "$skip" != runtime ]]; then
  mkdir -p "$out/runtime"
  for level in $runtime_levels; do
    grid="$(lookup "$level" "$runtime_grid")"
    [[ "${SVIT_EVT_REUSE:-0}" == 1 ]] || rm -rf "$out/runtime/work/$level-base" "$out/runtime/work/$level-moved"
    echo "== $level: runtime, budgets ${grid%%:*} ms, ${grid##*:} frames"
    # Per-level flags (Sponza's settle takes many minutes on llvmpipe: once, cheaper).
    flags_var="SVIT_EVT_RUNTIME_FLAGS_${level^^}"
    default_flags=""
    [[ "$level" == sponza ]] && default_flags="$sponza_runtime_flags"
    read -r -a flags <<<"${!flags_var-$default_flags}"
    xvfb-run -a "$build/tests/bench/bench_runtime_error" --level "$level" --work "$out/runtime/work" \
      --json "$out/runtime/$level.json" --budgets "${grid%%:*}" --frames "${grid##*:}" \
      --quality "$runtime_quality" "${flags[@]}" 2>&1 | tee "$out/logs/runtime-$level.log"
    load "after-runtime-$level"
  done
fi

# 3. Baker curves: OUT/baker/LEVEL/{reference,reference-2,tT}/report.json and runs.tsv (wall times).
if [[ "$skip" != baker ]]; then
  for level in $levels; do
    path="$(level_path "$level")"
    ref_time="$(lookup "$level" "$references")"
    dir="$out/baker/$level"
    mkdir -p "$dir"
    stamp="$path seed 2 time $ref_time $(sha256sum "$path" | cut -c1-16) pair $([[ " $pair " == *" $level "* ]] && echo yes || true)"
    if [[ "${SVIT_EVT_REUSE:-0}" == 1 && -f "$dir/reference/report.json" && "$(cat "$dir/reference.stamp" 2>/dev/null)" == "$stamp" ]]; then
      echo "== $level: reusing the reference"
      grep -P '^reference(-2)?\t' "$dir/runs.tsv" >"$dir/runs.tsv.new" || true
      mv "$dir/runs.tsv.new" "$dir/runs.tsv"
    else
      rm -rf "$dir"/*
      echo "== $level: reference bake, --time $ref_time, seed 2"
      timed_bake "$dir/reference" "$path" --seed 2 --time "$ref_time"
      if [[ " $pair " == *" $level "* ]]; then
        echo "== $level: second reference (seed 3) against the first: the references' own noise"
        timed_bake "$dir/reference-2" "$path" --seed 3 --time "$ref_time" --reference "$dir/reference"
        rm -f "$dir"/reference-2/*.exr "$dir/reference-2/bake.svit"
      fi
      echo "$stamp" >"$dir/reference.stamp"
    fi
    level_budgets_var="SVIT_EVT_BUDGETS_$(echo "$level" | tr a-z A-Z)"
    echo "== $level: bakes at --time ${!level_budgets_var:-$budgets} (seed 1, --reference)"
    for t in ${!level_budgets_var:-$budgets}; do
      timed_bake "$dir/t$t" "$path" --seed 1 --time "$t" --reference "$dir/reference"
      rm -f "$dir/t$t"/*.exr "$dir/t$t/bake.svit"  # report.json is what is read
    done
    load "after-baker-$level"
  done
fi

# 4. Tables and plots.
"$python" "$root/tests/bench/error_vs_time.py" "$out"
echo "wrote $out/results.md, results.json, error-vs-time-baker.png, error-vs-time-runtime.png ($(($(date +%s) - start_all)) s in all)"
