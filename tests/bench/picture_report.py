#!/usr/bin/env python3
"""Writes the tables of docs/bench/picture_bench.md and its plot
(docs/images/picture_error.svg) from bench_picture JSON files.

usage: picture_report.py DOC SVG RUN.json [RUN.json ...]

The tables go between DOC's `<!-- picture_report.py: begin -->` and
`<!-- picture_report.py: end -->` markers (doc_section.py); the rest of DOC
is kept. The plot is SVG drawn here (no plotting library needed): per
level, the runtime view's static error (solid) and the baked-only view's
(dashed) at the reference frames."""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from doc_section import put_section  # noqa: E402

NAME = "picture_report.py"
COLOURS = ["#c0392b", "#2471a3", "#1e8449", "#7d3c98"]


def reference_rows(run):
    return [f for f in run["frames"] if "runtime" in f]


def level_name(run):
    return run["level"].rstrip("/").split("/")[-2]


def svg_plot(runs, width=640, height=300, margin=48):
    rows = [(run, reference_rows(run)) for run in runs]
    max_t = max((f["t_s"] for _, fs in rows for f in fs), default=1) or 1
    max_e = max((max(f["runtime"]["static_rel_rms"], f["baked_only"]["static_rel_rms"])
                 for _, fs in rows for f in fs), default=1) or 1
    def x(t):
        return margin + (width - 2 * margin) * t / max_t
    def y(e):
        return height - margin - (height - 2 * margin) * e / max_e
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" font-family="sans-serif" font-size="11">',
           f'<rect width="{width}" height="{height}" fill="white"/>',
           f'<line x1="{margin}" y1="{height - margin}" x2="{width - margin}" y2="{height - margin}" stroke="black"/>',
           f'<line x1="{margin}" y1="{margin}" x2="{margin}" y2="{height - margin}" stroke="black"/>',
           f'<text x="{width / 2}" y="{height - 12}" text-anchor="middle">walk time, s (frame / 30)</text>',
           f'<text x="14" y="{height / 2}" transform="rotate(-90 14 {height / 2})" text-anchor="middle">'
           'static-surface error (RMS / mean)</text>']
    for k in range(5):
        e = max_e * k / 4
        out.append(f'<text x="{margin - 4}" y="{y(e) + 4:.1f}" text-anchor="end">{e:.2f}</text>')
    for i, (run, fs) in enumerate(rows):
        colour = COLOURS[i % len(COLOURS)]
        for key, dash in (("runtime", ""), ("baked_only", ' stroke-dasharray="5,4"')):
            points = " ".join(f"{x(f['t_s']):.1f},{y(f[key]['static_rel_rms']):.1f}" for f in fs)
            out.append(f'<polyline points="{points}" fill="none" stroke="{colour}" stroke-width="2"{dash}/>')
        label_y = margin + 14 * i
        out.append(f'<text x="{width - margin}" y="{label_y}" text-anchor="end" fill="{colour}">'
                   f'{level_name(run)}: runtime (solid), baked only (dashed)</text>')
    out.append("</svg>")
    return "\n".join(out) + "\n"


def table(run):
    lines = ["| frame | t (s) | runtime static | baked-only static | objects, runtime | objects, baked-only | pending |",
             "|---:|---:|---:|---:|---:|---:|---:|"]
    for f in reference_rows(run):
        r, b = f["runtime"], f["baked_only"]
        lines.append(f"| {f['frame']} | {f['t_s']:.2f} | {r['static_rel_rms']:.4f} | {b['static_rel_rms']:.4f} | "
                     f"{100 * r['dynamic_mean_error']:+.1f} % | {100 * b['dynamic_mean_error']:+.1f} % | {f['pending']} |")
    return "\n".join(lines)


def section(runs, svg_link):
    parts = ["Per reference frame, the runtime view and the baked-only view (doing nothing at run time) against "
             "the baked view of a bake in which every dynamic object is static where it is at that frame, in "
             "linear radiance from the renderer's float target: RMS of the luminance difference over static "
             "pixels relative to the reference's mean, and the dynamic objects' mean luminance against the "
             "reference's over their pixels. Runtime lights off (neither bake has them).", "",
             f"![picture error against walk time]({svg_link})", ""]
    for run in runs:
        parts += [f"## {level_name(run)} ({run['renderer']})", "",
                  f"{run['samples_per_frame']} samples a frame; bakes at quality {run['bake_quality']}, "
                  f"{run['bake_time_s']} s; ready {run['create_ms']:.0f} ms after load, first frame "
                  f"{run['first_frame_ms']:.0f} ms, mean frame {run['mean_frame_ms']:.0f} ms.", "",
                  table(run), ""]
    return "\n".join(parts)


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    doc, svg = sys.argv[1], sys.argv[2]
    runs = [json.load(open(path)) for path in sys.argv[3:]]
    with open(svg, "w") as f:
        f.write(svg_plot(runs))
    svg_link = os.path.relpath(os.path.abspath(svg), os.path.dirname(os.path.abspath(doc)))
    put_section(doc, NAME, section(runs, svg_link))


if __name__ == "__main__":
    main()
