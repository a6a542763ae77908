#!/usr/bin/python3
"""Error against time for the baker and the runtime (issue 8).

Usage: error_vs_time.py OUT_DIR   (run by tests/bench/error_vs_time.sh)

Reads, under OUT_DIR:
  baker/LEVEL/runs.tsv             bake directory name, wall seconds of the process
  baker/LEVEL/reference/report.json      the long bake (seed 2)
  baker/LEVEL/reference-2/report.json    optional: a second one (seed 3) baked
                                   with --reference against the first
  baker/LEVEL/tT/report.json       bakes at --time T (seed 1) with --reference
  runtime/LEVEL.json               bench_runtime_error's output
  load.txt                         CPU and load averages
and writes results.json, results.md, error-vs-time-baker.png and
error-vs-time-runtime.png.

Baker error: the last entry of report.json's error_vs_time, i.e. after the
final lighting pass: est_rel_error (the baker's own estimate: spread between
lighting passes; a bake with a single pass has none, reported as 1) and
ref_rel_error (texel-wise RMS relative error of the bake's pages against
the reference's, at its covered texels; before 2026-12, raw texel means
against the reference's filtered pages, which counted the filter). The
reference is noisy too: with independent seeds, measured^2 = true^2 +
ref^2, and the gap between two references is sqrt(2) ref. Both the measured
error and the error with ref removed in quadrature are tabulated; time to
5/2/1% is log-log interpolated between bakes.

Runtime error: RMS difference of luminance at probe points relative to the
reference's mean, against the cumulative wall time of update() calls.
"""

import json
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cycles_compare import crossing  # noqa: E402  (time to an error, log-log interpolated)

TARGETS = (0.05, 0.02, 0.01)
NAMES = {"cornell": "Cornell box", "house": "house (2x2 rooms)", "sponza": "Sponza + sun + sky"}
COLOURS = {"cornell": "tab:red", "house": "tab:blue", "sponza": "tab:green"}


def final(report):
    """(est, ref) after the last lighting pass; est None when there is none."""
    last = report["error_vs_time"][-1]
    est = last["est_rel_error"]
    return (est if est is not None and est < 0.999 else None), last.get("ref_rel_error")


def read_json(path):
    with open(path) as f:
        return json.load(f)


def baker_level(level_dir):
    walls = {}
    with open(os.path.join(level_dir, "runs.tsv")) as f:
        for line in f:
            if line.strip() and not line.startswith("#"):
                name, wall = line.split("\t")
                walls[name] = float(wall)
    ref_report = read_json(os.path.join(level_dir, "reference", "report.json"))
    out = {"reference": {"wall_s": walls.get("reference"), "time_budget_s": ref_report["time_budget_s"],
                         "est_rel_error": final(ref_report)[0], "lighting_passes": ref_report["lightmap"]["lighting_passes"],
                         "covered_texels": ref_report["lightmap"]["covered_texels"]}}
    noise = None
    pair_path = os.path.join(level_dir, "reference-2", "report.json")
    if os.path.exists(pair_path):
        pair = read_json(pair_path)
        gap = final(pair)[1]
        out["reference"]["gap_between_references"] = gap
        # Its passes against the first reference: a long bake's own curve (in-bake seconds).
        out["reference"]["pair_passes"] = [e for e in pair["error_vs_time"] if e.get("ref_rel_error") is not None]
        noise = gap / math.sqrt(2)
    out["reference"]["noise"] = noise
    bakes = []
    for name, wall in walls.items():
        if not name.startswith("t"):
            continue
        report = read_json(os.path.join(level_dir, name, "report.json"))
        est, ref = final(report)
        bakes.append({"time_budget_s": report["time_budget_s"], "wall_s": wall, "bake_total_s": report["total_seconds"],
                      "lighting_passes": report["lightmap"]["lighting_passes"], "est_rel_error": est, "ref_rel_error": ref,
                      "ref_rel_error_noise_removed": (math.sqrt(max(ref * ref - noise * noise, 0.0)) if noise else None),
                      "curve": report["error_vs_time"]})
    bakes.sort(key=lambda b: b["time_budget_s"])
    out["bakes"] = bakes
    t = [b["wall_s"] for b in bakes]
    out["time_to"] = {}
    for target in TARGETS:
        key = "%g%%" % (100 * target)
        out["time_to"][key] = {
            "measured": crossing(t, [b["ref_rel_error"] for b in bakes], target),
            "noise_removed": crossing(t, [b["ref_rel_error_noise_removed"] for b in bakes], target) if noise else None,
            "first_bake": bakes[0]["wall_s"] if bakes else None}
    out["floor"] = min(b["ref_rel_error"] for b in bakes) if bakes else None
    return out


def fmt_time(value, level, key, column):
    if value is None:
        floor = level["floor"] if column == "measured" else min(
            b["ref_rel_error_noise_removed"] for b in level["bakes"])
        return "not reached (floor %.2f%%)" % (100 * floor)
    if abs(value - level["time_to"][key]["first_bake"]) < 1e-9:
        return "<= %.1f s (first bake)" % value
    return "%.1f s" % value


def pct(x):
    return "n/a" if x is None else "%.2f%%" % (100 * x)


def plain_ticks(ax):
    """Percent and seconds as plain numbers on log axes."""
    from matplotlib.ticker import FuncFormatter
    for axis in (ax.xaxis, ax.yaxis):
        axis.set_major_formatter(FuncFormatter(lambda v, _: "%g" % v))
        axis.set_minor_formatter(FuncFormatter(lambda v, _: "%g" % v if str("%g" % v)[0] in "1235" else ""))


def plot_baker(results, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(8, 5.5))
    for level, r in results.items():
        c = COLOURS.get(level, "black")
        t = [b["wall_s"] for b in r["bakes"]]
        ax.plot(t, [100 * b["ref_rel_error"] for b in r["bakes"]], "o-", color=c,
                label="%s: true (against reference)" % NAMES.get(level, level))
        for bake in r["bakes"]:  # --time of each bake (wall time is more under load, and not monotonic)
            ax.annotate("%g" % bake["time_budget_s"], (bake["wall_s"], 100 * bake["ref_rel_error"]), fontsize=6,
                        xytext=(3, 4), textcoords="offset points", color=c)
        est = [(b["wall_s"], 100 * b["est_rel_error"]) for b in r["bakes"] if b["est_rel_error"] is not None]
        if est:
            ax.plot(*zip(*est), "x--", color=c, label="%s: estimated" % NAMES.get(level, level))
        if r["reference"]["noise"]:
            ax.axhline(100 * r["reference"]["noise"], color=c, linestyle=":", linewidth=1)
        passes = r["reference"].get("pair_passes")
        if passes:
            ax.plot([e["t_s"] for e in passes], [100 * e["ref_rel_error"] for e in passes], "s-", color=c,
                    alpha=0.45, markersize=4, linewidth=1,
                    label="%s: 2nd reference's passes vs the 1st (in-bake s)" % NAMES.get(level, level))
    for target in TARGETS:
        ax.axhline(100 * target, color="grey", linewidth=0.6, alpha=0.6)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("bake wall time, whole process (s)")
    ax.set_ylabel("RMS relative error of lightmap texels (%)")
    ax.set_title("svit-bake: error against time (labels: --time; dotted: reference's own noise)", fontsize=10)
    plain_ticks(ax)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def plot_runtime(results, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    levels = list(results)
    fig, axes = plt.subplots(1, len(levels), figsize=(5 * len(levels), 4.6), squeeze=False)
    for ax, level in zip(axes[0], levels):
        r = results[level]
        cmap = plt.get_cmap("viridis")
        runs = r["runs"]
        for i, run in enumerate(runs):
            # Frames after the runtime went idle add no time: one point for them.
            pts = [(t, 100 * e) for k, (t, e) in enumerate(zip(run["t_s"], run["rms_rel_error"]))
                   if k >= 1 and t > run["t_s"][k - 1]]
            unlimited = run["budget_ms"] <= 0
            label = "no budget" if unlimited else "budget %g ms" % run["budget_ms"]
            ax.plot(*zip(*pts), "*-" if unlimited else "o-", markersize=11 if unlimited else 3,
                    color="tab:orange" if unlimited else cmap(i / max(1, len(runs) - 1) * 0.8), label=label)
        settled = r.get("settled_after_budget")  # --one-settle: update(0) after the budgeted frames
        if settled:
            ax.plot([settled["t_s"]], [100 * settled["rms_rel_error"]], "*", markersize=11, color="tab:orange",
                    label="then update(0): settled")
        before = runs[0]["rms_rel_error"][0]
        ax.axhline(100 * before, color="black", linestyle="--", linewidth=1, label="before any update")
        ax.axhline(100 * r["rest_vs_start_bake"], color="grey", linestyle=":", linewidth=1,
                   label="settled at the start vs its static bake")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("cumulative update() wall time (s)")
        ax.set_ylabel("RMS relative error at %d probes (%%)" % r["probes"])
        ax.set_title("%s: %s moved" % (NAMES.get(level, level), r["node"]), fontsize=10)
        plain_ticks(ax)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    fig.suptitle("runtime against a bake with the object static at its new place (Mesa llvmpipe)", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=100)


def main():
    out = sys.argv[1]
    baker, runtime = {}, {}
    for level in ("cornell", "house", "sponza"):
        if os.path.exists(os.path.join(out, "baker", level, "runs.tsv")):
            baker[level] = baker_level(os.path.join(out, "baker", level))
        if os.path.exists(os.path.join(out, "runtime", level + ".json")):
            runtime[level] = read_json(os.path.join(out, "runtime", level + ".json"))
    with open(os.path.join(out, "load.txt")) as f:
        load = f.read()
    md = ["# Error against time", "", "Load averages (1/5/15 min) during the run:", "", "```", load.strip(), "```", ""]
    if baker:
        md += ["## Baker", "", "| level | --time (s) | wall (s) | passes | estimated | true | true, ref. noise removed |",
               "|---|---:|---:|---:|---:|---:|---:|"]
        for level, r in baker.items():
            for b in r["bakes"]:
                md.append("| %s | %g | %.1f | %d | %s | %s | %s |" % (
                    level, b["time_budget_s"], b["wall_s"], b["lighting_passes"], pct(b["est_rel_error"]),
                    pct(b["ref_rel_error"]), pct(b["ref_rel_error_noise_removed"])))
        md += ["", "| level | reference --time (s) | wall (s) | its estimate | gap to a 2nd reference | its noise (gap/sqrt 2) |",
               "|---|---:|---:|---:|---:|---:|"]
        for level, r in baker.items():
            ref = r["reference"]
            md.append("| %s | %g | %.1f | %s | %s | %s |" % (level, ref["time_budget_s"], ref["wall_s"] or 0,
                                                           pct(ref["est_rel_error"]), pct(ref.get("gap_between_references")),
                                                           pct(ref["noise"])))
        md += ["", "Second reference, pass by pass, against the first (in-bake seconds; both equally noisy):", "",
               "| level | t (s) | estimated | against the first reference |", "|---|---:|---:|---:|"]
        for level, r in baker.items():
            for e in r["reference"].get("pair_passes") or []:
                md.append("| %s | %.1f | %s | %s |" % (level, e["t_s"], pct(final({"error_vs_time": [e]})[0]),
                                                      pct(e["ref_rel_error"])))
        md += ["", "| level | error | time (measured) | time (ref. noise removed) |", "|---|---:|---:|---:|"]
        for level, r in baker.items():
            for key, v in r["time_to"].items():
                md.append("| %s | %s | %s | %s |" % (level, key, fmt_time(v["measured"], r, key, "measured"),
                                                    fmt_time(v["noise_removed"], r, key, "noise_removed")
                                                    if r["reference"]["noise"] else "n/a"))
        plot_baker(baker, os.path.join(out, "error-vs-time-baker.png"))
    if runtime:
        md += ["", "## Runtime", "",
               "| level | probes | budget (ms) | before | frame 1 | frame 2 | frame 4 | frame 8 | last frame | "
               "s to last |", "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
        for level, r in runtime.items():
            for run in r["runs"]:
                e = run["rms_rel_error"]
                cell = lambda f: ("%.2f%% (%.2f s)" % (100 * e[f], run["t_s"][f])) if f < len(e) else "n/a"
                md.append("| %s | %d | %s | %.2f%% | %s | %s | %s | %s | %.2f%% (frame %d) | %.2f |" % (
                    level, r["probes"], "%g" % run["budget_ms"] if run["budget_ms"] > 0 else "none", 100 * e[0],
                    cell(1), cell(2), cell(4), cell(8), 100 * e[-1], len(e) - 1, run["t_s"][-1]))
            settled = r.get("settled_after_budget")
            if settled:
                md.append("| %s | %d | then update(0) | | | | | | %.2f%% (settled) | %.2f |" % (
                    level, r["probes"], 100 * settled["rms_rel_error"], settled["t_s"]))
        md += ["", "| level | probes | runtime settled at the start vs the bake with the object static there | "
               "start bake vs moved bake |", "|---|---:|---:|---:|"]
        for level, r in runtime.items():
            md.append("| %s | %d | %.2f%% | %.2f%% |" % (level, r["probes"], 100 * r["rest_vs_start_bake"],
                                                      100 * r["start_bake_vs_moved_bake"]))
        plot_runtime(runtime, os.path.join(out, "error-vs-time-runtime.png"))
    with open(os.path.join(out, "results.json"), "w") as f:
        json.dump({"baker": baker, "runtime": runtime, "load": load}, f, indent=1)
    with open(os.path.join(out, "results.md"), "w") as f:
        f.write("\n".join(md) + "\n")
    print("\n".join(md))


if __name__ == "__main__":
    main()
