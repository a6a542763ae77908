#!/usr/bin/env python3
"""Scaling benchmark (issue 8 item 3): baker and runtime cost against
triangles, emitters, texels and dynamic objects, each as a curve with its
growth exponent (least-squares slope of log time against log size).

    scaling.py level OUT_DIR --segments S --lamps K   write one synthetic level
    scaling.py run --build BUILD --out OUT [--series a,b] [--max-segments S]
    scaling.py plot --out OUT                         refit and replot OUT/results.json

The synthetic level: a closed 8 x 3 x 8 m room (inward faces), 64 UV spheres
of radius 0.3 m on an 8 x 8 grid (one mesh, 64 instances; S segments give
64 (S^2 - 2S) triangles), a 4 x 4 m grid of K x K emissive quads under the
ceiling (quarter of each cell lit, so 4 m2 at 500 cd/m2 whatever K: the same
6.3 klm in every level) and one dynamic crate parked in a corner, so bakes
carry runtime sections. Only the varied quantity changes between levels.

`run` bakes with `/usr/bin/time -v` (peak RSS), reads report.json's
stage_seconds, runs bench_scaling_runtime under xvfb-run, and writes
OUT/results.json, OUT/results.md and OUT/scaling-baker.png,
OUT/scaling-runtime.png. Bakes and runtime points already in OUT are kept
(delete OUT to measure afresh). Python 3 standard library plus matplotlib (Debian python3-matplotlib:
scaling.sh runs /usr/bin/python3).
"""

import argparse
import array
import json
import math
import os
import re
import signal
import struct
import subprocess
import sys
import time

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
SCENES = os.path.abspath(os.path.join(ROOT, "..", "shared", "scenes"))

ROOM_HALF_M = 4.0
ROOM_HEIGHT_M = 3.0
SPHERE_RADIUS_M = 0.3
SPHERE_GRID = 8          # 8 x 8 spheres
SPHERE_PITCH_M = 0.9
LAMP_HALF_M = 2.0        # the lamp grid covers x, z in [-2, 2]
LAMP_Y_M = 2.99
LAMP_LUMINANCE = 500.0   # cd/m2 (emissiveFactor 1 x emissive_strength)
POINT_LIGHTS_CD = 500.0  # all point lights of a level together (6.3 klm, as the lamp quads)

QUALITY = 0.1            # fixed: passes and error target
TEXELS_PER_M = 25.0      # fixed for the triangle and emitter series (~0.2 M texels)
SEED = 1

# Series grids (sized for about an hour on the loaded 2-core machine).
TRIANGLE_SEGMENTS = [14, 24, 40, 70, 126]    # ~10k, 34k, 97k, 305k, 1.0M triangles
EMITTER_GRID = [1, 4, 10, 32, 100]           # 1, 16, 100, 1024, 10000 quads
POINT_LIGHT_GRID = [1, 4, 16, 32]            # 1, 16, 256, 1024 baked point lights
TEXEL_DENSITIES = [6.25, 12.5, 25.0, 50.0, 100.0]
TEXEL_SEGMENTS = 24
EMITTER_SEGMENTS = 14
REAL_LEVELS = [  # name, level file (real lights, default texel density: ~256k texels)
    ("cornell_box_original", os.path.join(ROOT, "samples/levels/cornell/level.json")),
    ("cornell_box_vinc3r", os.path.join(SCENES, "cornell_box_vinc3r/cornellBox-2.80-Eevee-gltf.gltf")),
    ("virtual_city", os.path.join(ROOT, "samples/levels/city/level.json")),
    ("sponza", os.path.join(ROOT, "samples/levels/sponza/level.json")),
]
RUNTIME_OBJECTS = [1, 4, 16, 64]
RUNTIME_FRAMES = 2
# Triangle series: a fixed budget of samples per frame at the default map
# resolution, so a frame is that many maps of the level (cost per map).
RUNTIME_TRIANGLE_BUDGET = 32
# Object and emitter series: every emitter current (budget 0) at 32x32 map
# faces, so a settle-everything frame stays within a minute on llvmpipe.
RUNTIME_SETTLE_RESOLUTION = 32
STAGES = ["load", "radiosity", "atlas", "texels", "lighting", "pages", "runtime", "write"]
RUNTIME_STAGES = ["maps_ms", "reduction_ms", "bounce_ms", "upload_ms"]


# ---------------------------------------------------------------- level writer

def sphere(segments):
    """UV sphere of SPHERE_RADIUS_M, outward: (positions, normals, indices);
    segments around, segments/2 rings from pole to pole, segments^2 - 2 segments triangles."""
    rings = segments // 2
    pos, nrm, idx = array.array("f"), array.array("f"), array.array("I")
    pos.extend([0, SPHERE_RADIUS_M, 0]); nrm.extend([0, 1, 0])
    for r in range(1, rings):
        theta = math.pi * r / rings
        for s in range(segments):
            phi = 2 * math.pi * s / segments
            n = (math.sin(theta) * math.cos(phi), math.cos(theta), math.sin(theta) * math.sin(phi))
            nrm.extend(n)
            pos.extend(SPHERE_RADIUS_M * c for c in n)
    pos.extend([0, -SPHERE_RADIUS_M, 0]); nrm.extend([0, -1, 0])
    bottom = 1 + (rings - 1) * segments

    def ring(r, s):  # vertex of ring r (1..rings-1), segment s
        return 1 + (r - 1) * segments + s % segments
    for s in range(segments):  # caps; CCW seen from outside
        idx.extend([0, ring(1, s + 1), ring(1, s)])
        idx.extend([bottom, ring(rings - 1, s), ring(rings - 1, s + 1)])
    for r in range(1, rings - 1):
        for s in range(segments):
            a, b, c, d = ring(r, s), ring(r, s + 1), ring(r + 1, s + 1), ring(r + 1, s)
            idx.extend([a, b, c, a, c, d])
    return pos, nrm, idx


def quads(corner_lists, normal):
    """Flat quads (4 corners each, in order around) facing `normal`."""
    pos, nrm, idx = array.array("f"), array.array("f"), array.array("I")
    for corners in corner_lists:
        base = len(pos) // 3
        a, b, c = corners[0], corners[1], corners[2]
        u = [b[k] - a[k] for k in range(3)]
        v = [c[k] - a[k] for k in range(3)]
        cross = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
        order = [0, 1, 2, 0, 2, 3] if sum(cross[k] * normal[k] for k in range(3)) > 0 else [0, 2, 1, 0, 3, 2]
        for p in corners:
            pos.extend(p)
            nrm.extend(normal)
        idx.extend(base + k for k in order)
    return pos, nrm, idx


def room_faces():
    """(material, geometry) per face of the room's inside."""
    h, y = ROOM_HALF_M, ROOM_HEIGHT_M
    return [
        ("floor", quads([[[-h, 0, -h], [h, 0, -h], [h, 0, h], [-h, 0, h]]], [0, 1, 0])),
        ("ceiling", quads([[[-h, y, -h], [h, y, -h], [h, y, h], [-h, y, h]]], [0, -1, 0])),
        ("wall", quads([[[-h, 0, -h], [h, 0, -h], [h, y, -h], [-h, y, -h]]], [0, 0, 1])),
        ("wall", quads([[[-h, 0, h], [h, 0, h], [h, y, h], [-h, y, h]]], [0, 0, -1])),
        ("wall", quads([[[-h, 0, -h], [-h, 0, h], [-h, y, h], [-h, y, -h]]], [1, 0, 0])),
        ("wall", quads([[[h, 0, -h], [h, 0, h], [h, y, h], [h, y, -h]]], [-1, 0, 0])),
    ]


def lamp_grid(k):
    """k x k emissive quads, each the middle half (by edge) of its cell: 4 m2 in all."""
    cell = 2 * LAMP_HALF_M / k
    half = cell / 4
    corners = []
    for i in range(k):
        for j in range(k):
            cx, cz = -LAMP_HALF_M + (i + 0.5) * cell, -LAMP_HALF_M + (j + 0.5) * cell
            corners.append([[cx - half, LAMP_Y_M, cz - half], [cx + half, LAMP_Y_M, cz - half],
                            [cx + half, LAMP_Y_M, cz + half], [cx - half, LAMP_Y_M, cz + half]])
    return quads(corners, [0, -1, 0])


def write_level(out_dir, segments, lamps, point_lights=0):
    """Writes scene.gltf, scene.bin and level.json; returns the static triangle
    count. lamps = 0: no lamp quads; point_lights = K > 0 adds K x K baked point
    lights 0.3 m under the ceiling over the lamp area, POINT_LIGHTS_CD in all."""
    os.makedirs(out_dir, exist_ok=True)
    materials = [("floor", [0.5, 0.45, 0.4], None), ("ceiling", [0.8, 0.8, 0.8], None),
                 ("wall", [0.7, 0.7, 0.68], None), ("sphere", [0.6, 0.5, 0.4], None),
                 ("lamp", [0.8, 0.8, 0.8], LAMP_LUMINANCE)]
    material_index = {m[0]: i for i, m in enumerate(materials)}
    blob = bytearray()
    views, accessors = [], []

    def add(data, target, component, kind, count, bounds=None):
        while len(blob) % 4:
            blob.append(0)
        views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(data) * 4, "target": target})
        blob.extend(data.tobytes())
        acc = {"bufferView": len(views) - 1, "componentType": component, "count": count, "type": kind}
        if bounds:
            acc["min"], acc["max"] = bounds
        accessors.append(acc)
        return len(accessors) - 1

    def primitive(material, geometry):
        pos, nrm, idx = geometry
        xs, ys, zs = pos[0::3], pos[1::3], pos[2::3]
        bounds = ([min(xs), min(ys), min(zs)], [max(xs), max(ys), max(zs)])
        p = add(pos, 34962, 5126, "VEC3", len(pos) // 3, bounds)
        n = add(nrm, 34962, 5126, "VEC3", len(nrm) // 3)
        i = add(idx, 34963, 5125, "SCALAR", len(idx))
        return {"attributes": {"POSITION": p, "NORMAL": n}, "indices": i, "material": material_index[material]}

    meshes = [{"name": "room", "primitives": [primitive(m, g) for m, g in room_faces()]},
              {"name": "sphere", "primitives": [primitive("sphere", sphere(segments))]}]
    nodes = [{"name": "room", "mesh": 0}]
    if lamps:
        meshes.append({"name": "lamps", "primitives": [primitive("lamp", lamp_grid(lamps))]})
        nodes.append({"name": "lamps", "mesh": 2})
    lights = []
    for i in range(point_lights):
        for j in range(point_lights):
            cell = 2 * LAMP_HALF_M / point_lights
            lights.append({"name": f"light_{i}_{j}", "type": "point", "intensity": POINT_LIGHTS_CD / point_lights ** 2})
            nodes.append({"name": f"light_{i}_{j}", "extensions": {"KHR_lights_punctual": {"light": len(lights) - 1}},
                          "translation": [-LAMP_HALF_M + (i + 0.5) * cell, ROOM_HEIGHT_M - 0.3,
                                          -LAMP_HALF_M + (j + 0.5) * cell]})
    for i in range(SPHERE_GRID):
        for j in range(SPHERE_GRID):
            offset = (SPHERE_GRID - 1) / 2
            nodes.append({"name": f"sphere_{i}_{j}", "mesh": 1,
                          "translation": [(i - offset) * SPHERE_PITCH_M, SPHERE_RADIUS_M + 0.01,
                                          (j - offset) * SPHERE_PITCH_M]})
    gltf_materials = []
    for name, albedo, luminance in materials:
        m = {"name": name, "pbrMetallicRoughness": {"baseColorFactor": albedo + [1.0], "metallicFactor": 0.0,
                                                     "roughnessFactor": 1.0}}
        if luminance:
            m["emissiveFactor"] = [1.0, 1.0, 1.0]
            m["extensions"] = {"KHR_materials_emissive_strength": {"emissiveStrength": luminance}}
        gltf_materials.append(m)
    gltf = {"asset": {"version": "2.0", "generator": "svit tests/bench/scaling.py"},
            "extensionsUsed": ["KHR_materials_emissive_strength"] + (["KHR_lights_punctual"] if lights else []),
            "scene": 0, "scenes": [{"nodes": list(range(len(nodes)))}], "nodes": nodes, "meshes": meshes,
            "materials": gltf_materials, "accessors": accessors, "bufferViews": views,
            "buffers": [{"uri": "scene.bin", "byteLength": len(blob)}]}
    if lights:
        gltf["extensions"] = {"KHR_lights_punctual": {"lights": lights}}
    with open(os.path.join(out_dir, "scene.bin"), "wb") as f:
        f.write(blob)
    with open(os.path.join(out_dir, "scene.gltf"), "w") as f:
        json.dump(gltf, f, indent=1)
    level = {"description": f"scaling.py: room, 64 spheres of {segments} segments, {lamps}x{lamps} lamp quads, "
                            f"{point_lights}x{point_lights} point lights",
             "gltf": "scene.gltf",
             "objects": [{"name": "crate", "shape": "box", "size_m": 0.3, "albedo": 0.6,
                          "translation": [3.5, 0.16, 3.5], "dynamic": True}]}
    with open(os.path.join(out_dir, "level.json"), "w") as f:
        json.dump(level, f, indent=1)
    return 12 + SPHERE_GRID ** 2 * (segments * segments - 2 * segments) + 2 * lamps * lamps


# ---------------------------------------------------------------- measuring

def load_avg():
    return [round(x, 2) for x in os.getloadavg()]


def static_triangles(build, level):
    info = subprocess.run([os.path.join(build, "baker/svit-info"), level, "--json"], check=True,
                          capture_output=True, text=True)
    summary = json.loads(info.stdout)
    return summary["triangles"]["static"], summary["emitters"]["emissive_triangles"], summary["lights"]["point"]


def run_group(cmd, timeout_s):
    """Runs cmd in its own process group; None (the whole group killed) past
    timeout_s, since killing only the child would leave what /usr/bin/time or
    xvfb-run started running."""
    child = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True)
    try:
        stdout, stderr = child.communicate(timeout=timeout_s)
    except subprocess.TimeoutExpired:
        os.killpg(child.pid, signal.SIGKILL)
        child.communicate()
        return None
    return subprocess.CompletedProcess(cmd, child.returncode, stdout, stderr)


def bake(build, level, out_dir, texels_per_m, timeout_s):
    """Bakes `level` into out_dir/bake under /usr/bin/time -v; returns the point
    (kept in out_dir/point.json, so a rerun reuses it), or None past timeout_s."""
    saved = os.path.join(out_dir, "point.json")
    if os.path.exists(saved):
        with open(saved) as f:
            return json.load(f)
    os.makedirs(out_dir, exist_ok=True)
    cmd = ["/usr/bin/time", "-v", os.path.join(build, "baker/svit-bake"), level, "-o", os.path.join(out_dir, "bake"),
           "--quality", str(QUALITY), "--seed", str(SEED), "--quiet"]
    if texels_per_m:
        cmd += ["--texels-per-m", str(texels_per_m)]
    load_before = load_avg()
    done = run_group(cmd, timeout_s)
    if done is None:
        print(f"  timed out after {timeout_s} s: {level}", flush=True)
        return None
    if done.returncode != 0:
        sys.exit(f"svit-bake failed on {level}:\n{done.stderr}")
    rss_kb = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", done.stderr).group(1))
    # CPU seconds (user + system) of the whole process: less inflated than
    # wall time when other jobs share the cores.
    cpu_s = sum(float(re.search(rf"{what} time \(seconds\): ([0-9.]+)", done.stderr).group(1))
                for what in ("User", "System"))
    with open(os.path.join(out_dir, "time.txt"), "w") as f:
        f.write(done.stderr)
    with open(os.path.join(out_dir, "bake", "report.json")) as f:
        report = json.load(f)
    triangles, emissive, point_lights = static_triangles(build, level)
    point = {"level": os.path.relpath(level, ROOT), "static_triangles": triangles, "emissive_triangles": emissive,
             "point_lights": point_lights,
             "texels_per_m": report["texels_per_m"], "covered_texels": report["lightmap"]["covered_texels"],
             "page_texels": report["lightmap"]["pages"] * report["lightmap"]["page_width"] * report["lightmap"]["page_height"],
             "radiosity_rays": report["radiosity"]["rays"], "radiosity_elements": report["radiosity"]["elements"],
             "radiosity_leaves": report["radiosity"]["leaves"], "radiosity_passes": report["radiosity"]["passes"],
             "stage_seconds": report["stage_seconds"], "total_seconds": report["total_seconds"],
             "peak_rss_mb": rss_kb / 1024.0, "cpu_seconds": cpu_s, "load_before": load_before, "load_after": load_avg()}
    with open(saved, "w") as f:
        json.dump(point, f, indent=1)
    return point


def runtime_point(build, level, bake_dir, out_json, proxies, objects, budget, resolution, timeout_s):
    """One bench_scaling_runtime run under Xvfb; None past timeout_s."""
    if os.path.exists(out_json):
        with open(out_json) as f:
            return json.load(f)
    cmd = ["xvfb-run", "-a", "-s", "-screen 0 640x480x24", os.path.join(build, "tests/bench/bench_scaling_runtime"),
           level, bake_dir, "--proxies", str(int(proxies)), "--objects", str(objects),
           "--frames", str(RUNTIME_FRAMES), "--budget-samples", str(budget), "--map-resolution", str(resolution),
           "--json", out_json]
    load_before = load_avg()
    done = run_group(cmd, timeout_s)
    if done is None:
        print(f"  timed out after {timeout_s} s: runtime {level} proxies={proxies} objects={objects}", flush=True)
        return None
    if done.returncode != 0:
        sys.exit(f"bench_scaling_runtime failed:\n{done.stdout}\n{done.stderr}")
    print("  " + done.stdout.strip(), flush=True)
    with open(out_json) as f:
        point = json.load(f)
    point["load_before"], point["load_after"] = load_before, load_avg()
    with open(out_json, "w") as f:
        json.dump(point, f, indent=1)
    return point


def run(args):
    out = os.path.abspath(args.out)
    build = os.path.abspath(args.build)
    series = set(args.series.split(","))
    results = {"machine": os.uname().nodename, "cpus": os.cpu_count(), "quality": QUALITY, "seed": SEED,
               "texels_per_m": TEXELS_PER_M, "started": time.strftime("%Y-%m-%d %H:%M:%S"),
               "load_start": load_avg()}
    levels = os.path.join(out, "levels")

    def synthetic(segments, lamps, point_lights=0):
        d = os.path.join(levels, f"s{segments}_k{lamps}" + (f"_p{point_lights}" if point_lights else ""))
        if not os.path.exists(os.path.join(d, "level.json")):
            write_level(d, segments, lamps, point_lights)
        return d

    def bake_series(name, cases):
        points = []
        for label, level, point_dir, tpm in cases:
            print(f"[{name}] {label}", flush=True)
            p = bake(build, level, point_dir, tpm, args.bake_timeout)
            if p is None:
                results.setdefault("cut", []).append(f"{name}: {label} (over {args.bake_timeout} s)")
                break  # bigger cases would take longer still
            p["label"] = label
            points.append(p)
            print(f"  {p['total_seconds']:.1f} s, {p['peak_rss_mb']:.0f} MB, {p['static_triangles']} triangles, "
                  f"{p['covered_texels']} texels", flush=True)
        results[name] = points

    segments = [s for s in TRIANGLE_SEGMENTS if s <= args.max_segments]
    if "triangles" in series:
        bake_series("bake_triangles", [(f"{s} segments", os.path.join(synthetic(s, 1), "level.json"),
                                        synthetic(s, 1), TEXELS_PER_M) for s in segments])
    if "real" in series:
        bake_series("bake_real", [(name, path, os.path.join(out, "real", name), None)
                                  for name, path in REAL_LEVELS if os.path.exists(path)])
    if "emitters" in series:
        bake_series("bake_emitters", [(f"{k * k} lamps", os.path.join(synthetic(EMITTER_SEGMENTS, k), "level.json"),
                                       synthetic(EMITTER_SEGMENTS, k), TEXELS_PER_M)
                                      for k in EMITTER_GRID])
    if "lights" in series:
        bake_series("bake_lights", [(f"{k * k} point lights", os.path.join(synthetic(EMITTER_SEGMENTS, 0, k), "level.json"),
                                     synthetic(EMITTER_SEGMENTS, 0, k), TEXELS_PER_M) for k in POINT_LIGHT_GRID])
    if "texels" in series:
        d = synthetic(TEXEL_SEGMENTS, 1)
        bake_series("bake_texels", [(f"{t} texels/m", os.path.join(d, "level.json"),
                                     os.path.join(out, "texels", f"tpm{t}"), t) for t in TEXEL_DENSITIES])

    def rt_series(name, cases):
        points = []
        for label, level, bake_dir, proxies, objects, key in cases:
            print(f"[{name}] {label}", flush=True)
            os.makedirs(os.path.join(out, "runtime"), exist_ok=True)
            budget, resolution = ((RUNTIME_TRIANGLE_BUDGET, 128) if name == "runtime_triangles"
                                  else (0, RUNTIME_SETTLE_RESOLUTION))
            p = runtime_point(build, level, bake_dir, os.path.join(out, "runtime", key + ".json"), proxies, objects,
                              budget, resolution, args.runtime_timeout)
            if p is None:
                results.setdefault("cut", []).append(f"{name}: {label} (over {args.runtime_timeout} s)")
                continue
            p["label"] = label
            points.append(p)
        results[name] = points

    if "rt_triangles" in series:
        cases = []
        for s in segments:
            d = synthetic(s, 1)
            if os.path.exists(os.path.join(d, "point.json")):
                for proxies in (0, 1):
                    cases.append((f"{s} segments proxies={proxies}", os.path.join(d, "level.json"),
                                  os.path.join(d, "bake"), proxies, 1, f"tri_s{s}_p{proxies}"))
        rt_series("runtime_triangles", cases)
    if "rt_objects" in series:
        d = synthetic(EMITTER_SEGMENTS, 1)
        rt_series("runtime_objects", [(f"{n} objects", os.path.join(d, "level.json"), os.path.join(d, "bake"), 0, n,
                                       f"obj_n{n}") for n in RUNTIME_OBJECTS])
    if "rt_emitters" in series:
        cases = []
        for k in EMITTER_GRID:
            d = synthetic(EMITTER_SEGMENTS, k)
            if os.path.exists(os.path.join(d, "point.json")):
                cases.append((f"{k * k} lamps", os.path.join(d, "level.json"), os.path.join(d, "bake"), 0, 4,
                              f"emit_k{k}"))
        rt_series("runtime_emitters", cases)

    if "rt_lights" in series:
        cases = []
        for k in POINT_LIGHT_GRID:
            d = synthetic(EMITTER_SEGMENTS, 0, k)
            if os.path.exists(os.path.join(d, "point.json")):
                cases.append((f"{k * k} point lights", os.path.join(d, "level.json"), os.path.join(d, "bake"), 0, 4,
                              f"lights_k{k}"))
        rt_series("runtime_lights", cases)

    results["finished"] = time.strftime("%Y-%m-%d %H:%M:%S")
    results["load_end"] = load_avg()
    path = os.path.join(out, "results.json")
    if os.path.exists(path):  # keep series measured by an earlier call with other --series
        with open(path) as f:
            old = json.load(f)
        old.update({k: v for k, v in results.items() if k != "cut"})
        old["cut"] = sorted(set(old.get("cut", []) + results.get("cut", [])))
        results = old
    with open(path, "w") as f:
        json.dump(results, f, indent=1)
    plot(argparse.Namespace(out=out))


# ---------------------------------------------------------------- fits and plots

def fit_exponent(xs, ys):
    """Least-squares slope and intercept of log y against log x (points with y > 0)."""
    pts = [(math.log(x), math.log(y)) for x, y in zip(xs, ys) if x > 0 and y > 0]
    if len(pts) < 2:
        return None
    mx = sum(p[0] for p in pts) / len(pts)
    my = sum(p[1] for p in pts) / len(pts)
    sxx = sum((p[0] - mx) ** 2 for p in pts)
    if sxx == 0:
        return None
    slope = sum((p[0] - mx) * (p[1] - my) for p in pts) / sxx
    return slope, my - slope * mx


def exponents(xs, ys):
    """Slope over all points and over the largest three (the asymptotic growth)."""
    whole = fit_exponent(xs, ys)
    top = fit_exponent(xs[-3:], ys[-3:]) if len(xs) > 3 else whole
    return {"all": whole[0] if whole else None, "top3": top[0] if top else None}


def bake_curves(points, x_key):
    """x values and named y series (per stage, total, peak RSS) of a bake series."""
    xs = [p[x_key] for p in points]
    curves = {stage: [p["stage_seconds"].get(stage, 0.0) for p in points] for stage in STAGES}
    curves["total"] = [p["total_seconds"] for p in points]
    if all("cpu_seconds" in p for p in points):  # user + system, whole process
        curves["cpu_seconds"] = [p["cpu_seconds"] for p in points]
    curves["peak_rss_mb"] = [p["peak_rss_mb"] for p in points]
    return xs, curves


def runtime_curves(points, x_key):
    xs = [p[x_key] for p in points]
    curves = {stage: [p[stage] for p in points]
              for stage in RUNTIME_STAGES + ["total_ms", "samples", "runtime_emitters", "bake_emitters",
                                             "fallback_triangles"]}
    return xs, curves


def x_of(p, series):
    if series == "bake_emitters":
        return p["emissive_triangles"] // 2  # quads
    if series == "bake_texels":
        return p["covered_texels"]
    if series == "bake_lights":
        return p["point_lights"]
    return p["static_triangles"]


def table(title, x_name, xs, labels, curves, fits, fmt):
    lines = [f"### {title}", "", "| " + x_name + " | " + " | ".join(curves) + " |",
             "|---:|" + "---:|" * len(curves)]
    for i, x in enumerate(xs):
        lines.append(f"| {x:,} | " + " | ".join(fmt(curves[c][i]) for c in curves) + " |")
    lines.append("| **exponent (all)** | " + " | ".join(
        f"{fits[c]['all']:.2f}" if fits[c]["all"] is not None else "n/a" for c in curves) + " |")
    lines.append("| **exponent (top 3)** | " + " | ".join(
        f"{fits[c]['top3']:.2f}" if fits[c]["top3"] is not None else "n/a" for c in curves) + " |")
    return lines + [""]


def plot(args):
    out = os.path.abspath(args.out)
    with open(os.path.join(out, "results.json")) as f:
        results = json.load(f)
    md = ["# svit scaling benchmark", "",
          f"quality {results['quality']}, seed {results['seed']}, {results['cpus']} CPUs; load averages "
          f"start {results.get('load_start')}, end {results.get('load_end')}", ""]
    fits_out = {}
    for series, x_name in (("bake_triangles", "static triangles"), ("bake_real", "static triangles"),
                           ("bake_emitters", "emissive quads"), ("bake_lights", "point lights"),
                           ("bake_texels", "covered texels")):
        points = sorted(results.get(series, []), key=lambda p: x_of(p, series))
        if not points:
            continue
        xs = [x_of(p, series) for p in points]
        _, curves = bake_curves(points, "static_triangles")
        fits = {c: exponents(xs, ys) for c, ys in curves.items()}
        fits_out[series] = fits
        md += table(series + " (seconds; peak RSS in MB)", x_name, xs, [p["label"] for p in points], curves, fits,
                    lambda v: f"{v:.3g}")
    for series, x_key, x_name in (("runtime_triangles", "static_triangles", "static triangles"),
                                  ("runtime_objects", "objects", "dynamic objects"),
                                  ("runtime_emitters", "lamp_quads", "lamp quads"),
                                  ("runtime_lights", "point_lights", "baked point lights")):
        points = results.get(series, [])
        if not points:
            continue
        groups = {}
        for p in points:
            bake_point = level_point(p)
            p["static_triangles"] = bake_point["static_triangles"]
            p["lamp_quads"] = bake_point["emissive_triangles"] // 2
            p["point_lights"] = bake_point.get("point_lights", 0)
            groups.setdefault(("proxies" if p["proxies"] else "full") if series == "runtime_triangles" else "", []).append(p)
        for group, pts in groups.items():
            pts.sort(key=lambda p: p[x_key])
            xs, curves = runtime_curves(pts, x_key)
            fits = {c: exponents(xs, ys) for c, ys in curves.items()}
            fits_out[series + (":" + group if group else "")] = fits
            md += table(f"{series} {group} (ms per frame, {RUNTIME_FRAMES}-frame mean)", x_name, xs,
                        [p["label"] for p in pts], curves, fits, lambda v: f"{v:.3g}")
    if results.get("cut"):
        md += ["Cut (over the time limit): " + "; ".join(results["cut"]), ""]
    results["exponents"] = fits_out
    with open(os.path.join(out, "results.json"), "w") as f:
        json.dump(results, f, indent=1)
    with open(os.path.join(out, "results.md"), "w") as f:
        f.write("\n".join(md) + "\n")
    print("\n".join(md))
    draw(out, results)


def level_point(runtime_point_json):
    """The bake point (point.json) of the level a runtime point ran on."""
    level_dir = os.path.dirname(runtime_point_json["level"])
    with open(os.path.join(level_dir, "point.json")) as f:
        return json.load(f)


def slopes(fit):
    """Legend text: exponent over all points and over the largest three."""
    if fit["all"] is None:
        return ""
    return f"(n^{fit['all']:.2f}; top 3: n^{fit['top3']:.2f})"


def draw(out, results):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    colours = dict(zip(STAGES + ["total"], ["#7f7f7f", "#1f77b4", "#ff7f0e", "#8c564b", "#2ca02c", "#bcbd22",
                                           "#9467bd", "#17becf", "#000000"]))
    fig, axes = plt.subplots(2, 2, figsize=(13, 10))
    loads = [x for series, points in results.items() if isinstance(points, list)
             for p in points if isinstance(p, dict) for x in (p.get("load_before", [None])[0],
                                                              p.get("load_after", [None])[0]) if x is not None]
    note = (f"1-min load average {min(loads):.1f} to {max(loads):.1f} during the runs "
            "(2-core machine shared with other jobs: wall times inflated)") if loads else ""

    def stage_panel(ax, series, x_label, title):
        points = sorted(results.get(series, []), key=lambda p: x_of(p, series))
        if not points:
            ax.set_visible(False)
            return
        xs = [x_of(p, series) for p in points]
        _, curves = bake_curves(points, "static_triangles")
        fits = results["exponents"][series]
        for c in STAGES + ["total"]:
            ys = curves[c]
            if max(ys) <= 0.005:
                continue
            ax.plot(xs, ys, "o-", color=colours[c], lw=2.5 if c == "total" else 1.2, label=f"{c} {slopes(fits[c])}")
        ax.set_xscale("log"); ax.set_yscale("log")
        ax.set_xlabel(x_label); ax.set_ylabel("seconds"); ax.set_title(title)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)

    stage_panel(axes[0][0], "bake_triangles", "static triangles (synthetic room, 25 texels/m)",
                "Baker time by stage vs triangles")
    real = results.get("bake_real", [])
    if real:
        ax = axes[0][0]
        ax.plot([p["static_triangles"] for p in real], [p["total_seconds"] for p in real], "s", color="red",
                label="real levels, total (default density)")
        for p in real:
            ax.annotate(p["label"], (p["static_triangles"], p["total_seconds"]), fontsize=7, color="red",
                        xytext=(3, 3), textcoords="offset points")
        ax.legend(fontsize=8)
    ax = axes[0][1]
    tri = sorted(results.get("bake_triangles", []), key=lambda p: p["static_triangles"])
    if tri:
        xs = [p["static_triangles"] for p in tri]
        fit = results["exponents"]["bake_triangles"]["peak_rss_mb"]
        ax.plot(xs, [p["peak_rss_mb"] for p in tri], "o-", color="black", label=f"synthetic {slopes(fit)}")
    if real:
        ax.plot([p["static_triangles"] for p in real], [p["peak_rss_mb"] for p in real], "s", color="red",
                label="real levels")
        for p in real:
            ax.annotate(p["label"], (p["static_triangles"], p["peak_rss_mb"]), fontsize=7, color="red",
                        xytext=(3, 3), textcoords="offset points")
    ax.set_xscale("log"); ax.set_yscale("log")
    ax.set_xlabel("static triangles"); ax.set_ylabel("peak RSS, MB (/usr/bin/time -v)")
    ax.set_title("Baker peak memory vs triangles"); ax.grid(True, which="both", alpha=0.3); ax.legend(fontsize=8)
    stage_panel(axes[1][0], "bake_emitters", "emissive quads (same 4 m2) or point lights (dashed); same 6.3 klm",
                "Baker time vs emitters")
    lights = sorted(results.get("bake_lights", []), key=lambda p: p["point_lights"])
    if lights:
        ax = axes[1][0]
        fits = results["exponents"]["bake_lights"]
        xs = [p["point_lights"] for p in lights]
        _, curves = bake_curves(lights, "static_triangles")
        for c in ("radiosity", "lighting", "runtime", "total"):
            ax.plot(xs, curves[c], "s--", color=colours[c], lw=2.5 if c == "total" else 1.2,
                    label=f"point lights: {c} {slopes(fits[c])}")
        ax.legend(fontsize=7)
    stage_panel(axes[1][1], "bake_texels", "covered texels (--texels-per-m 6.25 .. 100)", "Baker time vs texels")
    fig.suptitle(f"svit-bake scaling, quality {results['quality']}\n{note}", fontsize=10)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "scaling-baker.png"), dpi=90)
    plt.close(fig)

    fig, axes = plt.subplots(1, 3, figsize=(16, 5.2))
    rcol = dict(zip(RUNTIME_STAGES + ["total_ms"], ["#1f77b4", "#ff7f0e", "#2ca02c", "#bcbd22", "#000000"]))
    ax = axes[0]
    for group, style in (("full", "-"), ("proxies", "--")):
        pts = sorted([p for p in results.get("runtime_triangles", []) if (p["proxies"] and group == "proxies")
                      or (not p["proxies"] and group == "full")], key=lambda p: p["static_triangles"])
        if not pts:
            continue
        fits = results["exponents"]["runtime_triangles:" + group]
        for c in ("maps_ms", "reduction_ms", "total_ms"):
            ax.plot([p["static_triangles"] for p in pts], [p[c] for p in pts], "o" + style, color=rcol[c],
                    lw=2.2 if c == "total_ms" else 1.2, label=f"{group} {c[:-3]} {slopes(fits[c])}")
    ax.set_xlabel(f"static triangles (1 crate, {RUNTIME_TRIANGLE_BUDGET}-sample budget per frame)")
    ax.set_title("Runtime frame vs static triangles")
    for ax, series, x_key, x_label, title in ((axes[1], "runtime_objects", "objects", "dynamic objects (10.8k-triangle room)",
                                               "Runtime frame vs dynamic objects"),
                                              (axes[2], "runtime_emitters", "lamp_quads",
                                               "lamp quads, 6.3 klm",
                                               "Runtime frame vs emitters (4 crates)")):
        pts = sorted(results.get(series, []), key=lambda p: p[x_key])
        if not pts:
            continue
        fits = results["exponents"][series]
        for c in RUNTIME_STAGES + ["total_ms"]:
            ys = [p[c] for p in pts]
            if max(ys) <= 0.01:
                continue
            ax.plot([p[x_key] for p in pts], ys, "o-", color=rcol[c], lw=2.2 if c == "total_ms" else 1.2,
                    label=f"{c[:-3]} {slopes(fits[c])}")
        ax.set_xlabel(x_label); ax.set_title(title)
    pts = sorted(results.get("runtime_lights", []), key=lambda p: p["point_lights"])
    if pts:
        fits = results["exponents"]["runtime_lights"]
        for c in ("maps_ms", "reduction_ms", "total_ms"):
            axes[2].plot([p["point_lights"] for p in pts], [p[c] for p in pts], "s--", color=rcol[c],
                         lw=2.2 if c == "total_ms" else 1.2, label=f"point lights: {c[:-3]} {slopes(fits[c])}")
        axes[2].set_xlabel("lamp quads (solid) or point lights (dashed), 6.3 klm")
    for ax in axes:
        ax.set_xscale("log"); ax.set_yscale("log"); ax.set_ylabel("ms per frame (llvmpipe)")
        ax.grid(True, which="both", alpha=0.3); ax.legend(fontsize=8)
    fig.suptitle(f"svit runtime scaling on Mesa llvmpipe under Xvfb: triangles at {RUNTIME_TRIANGLE_BUDGET} samples per frame "
                 f"(128x128 maps); objects and emitters with every emitter current (budget 0, "
                 f"{RUNTIME_SETTLE_RESOLUTION}x{RUNTIME_SETTLE_RESOLUTION} maps)\n"
                 + note, fontsize=10)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "scaling-runtime.png"), dpi=90)
    plt.close(fig)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="command", required=True)
    p = sub.add_parser("level", help="write one synthetic level")
    p.add_argument("out_dir")
    p.add_argument("--segments", type=int, default=14)
    p.add_argument("--lamps", type=int, default=1, help="K: K x K emissive quads")
    p = sub.add_parser("run", help="measure, fit and plot")
    p.add_argument("--build", required=True)
    p.add_argument("--out", required=True)
    p.add_argument("--series", default="triangles,real,emitters,lights,texels,rt_triangles,rt_objects,rt_emitters,rt_lights")
    p.add_argument("--max-segments", type=int, default=max(TRIANGLE_SEGMENTS))
    p.add_argument("--bake-timeout", type=int, default=900, help="seconds per bake; a series stops at the first over")
    p.add_argument("--runtime-timeout", type=int, default=300, help="seconds per runtime point")
    p = sub.add_parser("plot", help="refit and replot OUT/results.json")
    p.add_argument("--out", required=True)
    args = parser.parse_args()
    if args.command == "level":
        print(write_level(args.out_dir, args.segments, args.lamps), "static triangles")
    elif args.command == "run":
        run(args)
    else:
        plot(args)


if __name__ == "__main__":
    main()
