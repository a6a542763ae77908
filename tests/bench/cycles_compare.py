#!/usr/bin/python3
"""Error against time for svit and Blender Cycles on the same lightmap texels.

Usage: cycles_compare.py OUT_DIR   (run by tests/bench/cycles_compare.sh)

Reads, under OUT_DIR:
  npy/cycles-sNNNNN.npy (+ .alpha.npy)  Cycles bakes of the series (seed 1)
  npy/reference.npy (+ .alpha.npy)      the long Cycles bake (seed 2)
  npy/svit-tBUDGET.npy                  svit bakes
  cycles/cycles_timings.json, reference/cycles_timings.json
  svit/runs.tsv                         budget, wall seconds, bake directory
  scene/texels.npz                      texel owner and hidden flags
  load.txt                              CPU and load averages
and writes results.json, results.md, error_vs_time.png and previews/*.png.

Texel sets ("masks"), all within the texels Cycles baked (texel centre inside
a UV triangle; Cycles' margin is 0, so unbaked texels keep alpha 0; svit
covers these too, rasterizing conservatively, and dilates beyond):
  all      every such texel (the headline);
  visible  minus hidden texels (the floor under the boxes, the ceiling in the
           1 cm gap above the light), which no viewer in the room can see,
           and minus texels of the boxes' duplicated faces (the source OBJ
           has each box's right face twice; light on two coinciding faces
           depends on how a ray tracer treats hits at distance 0);
  visible interior  minus also chart-border texels (a neighbour not baked),
           where the two bakers place their sample points differently.
Error: RMS relative error of luminance (Rec. 709 Y), sqrt(mean((x - ref)^2)) /
mean(ref), the definition svit's report.json uses. svit's lux are compared
with k x Cycles, one global factor k fitted by least squares (all channels,
visible interior texels) between svit's longest bake and the reference.

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
MASKS = ("all", "visible", "visible interior")


def load(npy_dir, name):
    return np.load(os.path.join(npy_dir, name + ".npy")).astype(np.float64)


def rms_rel(x, ref):
    return float(np.sqrt(np.mean((x - ref) ** 2)) / np.mean(ref))


def crossing(times, errors, target):
    """First time the curve reaches target, log-log interpolated; None if
    never; an upper bound (the first bake's time) if the first bake does."""
    pts = [(t, e) for t, e in zip(times, errors) if t > 0 and e is not None and e > 0]
    for i, (t, e) in enumerate(pts):
        if e <= target:
            if i == 0:
                return t
            t0, e0 = pts[i - 1]
            f = (math.log(target) - math.log(e0)) / (math.log(e) - math.log(e0))
            return math.exp(math.log(t0) + f * (math.log(t) - math.log(t0)))
    return None


def noise_fit(samples, measured, n_ref):
    """a, q of measured^2 = a (N^-q + N_ref^-q), relative least squares, N >= 8."""
    keep = [(n, m) for n, m in zip(samples, measured) if n >= 8] or list(zip(samples, measured))
    n = np.array([k[0] for k in keep], dtype=float)
    m2 = np.array([k[1] for k in keep]) ** 2
    best = None
    for q in np.linspace(0.7, 1.5, 801):
        f = (n ** -q + float(n_ref) ** -q) / m2
        a = float(np.sum(f) / np.sum(f * f))
        residual = float(np.sum((a * f - 1.0) ** 2))
        if best is None or residual < best[0]:
            best = (residual, float(q), a)
    return {"a": best[2], "q": best[1], "relative_residual": best[0], "min_samples": int(n.min())}


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
    with open(os.path.join(out, "load.txt")) as f:
        for line in f:
            key, _, value = line.strip().partition(" ")
            machine[key] = value
    texel_info = np.load(os.path.join(out, "scene", "texels.npz"))
    owner, hidden, names = texel_info["owner"], texel_info["hidden"], [str(n) for n in texel_info["names"]]
    duplicate = texel_info["duplicate"]

    reference = load(npy, "reference")
    n_ref = reference_timing["bakes"][0]["samples"]
    baked = np.load(os.path.join(npy, "reference.alpha.npy")) > 0.5
    cycles = []
    for bake in cycles_timing["bakes"]:
        name = os.path.splitext(bake["file"])[0]
        cycles.append({"baker": "Cycles", "setting": "%d samples" % bake["samples"], "samples": bake["samples"],
                       "time_s": bake["seconds"], "image": load(npy, name)})
        baked &= np.load(os.path.join(npy, name + ".alpha.npy")) > 0.5
    svit = []
    for run in svit_runs:
        with open(os.path.join(run["dir"], "report.json")) as f:
            report = json.load(f)
        svit.append({"baker": "svit", "setting": "--time %g" % run["budget_s"], "budget_s": run["budget_s"],
                     "time_s": run["wall_s"], "image": load(npy, "svit-t%g" % run["budget_s"]), "report": report})
    if reference.shape != svit[0]["image"].shape or owner.shape != reference.shape[:2]:
        raise SystemExit("cycles_compare.py: page sizes differ: Cycles %s, svit %s, texel map %s" %
                         (reference.shape, svit[0]["image"].shape, owner.shape))
    if np.any(baked != (owner >= 0)):
        print("cycles_compare.py: note: %d texels differ between Cycles' coverage and the texel map" %
              int(np.sum(baked != (owner >= 0))))

    interior = baked.copy()
    padded = np.pad(baked, 1)
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            interior &= padded[1 + dy:1 + dy + baked.shape[0], 1 + dx:1 + dx + baked.shape[1]]
    visible = ~hidden & ~duplicate
    masks = {"all": baked, "visible": baked & visible, "visible interior": interior & visible}

    # One global unit factor: svit lux = k x Cycles.
    longest = max(svit, key=lambda r: r["time_s"])
    fit_mask = masks["visible interior"]
    s, r = longest["image"][fit_mask], reference[fit_mask]
    k = float(np.sum(s * r) / np.sum(r * r))
    k_per_channel = [float(np.sum(s[:, c] * r[:, c]) / np.sum(r[:, c] ** 2)) for c in range(3)]
    ref_y = reference @ LUMA * k

    ns = np.array([b["samples"] for b in cycles], dtype=float)
    ts = np.array([b["time_s"] for b in cycles])
    # Cycles bake time = t0 + c N, through the smallest and the largest bake
    # (the largest is the timing that matters for extrapolation).
    lo, hi = int(np.argmin(ns)), int(np.argmax(ns))
    c_per_sample = float((ts[hi] - ts[lo]) / (ns[hi] - ns[lo]))
    t0 = float(ts[lo] - c_per_sample * ns[lo])

    evaluation = {}
    for mask_name, mask in masks.items():
        ref_m = ref_y[mask]
        for b in cycles:
            b.setdefault("measured", {})[mask_name] = rms_rel(b["image"][mask] @ LUMA * k, ref_m)
        for b in svit:
            b.setdefault("measured", {})[mask_name] = rms_rel(b["image"][mask] @ LUMA, ref_m)
        fit = noise_fit([b["samples"] for b in cycles], [b["measured"][mask_name] for b in cycles], n_ref)
        ref_noise = math.sqrt(fit["a"] * float(n_ref) ** -fit["q"])
        for b in cycles + svit:
            b.setdefault("corrected", {})[mask_name] = math.sqrt(max(b["measured"][mask_name] ** 2 - ref_noise ** 2, 0.0))
        rows = []
        for target in TARGETS:
            row = {"target": target}
            for who, runs in (("cycles", cycles), ("svit", svit)):
                times = [b["time_s"] for b in runs]
                row[who + "_s"] = crossing(times, [b["corrected"][mask_name] for b in runs], target)
                row[who + "_upper_bound"] = bool(runs) and runs[0]["corrected"][mask_name] <= target
                row[who + "_measured_s"] = crossing(times, [b["measured"][mask_name] for b in runs], target)
            row["cycles_extrapolated"] = False
            if row["cycles_s"] is None:
                n_needed = (fit["a"] / target ** 2) ** (1.0 / fit["q"])
                row["cycles_s"] = float(t0 + c_per_sample * n_needed)
                row["cycles_extrapolated"] = True
            row["ratio_cycles_over_svit"] = row["cycles_s"] / row["svit_s"] if row["svit_s"] else None
            rows.append(row)
        # The same for svit's longest bake with the nominal factor k = pi
        # (Cycles' Diffuse light pass is irradiance / pi) instead of the fit.
        with_pi = rms_rel(longest["image"][mask] @ LUMA, (reference[mask] @ LUMA) * math.pi)
        evaluation[mask_name] = {"texels": int(mask.sum()), "reference_noise": ref_noise, "cycles_noise_fit": fit,
                                 "svit_longest_measured_with_k_pi": with_pi, "time_to_error": rows}

    # Where svit's error lies: per object, longest bake and the longest Cycles series bake.
    longest_cycles = max(cycles, key=lambda b: b["samples"])
    total_svit = float(np.sum((longest["image"][baked] @ LUMA - ref_y[baked]) ** 2))
    per_object = []
    mean_ref = float(np.mean(ref_y[baked]))
    for i, name in enumerate(names):
        for part, extra in (("visible", visible), ("hidden", hidden), ("duplicated face", duplicate & ~hidden)):
            m = baked & (owner == i) & extra
            if not m.any():
                continue
            sv = longest["image"][m] @ LUMA
            cy = longest_cycles["image"][m] @ LUMA * k
            per_object.append({
                "object": name, "texels": part, "count": int(m.sum()),
                "reference_mean_lux": float(np.mean(ref_y[m])),
                "svit_over_reference": float(np.mean(sv) / np.mean(ref_y[m])) if np.mean(ref_y[m]) > 0 else None,
                "svit_share_of_squared_error": float(np.sum((sv - ref_y[m]) ** 2) / total_svit),
                "svit_rms_over_global_mean": float(np.sqrt(np.mean((sv - ref_y[m]) ** 2)) / mean_ref),
                "cycles_%d_rms_over_global_mean" % longest_cycles["samples"]:
                    float(np.sqrt(np.mean((cy - ref_y[m]) ** 2)) / mean_ref)})
    border = baked & ~interior
    border_share = float(np.sum((longest["image"][border] @ LUMA - ref_y[border]) ** 2) / total_svit)

    def clean(b):
        keep = {key: value for key, value in b.items() if key not in ("image", "report")}
        if "report" in b:
            keep["report_stage_seconds"] = b["report"].get("stage_seconds")
            keep["report_lightmap"] = b["report"].get("lightmap")
            keep["report_radiosity"] = b["report"].get("radiosity")
            keep["report_est_rel_error"] = (b["report"].get("error_vs_time") or [{}])[-1].get("est_rel_error")
        return keep

    results = {
        "level": "cornell_box_original with Blender Lightmap Pack UVs as TEXCOORD_1",
        "machine": "%s CPUs (%s), all threads for both bakers, no GPU" % (machine.get("cpus", "?"), machine.get("cpu", "?")),
        "load_average_1_5_15_min": {key: v for key, v in machine.items() if key not in ("cpus", "cpu")},
        "page": list(reference.shape[:2]),
        "unit_factor_svit_lux_per_cycles": k,
        "unit_factor_per_channel": k_per_channel,
        "unit_factor_over_pi": k / math.pi,
        "reference": {"samples": n_ref, "seconds": reference_timing["bakes"][0]["seconds"],
                      "seed": reference_timing["seed"]},
        "cycles_time_model": {"seconds_per_sample": float(c_per_sample), "seconds_fixed": float(t0)},
        "masks": evaluation,
        "svit_longest_error_by_object": per_object,
        "svit_longest_error_share_chart_border_texels": border_share,
        "cycles": [clean(b) for b in cycles],
        "svit": [clean(b) for b in svit],
    }
    with open(os.path.join(out, "results.json"), "w") as f:
        json.dump(results, f, indent=1)

    def cell(t, extrapolated=False, upper_bound=False):
        if t is None:
            return "not reached"
        return ("<= " if upper_bound else "") + ("%.3g s" % t) + (" (extrap.)" if extrapolated else "")

    lines = [
        "Cornell box (original), %dx%d lightmap (same Lightmap Pack UVs for both); %s" %
        (reference.shape[1], reference.shape[0], results["machine"]),
        "Reference: Cycles %d samples, seed 2 (%.0f s); unit factor k = %.4f svit lux per Cycles unit (k / pi = %.4f)" %
        (n_ref, results["reference"]["seconds"], k, k / math.pi),
        "Load average (1/5/15 min) at start, after Cycles, after svit: %s; %s; %s" %
        (machine.get("start", "?"), machine.get("after-cycles", "?"), machine.get("after-svit", "?")),
        "",
        "Time to reach an RMS relative error (luminance; reference noise removed):",
        "",
        "| texels | error | Cycles | svit | Cycles / svit |",
        "|---|---:|---:|---:|---:|",
    ]
    for mask_name in MASKS:
        e = evaluation[mask_name]
        for row in e["time_to_error"]:
            ratio = "%.2g" % row["ratio_cycles_over_svit"] if row["ratio_cycles_over_svit"] else "n/a"
            lines.append("| %s (%d) | %g%% | %s | %s | %s |" % (
                mask_name, e["texels"], 100 * row["target"],
                cell(row["cycles_s"], row["cycles_extrapolated"], row["cycles_upper_bound"]),
                cell(row["svit_s"], upper_bound=row["svit_upper_bound"]), (">= " if row["svit_upper_bound"] and ratio != "n/a" else "") + ratio))
    lines.append("")
    lines.append("Reference noise (from the Cycles fit measured^2 = a (N^-q + N_ref^-q)): " + "; ".join(
        "%s %.2f%% (q = %.3f)" % (m, 100 * evaluation[m]["reference_noise"], evaluation[m]["cycles_noise_fit"]["q"])
        for m in MASKS))
    lines.append("svit's longest bake with k = pi instead of the fitted k (measured): " + "; ".join(
        "%s %.2f%%" % (m, 100 * evaluation[m]["svit_longest_measured_with_k_pi"]) for m in MASKS))
    lines.append("")
    lines.append("| baker | setting | time (s) | " + " | ".join("%s: measured / noise removed" % m for m in MASKS) + " |")
    lines.append("|---|---:|---:|" + "---:|" * len(MASKS))
    for b in cycles + svit:
        lines.append("| %s | %s | %.2f | %s |" % (b["baker"], b["setting"], b["time_s"], " | ".join(
            "%.2f%% / %.2f%%" % (100 * b["measured"][m], 100 * b["corrected"][m]) for m in MASKS)))
    lines.append("")
    lines.append("svit's longest bake: chart-border texels hold %.0f%% of its squared error; by object:" % (100 * border_share))
    lines.append("")
    lines.append("| object | texels | count | ref. mean (lux) | svit / ref. | share of svit's sq. error |")
    lines.append("|---|---|---:|---:|---:|---:|")
    for o in per_object:
        lines.append("| %s | %s | %d | %.3f | %s | %.1f%% |" % (
            o["object"], o["texels"], o["count"], o["reference_mean_lux"],
            "%.3f" % o["svit_over_reference"] if o["svit_over_reference"] is not None else "n/a",
            100 * o["svit_share_of_squared_error"]))
    text = "\n".join(lines) + "\n"
    with open(os.path.join(out, "results.md"), "w") as f:
        f.write(text)
    print(text)

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, len(MASKS), figsize=(6 * len(MASKS), 5.2), sharey=True)
    for ax, mask_name in zip(axes, MASKS):
        e = evaluation[mask_name]
        fit = e["cycles_noise_fit"]
        ct = [b["time_s"] for b in cycles]
        st = [b["time_s"] for b in svit]
        ax.loglog(ct, [b["corrected"][mask_name] for b in cycles], "o-", color="tab:blue", label="Cycles")
        ax.loglog(ct, [b["measured"][mask_name] for b in cycles], "o--", color="tab:blue", alpha=0.35,
                  label="Cycles, measured (incl. reference noise)")
        ax.loglog(st, [b["corrected"][mask_name] for b in svit], "s-", color="tab:red", label="svit")
        ax.loglog(st, [b["measured"][mask_name] for b in svit], "s--", color="tab:red", alpha=0.35,
                  label="svit, measured (incl. reference noise)")
        n_line = np.geomspace(8, max(ns.max(), (fit["a"] / min(TARGETS) ** 2) ** (1.0 / fit["q"])), 60)
        ax.loglog(t0 + c_per_sample * n_line, np.sqrt(fit["a"] * n_line ** -fit["q"]), ":", color="tab:blue",
                  alpha=0.7, label="Cycles fit: error^2 = %.3g N^-%.2f" % (fit["a"], fit["q"]))
        for target in TARGETS:
            ax.axhline(target, color="gray", lw=0.6)
        ax.axhline(e["reference_noise"], color="tab:green", lw=0.8, ls="-.", label="reference's own noise")
        ax.set_xlabel("bake wall time (s), %s CPUs" % machine.get("cpus", "?"))
        ax.set_title("%s texels (%d)" % (mask_name, e["texels"]))
        ax.grid(True, which="both", lw=0.3)
    every = [b[key][m] for b in cycles + svit for key in ("measured", "corrected") for m in MASKS if b[key][m] > 0]
    axes[0].set_ylim(min(every + [min(TARGETS)]) * 0.5, max(every) * 1.5)
    axes[0].set_ylabel("RMS relative error of luminance vs Cycles reference")
    axes[0].legend(fontsize=7)
    fig.suptitle("cornell_box_original, %dx%d lightmap, same UVs: svit vs Blender Cycles %s" %
                 (reference.shape[1], reference.shape[0], "3.4"))
    fig.tight_layout()
    fig.savefig(os.path.join(out, "error_vs_time.png"), dpi=110)

    previews = os.path.join(out, "previews")
    os.makedirs(previews, exist_ok=True)
    scale = float(np.percentile(ref_y[baked], 99))

    def save(name, image):
        plt.imsave(os.path.join(previews, name), np.clip(image / scale, 0, 1) ** (1 / 2.2))

    save("reference.png", reference * k * baked[:, :, None])
    save("cycles-s%05d.png" % longest_cycles["samples"], longest_cycles["image"] * k * baked[:, :, None])
    save("svit-longest.png", longest["image"] * baked[:, :, None])
    save("svit-longest-dilated.png", longest["image"])
    diff = np.where(baked, longest["image"] @ LUMA - ref_y, np.nan)
    plt.imsave(os.path.join(previews, "svit-minus-reference.png"), diff, cmap="coolwarm",
               vmin=-0.2 * scale, vmax=0.2 * scale)
    return 0


if __name__ == "__main__":
    sys.exit(main())
