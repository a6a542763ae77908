#!/usr/bin/env bash
# The ball's shadow in the sun on Sponza, before and after shadow masks:
# bench_sun_shadow (tests/bench/sun_shadow_bench.cpp says what it measures)
# with the ball moved to BALL_X, then WORK/sun_shadow.json, the crops
# docs/images/sun-shadow-{reference,before,after}.png, WORK/sun_shadow.md and
# its tables in docs/bench/sun_shadow_bench.md, between its sun_shadow_bench.sh
# markers (tests/bench/doc_section.py). Builds nothing; headless
# under xvfb-run without a display. Bakes are kept in WORK and reused while
# their stamp matches. Skipped (and says so) without ../shared/scenes/sponza.
# usage: tests/bench/sun_shadow_bench.sh BUILD_DIR WORK [bake-seconds]
#   BUILD_DIR: a build with -DSVIT_BUILD_BENCH=ON (its tests/bench/bench_sun_shadow)
#   bake-seconds: time budget of each of the four Sponza bakes (default 150)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
usage="usage: sun_shadow_bench.sh BUILD_DIR WORK [bake-seconds]"
build="${1:?$usage}"
work="${2:?$usage}"
bake_s="${3:-150}"
ball_x="${BALL_X:--3.0177}"
bench="$build/tests/bench/bench_sun_shadow"
if [[ ! -f "$root/../shared/scenes/sponza/Sponza.gltf" ]]; then
  echo "sun_shadow_bench.sh: skipped (no ../shared/scenes/sponza)"
  exit 0
fi
[[ -x "$bench" ]] || { echo "sun_shadow_bench.sh: no $bench (configure with -DSVIT_BUILD_BENCH=ON)" >&2; exit 1; }
xvfb=()
[[ -z "${DISPLAY:-}" ]] && xvfb=(xvfb-run -a -s "-screen 0 1280x720x24")
mkdir -p "$work"
"${xvfb[@]}" "$bench" --level "$root/samples/levels/sponza/level.json" --work "$work" \
  --json "$work/sun_shadow.json" --time "$bake_s" --ball-x "$ball_x" \
  --png-prefix "$root/docs/images/sun-shadow" | tee "$work/sun_shadow.txt"
python3 - "$work/sun_shadow.json" "$work/sun_shadow.md" "$bake_s" "$ball_x" <<'PY'
import json, sys
path, out, bake_s, ball_x = sys.argv[1:5]
r = json.load(open(path))
pe, ed, cam = r["picture_error"], r["edges"], r["camera"]
f = lambda v: f"{v:.4f}"
v3 = lambda v: "(" + ", ".join(f"{x:.2f}" for x in v) + ")"
def edge(name):
    e = ed[name]
    if not e["shadow_found"]:
        return (f"no shadow (contrast {e['contrast']:.2f}); empty region: "
                f"{e['edge_error_cm_vs_reference']:.1f}", f"{e['edge_error_cm_vs_geometric']:.1f}")
    return f"{e['edge_error_cm_vs_reference']:.2f}", f"{e['edge_error_cm_vs_geometric']:.2f}"
rows = [("before: no masks, runtime settled", "before"), ("after: masks, runtime settled", "after"),
        ("before's bake, baked-only", "before_baked_only"), ("after's bake, baked-only", "after_baked_only"),
        ("second reference (noise floor)", "noise_floor")]
lines = [
    f"`tests/bench/sun_shadow_bench.sh build/bench /tmp/sunshadow {bake_s}` "
    f"({r['renderer']}, 2-core CPU; four Sponza bakes of {float(r['bake_time_s']):.0f} s, quality "
    f"{r['bake_quality']}, {r['bakes_wall_s']:.0f} s of baking in this run, 0 when reused). "
    f"The ball (radius {r['ball_radius_m']:.2f} m) moved from the level's start to "
    f"{v3(r['ball'])} on the sunlit atrium floor (y {r['floor_y_m']:.2f} m); the runtime of each "
    f"bake settled there as far as {r['settle']['max_updates']} updates of "
    f"{r['settle']['samples_per_update']} samples allow, for this view (before: "
    f"{r['settle']['before']['updates']} updates, {r['settle']['before']['pending']} emitters left "
    f"pending; after: {r['settle']['after']['updates']}, {r['settle']['after']['pending']} pending; "
    "unbounded, the ~15,000 emitters the ball reaches take over 10 minutes per bake on llvmpipe), "
    "runtime lights off. Reference: the baked view of a bake with the ball static there "
    "(seed 8); before: the dynamic level baked with `--no-shadow-masks`; after: with shadow "
    "masks (seed 7 both). Camera at " + v3(cam["position"]) + " looking at the shadow's centre "
    + v3(r["shadow_centre"]) + f" from the side away from the sun, "
    f"{cam['elevation_rad'] * 57.29578:.0f}° down, vertical field of view {cam['yfov_rad']:.2f} rad, "
    f"{cam['width']}×{cam['height']}.",
    "",
    "(a) Relative RMS of the luminance difference (tests/runtime/picture_metric.h) over static pixels, "
    f"split by the shadow's footprint: the {r['footprint_pixels']} pixels where the reference is "
    f"darker by more than {100 * r['footprint_darkening']:.0f} % than the picture without that "
    "shadow (the no-masks bake's baked view, its ball far away at the start).",
    "",
    "| picture against the reference | inside the footprint | outside | whole view |",
    "|---|---:|---:|---:|",
]
for label, key in rows:
    s = pe[key]
    lines.append(f"| {label} | {f(s['inside']['rel_rms'])} | {f(s['outside']['rel_rms'])} | {f(s['all']['rel_rms'])} |")
lines += [
    "",
    "(b) The shadow's edge on the floor: a grid of "
    f"{1000 * r['grid_step_m']:.0f} mm cells projected into each picture ({r['grid_points_seen']} "
    "points seen; those the ball hides left out), each picture divided by the picture without the "
    "shadow and thresholded half way between its lit level (a ring just outside the geometric "
    "shadow) and its shadowed level (the geometric shadow's core). Edge error = area of the XOR of "
    "the two shadow regions / contour length of the reference's (or the geometric shadow's) region, "
    f"cm. Reference region {r['reference_shadow_area_cm2']:.0f} cm², contour "
    f"{r['reference_contour_cm']:.0f} cm; geometric shadow (rays to the sun's centre meeting the "
    f"ball) {r['geometric_shadow_area_cm2']:.0f} cm², contour {r['geometric_contour_cm']:.0f} cm "
    "(visible parts).",
    "",
    "| picture | shadow contrast | edge error against the reference (cm) | against the geometric shadow (cm) |",
    "|---|---:|---:|---:|",
]
for label, key in [("before: no masks, runtime settled", "before"), ("after: masks, runtime settled", "after"),
                   ("second reference (noise floor)", "second reference"), ("reference", "reference")]:
    a, b = edge(key)
    lines.append(f"| {label} | {ed[key]['contrast']:.2f} | {a} | {b} |")
c = r["at_centre_lux"]
texel_cm = 100 / c["texels_per_m"]
lines += [
    "",
    "(c) Irradiance at the shadow's centre and on the sunlit floor "
    f"{2 * r['ball_radius_m']:.1f} m beside it (luminance, lux; `Runtime::irradianceAt`, the "
    "reference through svit-probe). These bakes spread about 256 k texels over the whole level: "
    f"{c['texels_per_m']:.2f} texels per metre, a texel {texel_cm:.0f} cm, as wide as the ball's "
    "radius.",
    "",
    "| | shadow's centre | sunlit floor beside it | centre / sunlit |",
    "|---|---:|---:|---:|",
    f"| reference (ball static there) | {c['reference']:.0f} | {c['lit_reference']:.0f} | "
    f"{c['reference'] / c['lit_reference']:.3f} |",
    f"| before, settled | {c['before_settled']:.0f} | {c['lit_before']:.0f} | "
    f"{c['before_settled'] / c['lit_before']:.3f} |",
    f"| after: its lightmap alone (sky and bounce, as baked without the ball) | "
    f"{c['after_lightmap_alone']:.0f} | | {c['after_lightmap_alone'] / c['lit_after']:.3f} |",
    f"| after, settled | {c['after_settled']:.0f} | {c['lit_after']:.0f} | "
    f"{c['after_settled'] / c['lit_after']:.3f} |",
    "",
    "How to read it. A lightmap texel as wide as the ball's radius cannot hold the ball's shadow: "
    "the reference averages it with the sunlit floor around it, so it shows a faint, wide "
    f"darkening rather than a shadow ({c['reference'] / c['lit_reference']:.2f} of the sunlit "
    f"floor at the centre, {ed['reference']['shadowed_ratio']:.2f} in the geometric shadow's core "
    "in (b)). "
    "The after picture's umbra is as dark as the baked sky and bounce "
    "light under the ball, because those are all the light left when the sun is blocked: the "
    "masked bake's lightmap there, with no sun in it, is the smooth part of the light, which 30 cm "
    "texels do hold. The settled runtime changes it very little. The true umbra lies between "
    "the two: what a finer reference would add to the after picture's is the light the ball "
    "itself reflects onto the floor under it (and take the sky it hides), which the runtime "
    "spreads over whole patches. The geometric shadow is the sharper truth for the edge.",
    "",
    "Reference, before and after (the view's central half):",
    "",
    "![reference](../images/sun-shadow-reference.png) ![before](../images/sun-shadow-before.png) "
    "![after](../images/sun-shadow-after.png)",
]
section = "\n".join(lines) + "\n"
open(out, "w").write(section)
print(section)
PY
python3 "$root/tests/bench/doc_section.py" "$root/docs/bench/sun_shadow_bench.md" sun_shadow_bench.sh "$work/sun_shadow.md"
echo "sun_shadow_bench.sh: wrote $work/sun_shadow.json, docs/images/sun-shadow-*.png and docs/bench/sun_shadow_bench.md's tables"
