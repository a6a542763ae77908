#!/usr/bin/env python3
"""Irradiance at probe points of a glTF level, path traced by Mitsuba 3
(PyPI `mitsuba`, the CPU variant scalar_rgb): the reference no one here
wrote for tests/reference/check_probes.py.

The level: every triangle of gltf_triangles.load(), a Lambertian BSDF of its
base colour ('twosided' where the material is double-sided, else black from
behind, as svit shades it), an area emitter of its emission on the front
(Mitsuba's area lights emit on one side; the levels here keep emitters
one-sided, so svit agrees). Each probe line 'x y z nx ny nz' (svit-probe's
format) is snapped onto the surface below it, and a disk of radius
DISK_M carrying an irradiancemeter is laid there, 0.1 mm above the surface,
facing the normal: Mitsuba's path integrator (unbounded depth, Russian
roulette from depth 5) measures the irradiance arriving on it, lux per
channel. Two seeds give the reference's noise.

usage: mitsuba_irradiance.py LEVEL.gltf PROBES.txt -o OUT.json [--spp N] [--seeds 1 2]
                              [--workers W]
"""

import argparse
import json
import multiprocessing
import os
import sys
import tempfile
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import gltf_triangles  # noqa: E402

DISK_M = 1e-3
LIFT_M = 1e-4


def _write_ply(path, triangles):
    n = len(triangles)
    with open(path, "wb") as f:
        f.write((f"ply\nformat binary_little_endian 1.0\nelement vertex {3 * n}\n"
                 "property float x\nproperty float y\nproperty float z\n"
                 f"element face {n}\nproperty list uchar int vertex_indices\nend_header\n").encode())
        f.write(triangles.reshape(-1, 3).astype("<f4").tobytes())
        faces = np.zeros(n, dtype=[("n", "u1"), ("i", "<i4", 3)])
        faces["n"] = 3
        faces["i"] = np.arange(3 * n, dtype=np.int32).reshape(n, 3)
        f.write(faces.tobytes())


def level_dict(level_path, folder):
    shapes = {}
    for k, part in enumerate(gltf_triangles.load(level_path)):
        m = part["material"]
        ply = os.path.join(folder, f"part{k}.ply")
        _write_ply(ply, part["triangles"])
        bsdf = {"type": "diffuse", "reflectance": {"type": "rgb", "value": m["base_color"]}}
        if m["double_sided"]:
            bsdf = {"type": "twosided", "material": bsdf}
        shape = {"type": "ply", "filename": ply, "face_normals": True, "bsdf": bsdf}
        if any(c > 0 for c in m["emission"]):
            shape["emitter"] = {"type": "area", "radiance": {"type": "rgb", "value": m["emission"]}}
        shapes[f"part{k}"] = shape
    return shapes


def read_probes(path):
    probes = []
    with open(path) as f:
        for line in f:
            if line.strip() and not line.startswith("#"):
                v = [float(x) for x in line.split()]
                n = np.array(v[3:6]) / np.linalg.norm(v[3:6])
                probes.append((np.array(v[:3]), n))
    return probes


def snap(mi, scene, point, normal):
    """The surface point under `point` along -normal, and its side's normal."""
    ray = mi.Ray3f(mi.Point3f(*(point + 0.05 * normal)), mi.Vector3f(*(-normal)))
    si = scene.ray_intersect(ray)
    if not si.is_valid():
        raise SystemExit(f"probe {point.tolist()} {normal.tolist()}: no surface within 5 cm below")
    n = np.array(si.n)
    if np.dot(n, normal) < 0:
        n = -n
    return np.array(si.p), n


def _frame(mi, p, n):
    return mi.ScalarTransform4f().look_at(origin=(p + LIFT_M * n).tolist(),
                                          target=(p + n).tolist(),
                                          up=[0, 1, 0] if abs(n[1]) < 0.9 else [1, 0, 0]) @ \
        mi.ScalarTransform4f().scale([DISK_M, DISK_M, 1])


def render_probes(args):
    level_path, probes, spp, seed, indices = args
    import mitsuba as mi
    mi.set_variant("scalar_rgb")
    with tempfile.TemporaryDirectory() as folder:
        shapes = level_dict(level_path, folder)
        base = mi.load_dict({"type": "scene", **shapes})
        snapped = [snap(mi, base, p, n) for p, n in probes]
        scene = {"type": "scene", "integrator": {"type": "path", "max_depth": -1}, **shapes}
        for i in indices:
            p, n = snapped[i]
            scene[f"probe{i}"] = {
                "type": "disk", "to_world": _frame(mi, p, n),
                "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": [0, 0, 0]}},
                "sensor": {"type": "irradiancemeter",
                           "film": {"type": "hdrfilm", "width": 1, "height": 1,
                                    "rfilter": {"type": "box"}, "pixel_format": "rgb"},
                           "sampler": {"type": "independent", "sample_count": spp}}}
        loaded = mi.load_dict(scene)
        out = {}
        for s, sensor in enumerate(loaded.sensors()):
            i = indices[s]
            image = np.array(mi.render(loaded, sensor=sensor, spp=spp, seed=seed))
            out[i] = (snapped[i][0].tolist(), snapped[i][1].tolist(), image.reshape(-1)[:3].tolist())
        return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("level")
    parser.add_argument("probes")
    parser.add_argument("-o", "--out", required=True)
    parser.add_argument("--spp", type=int, default=1 << 18)
    parser.add_argument("--seeds", type=int, nargs=2, default=[1, 2])
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 1)
    args = parser.parse_args()
    probes = read_probes(args.probes)
    start = time.time()
    runs = []
    for seed in args.seeds:
        chunks = [list(range(k, len(probes), args.workers)) for k in range(args.workers)]
        jobs = [(args.level, probes, args.spp, seed, c) for c in chunks if c]
        with multiprocessing.Pool(len(jobs)) as pool:
            merged = {}
            for part in pool.map(render_probes, jobs):
                merged.update(part)
        runs.append([merged[i] for i in range(len(probes))])
    import mitsuba as mi
    result = {
        "level": os.path.relpath(os.path.abspath(args.level), os.path.dirname(os.path.abspath(args.out))),
        "renderer": f"Mitsuba {mi.__version__} scalar_rgb, path integrator max_depth -1",
        "spp": args.spp, "seeds": args.seeds, "seconds": round(time.time() - start, 1),
        "disk_m": DISK_M, "lift_m": LIFT_M,
        "probes": [{"position": a[0], "normal": a[1], "irradiance_seeds": [a[2], b[2]]}
                   for a, b in zip(runs[0], runs[1])]}
    with open(args.out, "w") as f:
        json.dump(result, f, indent=1)
    print(f"{args.out}: {len(probes)} probes, {args.spp} spp x 2 seeds, {result['seconds']} s")


if __name__ == "__main__":
    main()
