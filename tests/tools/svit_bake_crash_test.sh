#!/usr/bin/env bash
# svit-bake when the disk fills and the process dies (issue 24 item 4): under
# `ulimit -f` it exits 1 naming the file that was too large; killed (SIGKILL)
# at any moment it leaves OUT the previous bake or the whole new one; the next
# bake removes what the killed ones left (OUT.tmp-<pid>), never a live bake's.
# usage: svit_bake_crash_test.sh SVIT_BAKE SVIT_PROBE CORNELL_GLTF
set -u
bake="$1" probe="$2" cornell="$3"
level="$(dirname "$cornell")/level.json"  # the same box with dynamic objects: a bigger bake.svit
work="$(mktemp -d)"
sleeper=""
trap '[[ -n $sleeper ]] && kill $sleeper 2>/dev/null; rm -rf "$work"' EXIT
failures=0
fail() { echo "FAIL $*"; failures=$((failures + 1)); }
ok() { echo "ok   $*"; }
printf '0 0 0 0 1 0\n0 1.98 0 0 -1 0\n' >"$work/points.txt"

# OUT ($1) against the bake it replaced ($2): "old" when byte-identical, "new"
# when a whole bake of the same seed (bake.svit and the pages byte-identical,
# report.json equal but for its timings), anything else is a failure.
classify() {
  python3 - "$1" "$2" <<'PY'
import filecmp, json, os, sys
out, ref = sys.argv[1], sys.argv[2]
if not os.path.isdir(out):
    sys.exit(f"{out} is missing")
names = sorted(os.listdir(out))
if names != sorted(os.listdir(ref)):
    sys.exit(f"files {names}, expected {sorted(os.listdir(ref))}")
for name in names:
    if name != "report.json" and not filecmp.cmp(f"{out}/{name}", f"{ref}/{name}", shallow=False):
        sys.exit(f"{name} differs from the previous bake")
if filecmp.cmp(f"{out}/report.json", f"{ref}/report.json", shallow=False):
    print("old")
    sys.exit(0)
def untimed(path):  # what does not depend on the clock
    r = json.load(open(path))
    for key in ("stage_seconds", "total_seconds"):
        r.pop(key)
    r["radiosity"].pop("rays_per_s")
    r["radiosity"]["leak_guard"].pop("seconds")
    r["shadow_masks"].pop("seconds", None)
    for point in r["error_vs_time"]:
        point.pop("t_s")
    return r
if untimed(f"{out}/report.json") != untimed(f"{ref}/report.json"):
    sys.exit("report.json differs beyond its timings")
print("new")
PY
}
loads() { "$probe" "$1" "$work/points.txt" >/dev/null 2>"$work/probe_err.txt"; }
leftovers() { (cd "$work" && ls -d "$1".tmp-* "$1".old-* 2>/dev/null); }

# (a) File-size limits. A small bake: the page is smaller than bake.svit, so
# limits between them fail at one file or the other.
small=(--quality 0.2 --texels-per-m 8 --seed 7 --quiet)
"$bake" "$level" -o "$work/a" "${small[@]}" || { echo "FAIL the first bake"; exit 1; }
cp -r "$work/a" "$work/a_ref"
(cd "$work/a" && sha256sum ./*) >"$work/a.sha256"
exr_kib=$(($(stat -c %s "$work/a/lightmap-0.exr") / 1024))
bake_kib=$(($(stat -c %s "$work/a/bake.svit") / 1024))
[[ $((exr_kib + 2)) -lt $bake_kib ]] || fail "the page ($exr_kib KiB) should be smaller than bake.svit ($bake_kib KiB)"
# (bash's ulimit -f counts KiB; report.json, the smallest file, is written
# last, so no limit stops at it alone; it shares bake.svit's writer.)
for case in "1 lightmap-0.exr" "$((exr_kib / 2)) lightmap-0.exr" "$((exr_kib + 2)) bake.svit"; do
  read -r kib file <<<"$case"
  (ulimit -f "$kib"; exec "$bake" "$level" -o "$work/a" "${small[@]}") >"$work/out.txt" 2>"$work/err.txt"
  rc=$?
  name="ulimit -f $kib"
  [[ $rc -eq 1 ]] && ok "$name: exit 1" || fail "$name: exit $rc, expected 1"
  grep -q "$file.tmp: cannot write [0-9]* bytes: File too large; .*a left as it was" "$work/err.txt" \
    && ok "$name: message names $file and the reason" || { fail "$name: message"; cat "$work/err.txt"; }
  [[ $(wc -l <"$work/err.txt") -eq 1 ]] || fail "$name: more than one line on stderr"
  (cd "$work/a" && sha256sum --quiet -c "$work/a.sha256") && [[ $(ls "$work/a" | wc -l) -eq 3 ]] \
    && ok "$name: OUT byte-identical" || fail "$name: OUT changed"
  [[ -z $(leftovers a) ]] && ok "$name: nothing left beside OUT" || fail "$name: left $(leftovers a)"
done
# A limit above every file: the bake goes through (so the limits above were what failed).
(ulimit -f 4096; exec "$bake" "$level" -o "$work/a" "${small[@]}") >"$work/out.txt" 2>"$work/err.txt"
rc=$?
[[ $rc -eq 0 && $(classify "$work/a" "$work/a_ref") == new ]] && ok "ulimit -f 4096: a new bake" \
  || fail "ulimit -f 4096: exit $rc, $(classify "$work/a" "$work/a_ref")"

# (b) SIGKILL at seeded moments over the whole bake, and at the write stage's
# steps. A bake whose write stage (a 3 MB page) is a good part of it. Each
# kill's OUT is compared with OUT before it (k_prev).
big=(--quality 0.05 --texels-per-m 96 --seed 7 --quiet)
start_ns=$(date +%s%N)
"$bake" "$cornell" -o "$work/k" "${big[@]}" || { echo "FAIL the big bake"; exit 1; }
bake_s=$(awk -v ns=$(($(date +%s%N) - start_ns)) 'BEGIN { printf "%.3f", ns / 1e9 }')
write_s=$(python3 -c "import json; print(json.load(open('$work/k/report.json'))['stage_seconds']['write'])")
echo "big bake: $bake_s s wall, write stage $write_s s"
# Seven delays over [0, 1.1 x the bake], one drawn in each seventh, and four
# over [0, 1.2 x the write stage] counted from the moment the staging
# directory appears (the write stage is ~7% of the bake: few plain delays
# land in it); a fixed-seed LCG (seed 24).
lcg_delays() {  # COUNT SPAN_S PREFIX
  awk -v n="$1" -v t="$2" -v p="$3" 'BEGIN { x = 24 + n; for (i = 0; i < n; ++i) {
    x = (1103515245 * x + 12345) % 2147483648; printf "%s%.3fs ", p, t * (i + x / 2147483648) / n } }'
}
read -r -a triggers <<<"$(lcg_delays 7 "$(awk -v t="$bake_s" 'BEGIN { print 1.1 * t }')" "")"
read -r -a write_triggers <<<"$(lcg_delays 4 "$(awk -v t="$write_s" 'BEGIN { print 1.2 * t }')" "write+")"
# And as soon as each file of the write stage is begun (NAME.tmp) or done
# (NAME): writing them takes milliseconds, after the page's encoding.
triggers+=("${write_triggers[@]}" after:lightmap-0.exr after:bake.svit after:report.json)
# The bake's state into `state`: Z once it has ended, a zombie or gone
# (bash reaps its background jobs itself and keeps their status for wait).
alive() { read -r _ _ state _ 2>/dev/null <"/proc/$pid/stat" || state=Z; }
in_write=0 old=0 new=0
for trigger in "${triggers[@]}"; do
  rm -rf "$work/k_prev" && cp -r "$work/k" "$work/k_prev"
  "$bake" "$cornell" -o "$work/k" "${big[@]}" >/dev/null 2>"$work/kill_err.txt" &
  pid=$!
  staging="$work/k.tmp-$pid"
  # Polled without sleeping (milliseconds count) until the staging
  # directory or the file appears or the bake has ended.
  state=R
  if [[ $trigger == write+* ]]; then
    until [[ -e $staging || $state == Z ]]; do alive; done
    sleep "${trigger#write+}"
  elif [[ $trigger == after:* ]]; then
    file="$staging/${trigger#after:}"
    until [[ -e $file.tmp || -e $file || $state == Z ]]; do alive; done
  else
    sleep "$trigger"
  fi
  # Stopped first, to see which step of the write stage the kill lands at.
  kill -STOP $pid 2>/dev/null
  step=$(ls "$staging" 2>/dev/null | tr '\n' ' ')
  kill -KILL $pid 2>/dev/null
  wait $pid 2>/dev/null
  rc=$?
  state=$(classify "$work/k" "$work/k_prev" 2>&1)
  stage="before the write stage"
  [[ $state == new ]] && stage="after the swap"
  [[ -d $staging ]] && { stage="in the write stage, staging holds: ${step:-nothing yet}"; in_write=$((in_write + 1)); }
  [[ $rc -eq 0 ]] && stage="after the bake ended"
  if [[ $state == old || $state == new ]] && loads "$work/k"; then
    ok "kill at $trigger (exit $rc, $stage): OUT is the $state bake and loads"
    [[ $state == old ]] && old=$((old + 1)) || new=$((new + 1))
  else
    fail "kill at $trigger (exit $rc, $stage): OUT: $state $(cat "$work/probe_err.txt")"
  fi
done
echo "kills: ${#triggers[@]}, $in_write in the write stage; OUT old $old, new $new"
[[ $in_write -ge 3 ]] && ok "the write stage was hit ($in_write kills)" || fail "only $in_write kills in the write stage"

# (c) The next bake removes what killed bakes left, and nothing else: not a
# live process's staging (this shell's sleep), not a name that is no pid, not
# another OUT's. pid_max + 1 is never a live process.
dead=$(($(cat /proc/sys/kernel/pid_max) + 1))
sleep 120 &
sleeper=$!
mkdir -p "$work/k.tmp-$sleeper" "$work/k.old-$dead" "$work/k.tmp-$dead/sub" "$work/k.tmp-x1" "$work/kk.tmp-$dead"
echo "beside OUT before the next bake: $(leftovers k | tr '\n' ' ')"
"$bake" "$cornell" -o "$work/k" --quality 0.05 --texels-per-m 16 --seed 7 >"$work/out.txt" 2>"$work/err.txt"
rc=$?
[[ $rc -eq 0 ]] && loads "$work/k" && ok "the next bake succeeds" || { fail "the next bake: exit $rc"; cat "$work/err.txt"; }
[[ $(leftovers k | sort | tr '\n' ' ') == "$(printf '%s\n' "k.tmp-$sleeper" k.tmp-x1 | sort | tr '\n' ' ')" ]] \
  && ok "removed the dead bakes' directories, kept the live one's and the odd name" \
  || fail "left beside OUT: $(leftovers k | tr '\n' ' ')"
[[ -d "$work/kk.tmp-$dead" ]] && ok "another OUT's directory kept" || fail "removed another OUT's directory"
[[ $(grep -c "removed what killed bakes left: " "$work/err.txt") -eq 1 ]] && grep -q "k.old-$dead" "$work/err.txt" \
  && ok "said so in one line" || { fail "no one-line notice"; cat "$work/err.txt"; }
mkdir "$work/k.tmp-$dead"
"$bake" "$cornell" -o "$work/k" --quality 0.05 --texels-per-m 16 --seed 7 --quiet >"$work/out.txt" 2>"$work/err.txt"
[[ ! -s "$work/err.txt" && ! -e "$work/k.tmp-$dead" ]] && ok "--quiet removes without a word" \
  || fail "--quiet: $(cat "$work/err.txt")"

# (d) An OUT that is not a previous bake is refused before any work, untouched.
echo notes >"$work/file"
mkdir "$work/notes" && echo mine >"$work/notes/todo.txt"
for target in file notes file/sub; do
  "$bake" "$cornell" -o "$work/$target" "${small[@]}" >"$work/out.txt" 2>"$work/err.txt"
  rc=$?
  [[ $rc -eq 1 ]] && grep -q "$work/$target" "$work/err.txt" && ok "-o $target refused (exit 1): $(cat "$work/err.txt")" \
    || fail "-o $target: exit $rc $(cat "$work/err.txt")"
done
[[ $(cat "$work/file") == notes && $(cat "$work/notes/todo.txt") == mine && $(ls "$work/notes") == todo.txt ]] \
  && ok "refused outputs untouched" || fail "a refused output changed"
# A trailing slash names the same OUT (OUT/ once made OUT/.tmp-<pid> inside it).
"$bake" "$level" -o "$work/a/" "${small[@]}" >"$work/out.txt" 2>"$work/err.txt"
[[ $? -eq 0 && $(classify "$work/a" "$work/a_ref") == new && -z $(leftovers a) && $(ls -A "$work/a" | wc -l) -eq 3 ]] \
  && ok "-o OUT/ replaces OUT" || { fail "-o OUT/"; cat "$work/err.txt"; ls -A "$work/a"; }

if [[ $failures -ne 0 ]]; then echo "$failures failed"; exit 1; fi
echo "all svit-bake crash checks passed"
