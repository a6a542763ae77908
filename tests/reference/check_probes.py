#!/usr/bin/env python3
"""svit against the Mitsuba reference at probe points (issue 46 item 4): bakes
LEVEL with svit-bake (fixed seed and passes, or --time), reads svit-probe's
irradiance at the reference's probe points, and holds the luminance error
within a bound derived from the bake's own error estimate.

Per probe the error is e_i = (svit_i - ref_i) / ref_i, ref_i the mean of the
reference's two seeds. The reference's noise at a probe is half their
difference, sigma_i = |a - b| / 2 / ref_i (each seed's own error; their
mean's is 1/sqrt(2) of it). The bake's estimate E is its report's last
est_rel_error: an RMS of relative texel error. The test holds
  RMS_i(e_i) <= K * sqrt(E^2 + RMS_i(sigma_i)^2 / 2)   (K = 3)
that is, svit's error at the probes is what its estimate and the
reference's noise allow, three times over (a point reads one texel's
bilinear filter, not an area's RMS), and every probe within 3x that bound.
Exit 0 when it holds, 1 when not, 2 on bad input; prints a table either way.

usage: check_probes.py BUILD_DIR RESULTS.json WORK [--passes P | --time S]
                       [--texels-per-m T] [--seed N] [--json OUT]
"""

import argparse
import json
import math
import os
import subprocess
import sys
import time

K = 3.0


def luminance(rgb):
    return 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]


def bake(build, level, out, args):
    cmd = [os.path.join(build, "baker/svit-bake"), level, "-o", out, "--seed", str(args.seed),
           "--quiet"]
    cmd += ["--time", str(args.time)] if args.time else ["--passes", str(args.passes)]
    if args.texels_per_m:
        cmd += ["--texels-per-m", str(args.texels_per_m)]
    start = time.time()
    subprocess.run(cmd, check=True)
    return time.time() - start


def probe(build, out, probes, work):
    points = os.path.join(work, "probes.txt")
    with open(points, "w") as f:
        for p in probes:
            f.write(" ".join(f"{v:.7g}" for v in p["position"] + p["normal"]) + "\n")
    text = subprocess.run([os.path.join(build, "baker/svit-probe"), out, points, "--json"],
                          check=True, capture_output=True, text=True).stdout
    return [luminance(p["irradiance_lux"]) for p in json.loads(text)]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("build")
    parser.add_argument("results")
    parser.add_argument("work")
    parser.add_argument("--passes", type=int, default=8)
    parser.add_argument("--time", type=float)
    parser.add_argument("--texels-per-m", type=float)
    parser.add_argument("--seed", type=int, default=7)
    parser.add_argument("--json")
    args = parser.parse_args()
    try:
        with open(args.results) as f:
            ref = json.load(f)
        probes = ref["probes"]
    except (OSError, ValueError, KeyError) as e:
        print(f"check_probes: {args.results}: {e}", file=sys.stderr)
        return 2
    level = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(args.results)),
                                          ref["level"]))
    os.makedirs(args.work, exist_ok=True)
    out = os.path.join(args.work, "bake")
    seconds = bake(args.build, level, out, args)
    with open(os.path.join(out, "report.json")) as f:
        report = json.load(f)
    estimate = report["error_vs_time"][-1]["est_rel_error"]
    mine = probe(args.build, out, probes, args.work)
    rows, errors, noises = [], [], []
    for p, value in zip(probes, mine):
        a, b = (luminance(s) for s in p["irradiance_seeds"])
        r = (a + b) / 2
        errors.append((value - r) / r)
        noises.append(abs(a - b) / 2 / r)
        rows.append((p["position"], p["normal"], value, r, errors[-1], noises[-1]))
    rms = math.sqrt(sum(e * e for e in errors) / len(errors))
    noise = math.sqrt(sum(n * n for n in noises) / len(noises))
    bound = K * math.sqrt(estimate ** 2 + noise ** 2 / 2)
    worst = max(abs(e) for e in errors)
    ok = rms <= bound and worst <= K * bound
    print(f"{os.path.basename(level)}: svit {seconds:.1f} s, "
          f"{report['lightmap']['lighting_passes']} passes, estimate {100 * estimate:.2f} %; "
          f"reference {ref['spp']} spp x 2 seeds, noise {100 * noise:.2f} % RMS")
    print("position | normal | svit lux | reference lux | error | ref noise")
    for pos, n, v, r, e, s in rows:
        print(f"{[round(x, 3) for x in pos]} | {[round(x, 2) for x in n]} | {v:.4g} | {r:.4g} | "
              f"{100 * e:+.2f} % | {100 * s:.2f} %")
    print(f"RMS error {100 * rms:.2f} % (bound {100 * bound:.2f} %), worst {100 * worst:.2f} % "
          f"(bound {100 * K * bound:.2f} %): {'ok' if ok else 'FAILED'}")
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"level": os.path.basename(level), "seconds": seconds,
                       "passes": report["lightmap"]["lighting_passes"], "estimate": estimate,
                       "covered_texels": report["lightmap"]["covered_texels"],
                       "rms_error": rms, "worst_error": worst, "reference_noise": noise,
                       "bound": bound}, f, indent=1)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
