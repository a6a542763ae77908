#!/usr/bin/python3
"""Error against time for svit and Blender Cycles on the same lightmap texels.

Usage: cycles_compare.py OUT_DIR   (run by tests/bench/cycles_compare.sh)

Reads, under OUT_DIR:
  npy/cycles-sNNNNN.npy (+ .alpha.npy)  Cycles bakes of the series (seed 1)
  npy/reference.npy (+ .alpha.npy)      the long Cycles bake (other seed)
  npy/svit-tBUDGET.npy                  svit bakes
  cycles/cycles_timings.json, reference/cycles_timings.json
  svit/runs.tsv                         budget, wall seconds, bake directory
and writes results.json, results.md, error_vs_time.png and previews/*.png.

Texels: those Cycles baked in every bake (texel centre inside a UV triangle;
Cycles' margin is 0 and unbaked texels keep alpha 0). svit covers all of them
(it rasterizes conservatively) and dilates beyond; the dilation is ignored.
Error: RMS relative error of luminance (Rec. 709 Y), sqrt(mean((x - ref)^2)) /
mean(ref) over those texels, the definition svit's report.json uses. svit's
lux are compared with k x Cycles, one global factor k fitted by least squares
(all texels, all channels) between svit's longest bake and the reference.

The reference is itself noisy. All bakes are independent of it (the Cycles
series uses another seed), so measured^2 = true^2 + ref_noise^2; ref_noise
comes from a fit of the Cycles series, measured^2 = a (N^-q + N_ref^-q).
The tables give the measured error and the error with ref_noise removed;
the headline times use the latter, and Cycles' beyond its series come from
the same fit (marked "extrapolated").
"""

import json
import math
import os
import sys

import numpy as np

LUMA = np.array([0.2126, 0.7152, 0.0722])
TARGETS = (0.05, 0.02, 0.01)


def load(npy_dir, name):
    return np.load(os.path.join(npy_dir, name + ".npy")).astype(np.float64)


def rms_rel(x, ref):
    return float(np.sqrt(np.mean((x - ref) ** 2)) / np.mean(ref))


def crossing(times, errors, target):
    """First time the curve reaches target, log-log interpolated; None if never."""
    pts = [(t, e) for t, e in zip(times, errors) if t > 0 and e is not None and e > 0]
    for i, (t, e) in enumerate(pts):
        if e <= target:
            if i == 0:
                return t
            t0, e0 = pts[i - 1]
            f = (math.log(target) - math.log(e0)) / (math.log(e) - math.log(e0))
            return math.exp(math.log(t0) + f * (math.log(t) - math.log(t0)))
    return None


def fmt_time(t, note=""):
    if t is None:
        return "not reached"
    return ("%.3g s" % t) + note


def preview(path, image, scale):
    import matplotlib.pyplot as plt
    shown = np.clip(image / scale, 0, 1) ** (1 / 2.2)
    plt.imsave(path, shown)


def main():
    if len(sys.argv) != 2:
        print("usage: cycles_compare.py OUT_DIR", file=sys.stderr)
        return 2
    out = sys.argv[1]
    npy = os.path.join(out, "npy")
    with open(os.path.join(out, "cycles", "cycles_timings.json")) as f:
        cycles_timing = json.load(f)
    with open(os.path.join(out, "reference", "cycles_timings.json")) as f:
        reference_timing = json.load(f)
    svit_runs = []
    with open(os.path.join(out, "svit", "runs.tsv")) as f:
        for line in f:
            if line.strip() and not line.startswith("#"):
                budget, wall, directory = line.split("\t")
                svit_runs.append({"budget_s": float(budget), "wall_s": float(wall), "dir": directory.strip()})

    machine = {}
    load_path = os.path.join(out, "load.txt")
    if os.path.exists(load_path):
        with open(load_path) as f:
            for line in f:
                key, _, value = line.strip().partition(" ")
                machine[key] = value
    reference = load(npy, "reference")
    mask = np.load(os.path.join(npy, "reference.alpha.npy")) > 0.5
    cycles = []
    for bake in cycles_timing["bakes"]:
        name = os.path.splitext(bake["file"])[0]
        cycles.append({"samples": bake["samples"], "time_s": bake["seconds"], "image": load(npy, name)})
        mask &= np.load(os.path.join(npy, name + ".alpha.npy")) > 0.5
    svit = []
    for run in svit_runs:
        name = "svit-t%g" % run["budget_s"]
        with open(os.path.join(run["dir"], "report.json")) as f:
            report = json.load(f)
        svit.append(dict(run, image=load(npy, name), report=report))
    if reference.shape != svit[0]["image"].shape:
        raise SystemExit("cycles_compare.py: Cycles page %s and svit page %s differ" %
                         (reference.shape, svit[0]["image"].shape))
    texels = int(mask.sum())

    # One global unit factor, svit lux = k x Cycles, fitted on the longest svit bake.
    longest = max(svit, key=lambda r: r["wall_s"])
    s = longest["image"][mask]
    r = reference[mask]
    k = float(np.sum(s * r) / np.sum(r * r))
    k_per_channel = [float(np.sum(s[:, c] * r[:, c]) / np.sum(r[:, c] ** 2)) for c in range(3)]
    ref_y = (reference[mask] @ LUMA) * k

    for b in cycles:
        b["measured"] = rms_rel((b["image"][mask] @ LUMA) * k, ref_y)
    for b in svit:
        b["measured"] = rms_rel(b["image"][mask] @ LUMA, ref_y)
    # Interior texels: all 8 neighbours baked too (no chart border texels).
    interior = mask.copy()
    padded = np.pad(mask, 1)
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            interior &= padded[1 + dy:1 + dy + mask.shape[0], 1 + dx:1 + dx + mask.shape[1]]
    ref_y_interior = (reference[interior] @ LUMA) * k
    for b in cycles:
        b["measured_interior"] = rms_rel((b["image"][interior] @ LUMA) * k, ref_y_interior)
    for b in svit:
        b["measured_interior"] = rms_rel(b["image"][interior] @ LUMA, ref_y_interior)

    # Noise model of the Cycles series: its bakes and the reference are one
    # estimator at N and N_ref samples with independent seeds, so measured^2
    # = a (N^-q + N_ref^-q); q is 1 for plain Monte Carlo, a little more
    # with Cycles' stratified samples. Fitted (relative least squares, grid
    # over q) on the bakes of at least 8 samples; the reference's own noise
    # is a N_ref^-q.
    n_ref = reference_timing["bakes"][0]["samples"]
    fit_bakes = [b for b in cycles if b["samples"] >= 8] or cycles
    n_fit = np.array([b["samples"] for b in fit_bakes], dtype=float)
    m2 = np.array([b["measured"] ** 2 for b in fit_bakes])
    best = None
    for q in np.linspace(0.7, 1.5, 801):
        f = (n_fit ** -q + float(n_ref) ** -q) / m2
        a_q = float(np.sum(f) / np.sum(f * f))
        residual = float(np.sum((a_q * f - 1.0) ** 2))
        if best is None or residual < best[0]:
            best = (residual, float(q), a_q)
    fit_residual, q, a = best
    ref_noise2 = a * float(n_ref) ** -q
    for b in cycles + svit:
        b["corrected"] = math.sqrt(max(b["measured"] ** 2 - ref_noise2, 0.0))
    # Cycles time per sample (bake time = t0 + c N) for extrapolation.
    ns = np.array([b["samples"] for b in cycles], dtype=float)
    ts = np.array([b["time_s"] for b in cycles])
    c_per_sample, t0 = np.polyfit(ns[ns >= 8], ts[ns >= 8], 1) if np.sum(ns >= 8) >= 2 else np.polyfit(ns, ts, 1)

    table = []
    summary = {}
    for target in TARGETS:
        row = {"target": target}
        for who, runs, tkey in (("cycles", cycles, "time_s"), ("svit", svit, "wall_s")):
            times = [b[tkey] for b in runs]
            row[who + "_measured_s"] = crossing(times, [b["measured"] for b in runs], target)
            row[who + "_s"] = crossing(times, [b["corrected"] for b in runs], target)
            row[who + "_extrapolated"] = False
        if row["cycles_s"] is None and a > 0:
            # Beyond the series: error^2 = a N^-q, so N = (a / target^2)^(1/q).
            n_needed = (a / target ** 2) ** (1.0 / q)
            row["cycles_s"] = float(t0 + c_per_sample * n_needed)
            row["cycles_extrapolated"] = True
        row["ratio_cycles_over_svit"] = (row["cycles_s"] / row["svit_s"]
                                         if row["cycles_s"] and row["svit_s"] else None)
        table.append(row)

    results = {
        "level": "cornell_box_original with Blender Lightmap Pack UVs (TEXCOORD_1)",
        "machine": "%s CPUs (%s), all threads for both bakers, no GPU" % (machine.get("cpus", "?"), machine.get("cpu", "?")),
        "load_average_1_5_15_min": {k2: v for k2, v in machine.items() if k2 not in ("cpus", "cpu")},
        "page": list(reference.shape[:2]),
        "texels_compared": texels,
        "texels_interior": int(interior.sum()),
        "unit_factor_svit_lux_per_cycles": k,
        "unit_factor_per_channel": k_per_channel,
        "unit_factor_over_pi": k / math.pi,
        "reference": {"samples": n_ref, "seconds": reference_timing["bakes"][0]["seconds"],
                      "seed": reference_timing["seed"], "noise_rel_error": math.sqrt(max(ref_noise2, 0.0))},
        "cycles_noise_model": {"model": "measured^2 = a (N^-q + N_ref^-q)", "a": a, "q": q,
                               "fit_relative_residual": fit_residual, "fit_samples_min": int(n_fit.min()),
                               "seconds_per_sample": float(c_per_sample), "seconds_fixed": float(t0)},
        "cycles": [{k2: v for k2, v in b.items() if k2 != "image"} for b in cycles],
        "svit": [{"budget_s": b["budget_s"], "wall_s": b["wall_s"], "measured": b["measured"],
                  "measured_interior": b["measured_interior"], "corrected": b["corrected"],
                  "report_stage_seconds": b["report"].get("stage_seconds"),
                  "report_lightmap": b["report"].get("lightmap"),
                  "report_est_rel_error": (b["report"].get("error_vs_time") or [{}])[-1].get("est_rel_error")}
                 for b in svit],
        "time_to_error": table,
    }
    with open(os.path.join(out, "results.json"), "w") as f:
        json.dump(results, f, indent=1)

    lines = []
    lines.append("Cornell box (original), %dx%d lightmap, %d texels compared; %s" %
                 (reference.shape[1], reference.shape[0], texels, results["machine"]))
    lines.append("Reference: Cycles %d samples (%.0f s), its own noise %.2f%% RMS; unit factor k = %.4f lux per Cycles unit (k / pi = %.4f)" %
                 (n_ref, results["reference"]["seconds"], 100 * results["reference"]["noise_rel_error"], k, k / math.pi))
    lines.append("Load average (1/5/15 min) at start, after Cycles, after svit: %s; %s; %s" %
                 (machine.get("start", "?"), machine.get("after-cycles", "?"), machine.get("after-svit", "?")))
    lines.append("")
    lines.append("| RMS rel. error | Cycles time | svit time | Cycles / svit |")
    lines.append("|---:|---:|---:|---:|")
    for row in table:
        cyc = fmt_time(row["cycles_s"], " (extrapolated)" if row["cycles_extrapolated"] else "")
        sv = fmt_time(row["svit_s"])
        ratio = "%.1f" % row["ratio_cycles_over_svit"] if row["ratio_cycles_over_svit"] else "n/a"
        lines.append("| %g%% | %s | %s | %s |" % (100 * row["target"], cyc, sv, ratio))
    lines.append("")
    lines.append("Times are with the reference's own noise removed (sqrt(measured^2 - ref_noise^2)); Cycles noise fit: error^2 = %.3g N^-%.3f." % (a, q))
    lines.append("")
    lines.append("| baker | setting | time (s) | measured | without ref. noise | interior texels |")
    lines.append("|---|---:|---:|---:|---:|---:|")
    for b in cycles:
        lines.append("| Cycles | %d samples | %.2f | %.2f%% | %.2f%% | %.2f%% |" %
                     (b["samples"], b["time_s"], 100 * b["measured"], 100 * b["corrected"], 100 * b["measured_interior"]))
    for b in svit:
        lines.append("| svit | --time %g | %.2f | %.2f%% | %.2f%% | %.2f%% |" %
                     (b["budget_s"], b["wall_s"], 100 * b["measured"], 100 * b["corrected"], 100 * b["measured_interior"]))
    text = "\n".join(lines) + "\n"
    with open(os.path.join(out, "results.md"), "w") as f:
        f.write(text)
    print(text)

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7, 5))
    ct = [b["time_s"] for b in cycles]
    st = [b["wall_s"] for b in svit]
    ax.loglog(ct, [b["corrected"] for b in cycles], "o-", color="tab:blue", label="Cycles (reference noise removed)")
    ax.loglog(ct, [b["measured"] for b in cycles], "o--", color="tab:blue", alpha=0.4, label="Cycles (measured)")
    ax.loglog(st, [b["corrected"] for b in svit], "s-", color="tab:red", label="svit (reference noise removed)")
    ax.loglog(st, [b["measured"] for b in svit], "s--", color="tab:red", alpha=0.4, label="svit (measured)")
    n_line = np.geomspace(n_fit.min(), max(n_fit.max(), (a / min(TARGETS) ** 2) ** (1.0 / q)), 50)
    ax.loglog(t0 + c_per_sample * n_line, np.sqrt(a * n_line ** -q), ":", color="tab:blue", alpha=0.6,
              label="Cycles fit, error^2 = a N^-%.2f, time = %.2f s + %.3f s N" % (q, t0, c_per_sample))
    for target in TARGETS:
        ax.axhline(target, color="gray", lw=0.5)
    ax.axhline(math.sqrt(ref_noise2), color="tab:green", lw=0.8, ls="-.", label="reference's own noise")
    every = [b[key] for b in cycles + svit for key in ("measured", "corrected") if b[key] > 0]
    ax.set_ylim(min(every + [min(TARGETS)]) * 0.5, max(every) * 1.5)
    ax.set_xlabel("bake wall time (s), 2-core CPU")
    ax.set_ylabel("RMS relative error of luminance vs reference")
    ax.set_title("cornell_box_original, %dx%d lightmap, same UVs" % (reference.shape[1], reference.shape[0]))
    ax.grid(True, which="both", lw=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "error_vs_time.png"), dpi=120)

    previews = os.path.join(out, "previews")
    os.makedirs(previews, exist_ok=True)
    scale = float(np.percentile(ref_y, 99)) * 1.0
    preview(os.path.join(previews, "reference.png"), reference * k * mask[:, :, None], scale)
    preview(os.path.join(previews, "svit-longest.png"), longest["image"] * mask[:, :, None], scale)
    preview(os.path.join(previews, "svit-longest-dilated.png"), longest["image"], scale)
    diff = (longest["image"] @ LUMA - (reference * k) @ LUMA) * mask
    plt.imsave(os.path.join(previews, "svit-minus-reference.png"), diff, cmap="coolwarm",
               vmin=-0.2 * scale, vmax=0.2 * scale)
    return 0


if __name__ == "__main__":
    sys.exit(main())
