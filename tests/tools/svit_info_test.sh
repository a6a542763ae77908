#!/usr/bin/env bash
# svit-info as a user runs it: output on good levels, exit codes on bad ones.
# usage: svit_info_test.sh SVIT_INFO CORNELL_GLTF TEST_DATA_DIR
set -u
info="$1" cornell="$2" data="$3"
failures=0
check() {  # check NAME EXPECTED_EXIT PATTERN -- command...
  local name="$1" want="$2" pattern="$3"
  shift 4
  local out rc
  out="$("$@" 2>&1)"
  rc=$?
  if [[ $rc -ne $want ]]; then
    echo "FAIL $name: exit $rc, expected $want"; echo "$out"; failures=$((failures + 1)); return
  fi
  if ! grep -qE -- "$pattern" <<<"$out"; then
    echo "FAIL $name: output lacks /$pattern/"; echo "$out"; failures=$((failures + 1)); return
  fi
  echo "ok   $name"
}
check cornell_text 0 '^triangles +36 \(36 static, 0 dynamic\)' -- "$info" "$cornell"
check cornell_emitters 0 '^emitters +2 emissive triangles' -- "$info" "$cornell"
check cornell_json 0 '"static": 36' -- "$info" "$cornell" --json
check json_parses 0 '^ok$' -- bash -c "'$info' '$cornell' --json | python3 -c 'import json,sys; d=json.load(sys.stdin); assert d[\"emitters\"][\"emissive_triangles\"]==2; print(\"ok\")'"
check missing_file 1 'no_such_level.gltf: file not found' -- "$info" "$data/no_such_level.gltf"
check bad_json 1 'bad_json.gltf' -- "$info" "$data/bad_json.gltf"
check no_arguments 2 'usage: svit-info' -- "$info"
check unknown_flag 2 "unexpected argument '--frobnicate'" -- "$info" "$cornell" --frobnicate
check help 0 'usage: svit-info' -- "$info" --help
if [[ $failures -ne 0 ]]; then echo "$failures failed"; exit 1; fi
echo "all svit-info checks passed"
