#!/usr/bin/env bash
# Remakes the committed Mitsuba references of tests/reference/results/ (run
# once; CI only reads them): the double-sided Cornell box at 2^22 samples a
# probe and the furnace at 2^20, each from seeds 1 and 2. About 6 minutes on
# the 2-core machine. Needs `scripts/setup --reference`.
# usage: tests/reference/make_references.sh
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
python="${SVIT_REFERENCE_PYTHON:-$here/../../build/reference-venv/bin/python}"
if ! "$python" -c "import mitsuba" 2>/dev/null; then
  echo "make_references: no Mitsuba at $python (run scripts/setup --reference)" >&2
  exit 2
fi
"$python" "$here/mitsuba_irradiance.py" "$here/levels/cornell_double_sided.gltf" \
  "$here/probes_cornell.txt" -o "$here/results/cornell_double_sided.json" --spp 4194304
"$python" "$here/mitsuba_irradiance.py" "$here/levels/furnace.gltf" \
  "$here/probes_furnace.txt" -o "$here/results/furnace.json" --spp 1048576
