#!/usr/bin/env bash
# svit-bake plan / shard / merge as a user runs them (docs/sharded-bakes.md):
# the shards run by GNU parallel, the merged OUT byte-identical to a whole
# bake with the same seed and passes; usage errors exit 2; a missing shard
# is named; a merge under `ulimit -f` or killed (SIGKILL) leaves the
# previous OUT intact, and so does a killed shard leave its previous file.
# usage: svit_bake_sharded_test.sh SVIT_BAKE SVIT_PROBE LEVEL
set -u
bake="$1" probe="$2" level="$3"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
failures=0
fail() { echo "FAIL $*"; failures=$((failures + 1)); }
ok() { echo "ok   $*"; }
printf '0 0 0 0 1 0\n0 1.98 0 0 -1 0\n' >"$work/points.txt"
opts=(--seed 5 --quality 0.2 --passes 2 --texels-per-m 12)
shards=5

# Every file of bake $1 but report.json byte-identical to bake $2's.
same_bake() {
  local name
  [[ $(ls "$1" | sort) == $(ls "$2" | sort) ]] || return 1
  for name in $(ls "$1"); do
    [[ $name == report.json ]] || cmp -s "$1/$name" "$2/$name" || return 1
  done
}

# (a) The whole bake, and the same bake as plan, GNU parallel shards, merge.
"$bake" "$level" -o "$work/whole" "${opts[@]}" --quiet || { echo "FAIL the whole bake"; exit 1; }
"$bake" plan "$level" -o "$work/plan" --shards $shards "${opts[@]}" >"$work/out.txt" 2>&1 \
  && ok "plan: $(tail -1 "$work/out.txt")" || { fail "plan"; cat "$work/out.txt"; }
seq 0 $((shards - 1)) | parallel --halt now,fail=1 -j 2 "$bake" shard "$work/plan" {} --quiet \
  && ok "GNU parallel ran the $shards shards" || fail "GNU parallel: exit $?"
"$bake" merge "$work/plan" -o "$work/merged" >"$work/out.txt" 2>&1 \
  && ok "merge: $(tail -1 "$work/out.txt")" || { fail "merge"; cat "$work/out.txt"; }
same_bake "$work/merged" "$work/whole" && ok "merged OUT byte-identical to the whole bake" \
  || fail "merged OUT differs from the whole bake"
"$probe" "$work/merged" "$work/points.txt" >/dev/null && ok "svit-probe reads the merged bake" \
  || fail "svit-probe on the merged bake"
python3 -c "import json,sys; r=json.load(open('$work/merged/report.json')); sys.exit(r['sharded']['shards'] != $shards)" \
  && ok "report.json says it was sharded" || fail "report.json has no sharded section"

# (b) Usage errors: exit 2, a message, nothing written.
usage_case() {  # NAME ARGS...
  local name="$1"
  shift
  "$bake" "$@" >"$work/out.txt" 2>"$work/err.txt"
  local rc=$?
  [[ $rc -eq 2 ]] && ok "$name: exit 2: $(head -1 "$work/err.txt")" || fail "$name: exit $rc"
}
usage_case "plan without --shards" plan "$level" -o "$work/u1"
usage_case "plan --shards 0" plan "$level" -o "$work/u1" --shards 0
usage_case "plan --time" plan "$level" -o "$work/u1" --shards 2 --time 30
usage_case "--passes 0" "$level" -o "$work/u1" --passes 0
usage_case "--passes with --time" "$level" -o "$work/u1" --passes 2 --time 30
usage_case "shard without I" shard "$work/plan"
usage_case "shard I not a number" shard "$work/plan" x
usage_case "shard with a bake option" shard "$work/plan" 0 --seed 3
usage_case "merge without -o" merge "$work/plan"
[[ ! -e $work/u1 ]] && ok "nothing written by a usage error" || fail "a usage error wrote $work/u1"

# (c) Bad shards: out of range, missing; OUT left as it was.
"$bake" shard "$work/plan" $shards >"$work/out.txt" 2>"$work/err.txt"
[[ $? -eq 1 ]] && grep -q "shard $shards out of range" "$work/err.txt" \
  && ok "shard $shards refused: $(cat "$work/err.txt")" || fail "shard $shards: $(cat "$work/err.txt")"
(cd "$work/merged" && sha256sum ./*) >"$work/merged.sha256"
unchanged() { (cd "$work/merged" && sha256sum --quiet -c "$work/merged.sha256") && [[ $(ls "$work/merged" | wc -l) -eq 3 ]]; }
mv "$work/plan/shard-3.bin" "$work/shard-3.bin"
"$bake" merge "$work/plan" -o "$work/merged" >"$work/out.txt" 2>"$work/err.txt"
[[ $? -eq 1 ]] && grep -q "shard-3.bin: missing" "$work/err.txt" \
  && ok "missing shard named: $(cat "$work/err.txt")" || fail "missing shard: $(cat "$work/err.txt")"
unchanged && ok "OUT unchanged after the refused merge" || fail "OUT changed by a refused merge"
mv "$work/shard-3.bin" "$work/plan/shard-3.bin"

# (d) A merge under file-size limits: exit 1 naming the file; OUT intact.
exr_kib=$(($(stat -c %s "$work/merged/lightmap-0.exr") / 1024))
for kib in 1 $((exr_kib + 2)); do
  (ulimit -f "$kib"; exec "$bake" merge "$work/plan" -o "$work/merged" --quiet) >"$work/out.txt" 2>"$work/err.txt"
  rc=$?
  [[ $rc -eq 1 ]] && grep -q "File too large; .*merged left as it was" "$work/err.txt" \
    && ok "merge under ulimit -f $kib: exit 1: $(cat "$work/err.txt")" || fail "merge under ulimit -f $kib: exit $rc $(cat "$work/err.txt")"
  unchanged && [[ -z $(ls -d "$work"/merged.tmp-* 2>/dev/null) ]] && ok "ulimit -f $kib: OUT intact, nothing left beside it" \
    || fail "ulimit -f $kib: OUT changed or staging left"
done

# (e) A merge killed at its write steps, and at seeded moments: OUT is the
# previous bake or the whole new one (the same bytes here) and loads.
start_ns=$(date +%s%N)
"$bake" merge "$work/plan" -o "$work/merged" --quiet || fail "a merge"
merge_s=$(awk -v ns=$(($(date +%s%N) - start_ns)) 'BEGIN { printf "%.3f", ns / 1e9 }')
alive() { read -r _ _ state _ 2>/dev/null <"/proc/$pid/stat" || state=Z; }
for trigger in 0.05 $(awk -v t="$merge_s" 'BEGIN { printf "%.3f %.3f", 0.4 * t, 0.8 * t }') \
    after:lightmap-0.exr after:bake.svit after:report.json; do
  "$bake" merge "$work/plan" -o "$work/merged" --quiet >/dev/null 2>&1 &
  pid=$!
  state=R
  if [[ $trigger == after:* ]]; then
    file="$work/merged.tmp-$pid/${trigger#after:}"
    until [[ -e $file.tmp || -e $file || $state == Z ]]; do alive; done
  else
    sleep "$trigger"
  fi
  kill -KILL $pid 2>/dev/null
  wait $pid 2>/dev/null
  same_bake "$work/merged" "$work/whole" && "$probe" "$work/merged" "$work/points.txt" >/dev/null \
    && ok "merge killed at $trigger: OUT whole and loads" || fail "merge killed at $trigger: OUT broken"
done
"$bake" merge "$work/plan" -o "$work/merged" >"$work/out.txt" 2>"$work/err.txt" \
  && ok "the next merge cleans up: $(head -1 "$work/err.txt")" || fail "the next merge"
[[ -z $(ls -d "$work"/merged.tmp-* 2>/dev/null) ]] && ok "nothing left beside OUT" || fail "staging left beside OUT"

# (f) A shard killed or out of space leaves its previous file whole (or none).
cp "$work/plan/shard-2.bin" "$work/shard-2.ref"
(ulimit -f 1; exec "$bake" shard "$work/plan" 2 --quiet) >"$work/out.txt" 2>"$work/err.txt"
[[ $? -eq 1 ]] && grep -q "shard-2.bin.tmp: cannot write .*File too large" "$work/err.txt" \
  && cmp -s "$work/plan/shard-2.bin" "$work/shard-2.ref" \
  && ok "shard under ulimit -f 1: exit 1, previous shard file intact" || fail "shard under ulimit -f: $(cat "$work/err.txt")"
"$bake" shard "$work/plan" 2 --quiet &
pid=$!
sleep 0.3
kill -KILL $pid 2>/dev/null
wait $pid 2>/dev/null
cmp -s "$work/plan/shard-2.bin" "$work/shard-2.ref" && ok "killed shard: previous shard file intact" \
  || fail "killed shard: shard-2.bin changed"

if [[ $failures -ne 0 ]]; then echo "$failures failed"; exit 1; fi
echo "all sharded bake checks passed"
