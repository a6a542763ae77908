#!/usr/bin/env bash
# svit-bake and svit-probe as users script them (docs/architecture.md "Command-line
# contracts"): outputs, exit codes, cancellation, atomic output, determinism.
# usage: svit_bake_test.sh SVIT_BAKE SVIT_PROBE CORNELL_GLTF TEST_DATA_DIR
set -u
bake="$1" probe="$2" cornell="$3" data="$4"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
failures=0
fail() { echo "FAIL $*"; failures=$((failures + 1)); }
ok() { echo "ok   $*"; }
expect_exit() {  # NAME WANT -- command...
  local name="$1" want="$2"; shift 3
  "$@" >"$work/out.txt" 2>"$work/err.txt"
  local rc=$?
  if [[ $rc -eq $want ]]; then ok "$name"; else fail "$name: exit $rc, expected $want"; cat "$work/err.txt"; fi
}

# Bad usage: exit 2 with a message.
expect_exit no_arguments 2 -- "$bake"
expect_exit no_output 2 -- "$bake" "$cornell"
expect_exit bad_quality 2 -- "$bake" "$cornell" -o "$work/x" --quality 7
expect_exit bad_time 2 -- "$bake" "$cornell" -o "$work/x" --time -1
expect_exit bad_texels 2 -- "$bake" "$cornell" -o "$work/x" --texels-per-m abc
expect_exit unknown_option 2 -- "$bake" "$cornell" -o "$work/x" --frobnicate
grep -q "unknown option '--frobnicate'" "$work/err.txt" || fail "unknown option message"
expect_exit plan_without_masks 2 -- "$bake" plan "$cornell" -o "$work/x" --shards 2 --no-shadow-masks
grep -q "no-shadow-masks is for whole bakes only" "$work/err.txt" || fail "plan --no-shadow-masks message"
expect_exit plan_without_filter 2 -- "$bake" plan "$cornell" -o "$work/x" --shards 2 --no-filter
grep -q "no-filter is for whole bakes only" "$work/err.txt" || fail "plan --no-filter message"
# Bad input: exit 1, message names the file.
expect_exit missing_level 1 -- "$bake" "$work/nope.gltf" -o "$work/x"
grep -q "nope.gltf" "$work/err.txt" || fail "missing level message names the file"
expect_exit malformed_level 1 -- "$bake" "$data/bad_json.gltf" -o "$work/x"
[[ ! -e "$work/x" ]] && ok "failed bakes write nothing" || fail "a failed bake left $work/x"

# A good bake, quiet: nothing on stdout, the three kinds of output.
expect_exit bake 0 -- "$bake" "$cornell" -o "$work/a" --quality 0.2 --texels-per-m 24 --seed 7 --quiet
[[ ! -s "$work/out.txt" ]] && ok "quiet prints nothing" || fail "--quiet printed: $(cat "$work/out.txt")"
for f in bake.svit lightmap-0.exr report.json; do
  [[ -f "$work/a/$f" ]] && ok "wrote $f" || fail "missing $f"
done
python3 - "$work/a/report.json" <<'PY' && ok "report.json fields" || fail "report.json fields"
import json, os, sys
r = json.load(open(sys.argv[1]))
for key in ("stage_seconds", "radiosity", "lightmap", "warnings", "error_vs_time", "sections_left_out"):
    assert key in r, key
assert r["radiosity"]["rays_per_s"] > 0
assert len(r["error_vs_time"]) >= 2 and all("t_s" in p and "est_rel_error" in p for p in r["error_vs_time"])
assert r["lightmap"]["covered_texels"] > 0
assert {s["section"] for s in r["sections_left_out"]} >= {"patches", "proxy", "probes"}
# The audit's section sizes add up to the file: 16-byte header, 12 bytes per
# section entry, 8-byte checksum.
written = r["sections_written"]
assert [s["section"] for s in written] == ["header", "pages", "triangle_uvs"], written
assert all(s["bytes"] > 0 and s["holds"] for s in written), written
size = os.path.getsize(os.path.join(os.path.dirname(sys.argv[1]), "bake.svit"))
assert sum(s["bytes"] for s in written) + 16 + 12 * len(written) + 8 == size, (written, size)
PY
# Determinism: the same seed gives identical files.
expect_exit bake_again 0 -- "$bake" "$cornell" -o "$work/b" --quality 0.2 --texels-per-m 24 --seed 7 --quiet --threads 1
cmp -s "$work/a/lightmap-0.exr" "$work/b/lightmap-0.exr" && ok "same seed, same EXR bytes (1 vs all threads)" || fail "EXR differs between runs"
cmp -s "$work/a/bake.svit" "$work/b/bake.svit" && ok "same seed, same bake.svit" || fail "bake.svit differs"
# --no-filter: the same texels, the gathered light left unfiltered; the
# report says which, and with what strength it filtered. The filter needs
# four passes (two a half); with fewer a bake is unfiltered either way.
expect_exit bake_filtered 0 -- "$bake" "$cornell" -o "$work/f4" --passes 4 --quality 0.2 --texels-per-m 24 --seed 7 --quiet
expect_exit bake_unfiltered 0 -- "$bake" "$cornell" -o "$work/raw" --passes 4 --quality 0.2 --texels-per-m 24 --seed 7 --quiet --no-filter
cmp -s "$work/f4/lightmap-0.exr" "$work/raw/lightmap-0.exr" && fail "--no-filter changed nothing" || ok "--no-filter pages differ"
python3 -c "import json; a = json.load(open('$work/f4/report.json'))['lightmap']; r = json.load(open('$work/raw/report.json'))['lightmap']; assert a['indirect_filter'] is True and r['indirect_filter'] is False and a['covered_texels'] == r['covered_texels']; assert a['filter_noise_sigmas'] in (0.75, 1.0, 1.5, 2.0) and r['filter_noise_sigmas'] is None, (a, r)" &&
  ok "report.json says whether the indirect light was filtered" || fail "report.json indirect_filter"

# Progress: plain lines when stderr is not a terminal.
expect_exit bake_progress 0 -- "$bake" "$cornell" -o "$work/c" --quality 0.1 --texels-per-m 16
grep -q "svit-bake: radiosity" "$work/err.txt" && ok "progress lines" || fail "no progress lines"
grep -q "^baked " "$work/out.txt" && ok "summary line" || fail "no summary line"

# Cancellation: SIGTERM mid-bake exits 3 and leaves the previous bake intact.
cp -r "$work/a" "$work/keep"
"$bake" "$cornell" -o "$work/a" --quality 1 --texels-per-m 64 --quiet &
pid=$!
sleep 1.5
kill -TERM $pid
wait $pid
rc=$?
[[ $rc -eq 3 ]] && ok "SIGTERM exits 3" || fail "SIGTERM exit $rc"
diff -r -q "$work/a" "$work/keep" >/dev/null && ok "cancelled bake left the previous output intact" || fail "output changed by a cancelled bake"
ls "$work" | grep -q "tmp-" && fail "temporary directory left behind" || ok "no temporary directory left"
# A killed bake (SIGKILL: no chance to clean up) leaves the previous bake intact too.
"$bake" "$cornell" -o "$work/a" --quality 1 --texels-per-m 64 --quiet &
pid=$!
sleep 1.5
kill -KILL $pid
wait $pid 2>/dev/null
diff -r -q "$work/a" "$work/keep" >/dev/null && ok "killed bake left the previous output intact" || fail "output changed by a killed bake"
rm -rf "$work"/a.tmp-*

# Probe: 'r g b' per line, --json, bad input.
printf '0 0 0 0 1 0\n# a comment\n\n0 1.98 0 0 -1 0\n' >"$work/points.txt"
expect_exit probe 0 -- "$probe" "$work/a" "$work/points.txt"
[[ $(wc -l <"$work/out.txt") -eq 2 ]] && ok "probe prints one line per point" || fail "probe output: $(cat "$work/out.txt")"
awk 'NF != 3 { exit 1 }' "$work/out.txt" && ok "probe lines are r g b" || fail "probe lines"
expect_exit probe_json 0 -- "$probe" "$work/a" "$work/points.txt" --json
python3 -c "import json,sys; assert len(json.load(open('$work/out.txt'))) == 2" && ok "probe --json parses" || fail "probe --json"
printf '0 0 zero 0 1 0\n' >"$work/bad_points.txt"
expect_exit probe_bad_points 1 -- "$probe" "$work/a" "$work/bad_points.txt"
grep -q "bad_points.txt:1" "$work/err.txt" && ok "bad point line named" || fail "bad point message"
expect_exit probe_no_bake 1 -- "$probe" "$work/nothing" "$work/points.txt"
expect_exit probe_usage 2 -- "$probe" "$work/a"
# A corrupt bake file is rejected.
cp -r "$work/a" "$work/corrupt"
printf 'garbage' | dd of="$work/corrupt/bake.svit" bs=1 seek=20 conv=notrunc status=none
expect_exit probe_corrupt 1 -- "$probe" "$work/corrupt" "$work/points.txt"

# A glTF with no light source (most glTF files carry none): the bake works,
# warns on stderr and in report.json, and every page's EXR says why it is
# black (its "comments" attribute).
expect_exit unlit 0 -- "$bake" "$data/good_quad.gltf" -o "$work/unlit" --passes 1
grep -q "svit-bake: warning: .*good_quad.gltf: no light source to bake" "$work/err.txt" \
  && ok "no-light warning on stderr" || { fail "no-light warning on stderr"; cat "$work/err.txt"; }
python3 - "$work/unlit" <<'PY' && ok "no-light warning in report.json and the EXR" || fail "no-light warning in report and EXR"
import json, sys
out = sys.argv[1]
assert any("no light source to bake" in w for w in json.load(open(f"{out}/report.json"))["warnings"])
exr = open(f"{out}/lightmap-0.exr", "rb").read()
at = exr.index(b"comments\0string\0")
assert b"no light source to bake" in exr[at:at + 120], exr[at:at + 120]
PY
expect_exit lit_quiet 0 -- "$bake" "$cornell" -o "$work/lit" --quality 0.05 --passes 1 --texels-per-m 8
grep -q "no light source" "$work/err.txt" && fail "a lit level warned of no light" || ok "a lit level does not warn"

# --sun / --sky give a bare glTF its sun and sky: the bake lights the quad and
# writes OUT/level.json, the level it baked (svit_walk.tool walks one).
sun='{"direction_to_sun": [0.3, 1, 0.2], "illuminance_lux": 100000}'
sky='{"model": "uniform", "zenith_luminance": [3000, 3000, 3000]}'
expect_exit sun_and_sky 0 -- "$bake" "$data/good_quad.gltf" -o "$work/sunlit" --passes 1 --sun "$sun" --sky "$sky"
grep -q "no light source" "$work/err.txt" && fail "--sun still warned of no light" || ok "--sun lights the level"
grep -q "sunlit/level.json: walk that one" "$work/out.txt" && ok "says which level it baked" || fail "no level.json line"
python3 - "$work/sunlit" "$data/good_quad.gltf" <<'PY' && ok "OUT/level.json names the glTF, sun and sky" || fail "OUT/level.json"
import json, os, sys
level = json.load(open(f"{sys.argv[1]}/level.json"))
assert level["gltf"] == os.path.abspath(sys.argv[2]), level["gltf"]
assert level["sun"]["illuminance_lux"] == 100000 and level["sky"]["model"] == "uniform", level
PY
# svit-probe reads the bake's level from report.json: OUT/level.json, whose
# hash is the bake's (the bare glTF alone would be "changed since baked").
printf '0 0 0 0 1 0\n' >"$work/up.txt"
expect_exit probe_sunlit 0 -- "$probe" "$work/sunlit" "$work/up.txt"
awk '$2 > 0 { found = 1 } END { exit !found }' "$work/out.txt" && ok "the sunlit quad probes lit" || fail "sunlit probe: $(cat "$work/out.txt")"
# Bad --sun / --sky: exit 2, naming the option and the field or value.
bad_sun() {  # NAME WANT-TEXT ARGS...
  local name="$1" text="$2"; shift 2
  expect_exit "$name" 2 -- "$bake" "$@" -o "$work/x"
  grep -qF -- "$text" "$work/err.txt" && ok "$name message" || { fail "$name message lacks '$text'"; cat "$work/err.txt"; }
}
bad_sun sun_not_json "--sun: not valid JSON" "$data/good_quad.gltf" --sun '{"illuminance_lux": '
bad_sun sun_no_lux "--sun: sun.illuminance_lux: is required" "$data/good_quad.gltf" --sun '{"direction_to_sun": [0, 1, 0]}'
bad_sun sun_unknown_field "--sun: sun.lux: unknown field" "$data/good_quad.gltf" --sun '{"lux": 5}'
bad_sun sky_bad_model "--sky: sky.model: 'cloudy'" "$data/good_quad.gltf" --sky '{"model": "cloudy"}'
bad_sun sun_on_level_json "--sun is for a bare glTF" "$data/good_level.json" --sun "$sun"
expect_exit sun_no_value 2 -- "$bake" "$data/good_quad.gltf" -o "$work/x" --sun
grep -qF -- "--sun needs a JSON object" "$work/err.txt" && ok "sun_no_value message" || fail "sun_no_value message"
bad_sun plan_with_sun "--sun and --sky are for whole bakes" plan "$data/good_quad.gltf" --shards 2 --passes 1 \
  --sun "$sun"
[[ ! -e "$work/x" ]] && ok "refused --sun/--sky write nothing" || fail "a refused bake left $work/x"

if [[ $failures -ne 0 ]]; then echo "$failures failed"; exit 1; fi
echo "all svit-bake / svit-probe checks passed"
