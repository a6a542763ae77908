#!/usr/bin/env bash
# The long soak (issue 24): bakes the 2 x 2 house (samples/levels/house) as
# the GL tests do, runs bench_soak for FRAMES frames under Xvfb, twice with
# the same seed (the replay), and writes OUT/soak.json and OUT/soak.md, the
# tables (resources() totals, the heap glibc reports in use, the emitter
# records, and host bytes by resources() line) that it also puts into
# docs/bench/soak_bench.md between its soak_bench.sh markers
# (tests/bench/doc_section.py).
# usage: tests/bench/soak_bench.sh [BUILD_DIR] [OUT_DIR] [FRAMES]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${1:-$root/build/bench}"
out="${2:-$root/out/bench-soak}"
frames="${3:-20000}"
mkdir -p "$out"
level="$root/samples/levels/house/level.json"
if [[ ! -f "$out/bake/bake.svit" ]]; then
  "$build/baker/svit-bake" "$level" -o "$out/bake" --quality 0.2 --seed 7 --quiet
fi
status=0
xvfb-run -a -s "-screen 0 640x480x24" "$build/tests/bench/bench_soak" "$level" "$out/bake" \
  --frames "$frames" --sample-every 500 --json "$out/soak.json" | tee "$out/soak.log" || status=$?
python3 - "$out/soak.json" "$frames" >"$out/soak.md" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
s = r["samples"]
warm = s[max(0, len(s) // 10 - 1)]  # warm-up: the first tenth of the frames
last = s[-1]
peak_host = max(x["host_bytes"] for x in s[len(s) // 10:])
quarter = max(1, len(s) // 4)
early = sum(x["mean_frame_ms"] for x in s[len(s) // 10:len(s) // 10 + quarter]) / quarter
late = sum(x["mean_frame_ms"] for x in s[-quarter:]) / quarter
print(f"| frames | props added / removed | light changes | door moves | failures | replay at frame {sys.argv[2]} |")
print("|---|---|---|---|---|---|")
print(f"| {r['frames']} | {r['objects_added']} / {r['objects_removed']} | {r['light_changes']} | "
      f"{r['door_moves']} | {r['failure_count']} | "
      f"{'identical bit for bit' if r.get('replay_identical') else 'DIFFERS'} |")
print()
print("| after warm-up (frame %d) to the end | host (resources().cpu_bytes) | GPU (resources().gpu_bytes) | patches |" % warm["frame"])
print("|---|---|---|---|")
print(f"| at warm-up | {warm['host_bytes']:,} B | {warm['gpu_bytes']:,} B | {warm['patches']} |")
print(f"| at the end | {last['host_bytes']:,} B | {last['gpu_bytes']:,} B | {last['patches']} |")
print(f"| growth | {last['host_bytes'] - warm['host_bytes']:+,} B (peak after warm-up {peak_host:,} B) | "
      f"{last['gpu_bytes'] - warm['gpu_bytes']:+,} B | {last['patches'] - warm['patches']:+d} |")
print()
print("| after warm-up to the end | heap in use (mallinfo2 uordblks) | emitter records (emitterStates) |")
print("|---|---|---|")
print(f"| at warm-up | {warm['heap_bytes']:,} B | {warm['emitters']} |")
print(f"| at the end | {last['heap_bytes']:,} B | {last['emitters']} |")
print(f"| growth | {last['heap_bytes'] - warm['heap_bytes']:+,} B | {last['emitters'] - warm['emitters']:+d} |")
print()
print("| host bytes by resources() line | at warm-up | at the end | growth |")
print("|---|---|---|---|")
for name, before in warm["host_lines"].items():
    after = last["host_lines"].get(name, 0)
    print(f"| {name} | {before:,} B | {after:,} B | {after - before:+,} B |")
print()
print(f"Frame time (update(), llvmpipe): {early:.2f} ms per frame in the first quarter after warm-up, "
      f"{late:.2f} ms in the last ({(late / early - 1) * 100:+.1f} %).")
PY
cat "$out/soak.md"
python3 "$root/tests/bench/doc_section.py" "$root/docs/bench/soak_bench.md" soak_bench.sh "$out/soak.md"
exit $status
