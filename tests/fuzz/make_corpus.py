#!/usr/bin/env python3
"""Writes the seed corpora of the fuzz targets into tests/fuzz/corpus/<target>/.

Python 3 standard library only and deterministic; the outputs are committed
(under 1 MB in all), so rerun this only when the seeds should change:

    python3 tests/fuzz/make_corpus.py [--bake-tool build/release/baker/svit-bake]

  fuzz_gltf          every .gltf of tests/data, plus rich.gltf: one file that
                     uses what the small cases do not (an embedded PNG texture
                     with a sampler and KHR_texture_transform, TEXCOORD_0/1,
                     a strided and a sparse accessor, normalized unsigned-byte
                     UVs, a triangle strip, a matrix node, child nodes, a spot
                     and a directional light, an animation with linear,
                     step and cubic-spline samplers)
  fuzz_glb           GLB versions of good_quad, good_emissive_quad,
                     dynamic_subtree and rich (its image in a bufferView),
                     and tests/data/truncated.glb
  fuzz_level_json    every .json of tests/data, plus rich.level.json (objects,
                     exclude, dynamic, paths by keys, all light types)
  fuzz_bake_file     bake.svit of good_emissive_quad.gltf (static only) and of
                     good_level.json (with runtime sections)
  fuzz_lightmap_exr  the lightmap-0.exr pages of those bakes

The bake seeds need the baker: with --bake-tool they are baked afresh (tiny
settings, one thread, seed 1); without it the committed ones are kept.
"""

import argparse
import base64
import json
import os
import shutil
import struct
import subprocess
import sys
import tempfile
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, "..", "data")
sys.path.insert(0, DATA)
import make_test_data as td  # noqa: E402  (the Gltf builder and the quad)

CORPUS = os.path.join(HERE, "corpus")
UNSIGNED_BYTE = 5121
MAX_CORPUS_BYTES = 1 << 20


def png_rgb(width, height, pixels):
    """A minimal 8-bit RGB PNG (stored with zlib, no filtering)."""
    def chunk(kind, data):
        return (struct.pack(">I", len(data)) + kind + data
                + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))
    raw = b"".join(b"\0" + bytes(c for p in pixels[y * width:(y + 1) * width] for c in p)
                   for y in range(height))
    return (b"\x89PNG\r\n\x1a\n"
            + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def rich(image_in_buffer=False):
    """The quad with most of what svit reads from a glTF in one file."""
    g = td.Gltf()
    index_view = g.index_view(td.QUAD_INDICES)
    # POSITION and NORMAL interleaved in one strided view (byteStride 24).
    interleaved = b"".join(struct.pack("<3f", *p) + struct.pack("<3f", *n)
                           for p, n in zip(td.QUAD_POSITIONS, td.QUAD_NORMALS))
    view = g.view(interleaved, td.ARRAY_BUFFER)
    g.doc["bufferViews"][view]["byteStride"] = 24
    lo = [min(p[i] for p in td.QUAD_POSITIONS) for i in range(3)]
    hi = [max(p[i] for p in td.QUAD_POSITIONS) for i in range(3)]
    position = g.accessor(view, td.FLOAT, 4, "VEC3", (lo, hi))
    normal = g.accessor(view, td.FLOAT, 4, "VEC3")
    g.doc["accessors"][normal]["byteOffset"] = 12
    # TEXCOORD_0 as normalized unsigned bytes (KHR_mesh_quantization).
    uv0_view = g.view(bytes([0, 255, 255, 255, 255, 0, 0, 0]), td.ARRAY_BUFFER)
    uv0 = g.accessor(uv0_view, UNSIGNED_BYTE, 4, "VEC2")
    g.doc["accessors"][uv0]["normalized"] = True
    # TEXCOORD_1: all zeros but vertex 2, through a sparse accessor.
    sparse_indices = g.view(struct.pack("<H", 2) + b"\0\0")
    sparse_values = g.view(struct.pack("<2f", 0.5, 0.25))
    g.doc["accessors"].append({"componentType": td.FLOAT, "count": 4, "type": "VEC2", "sparse": {
        "count": 1,
        "indices": {"bufferView": sparse_indices, "componentType": td.UNSIGNED_SHORT},
        "values": {"bufferView": sparse_values}}})
    uv1 = len(g.doc["accessors"]) - 1
    indices = g.accessor(index_view, td.UNSIGNED_SHORT, 6, "SCALAR")
    strip_view = g.index_view([0, 1, 3, 2])
    strip = g.accessor(strip_view, td.UNSIGNED_SHORT, 4, "SCALAR")
    attributes = {"POSITION": position, "NORMAL": normal, "TEXCOORD_0": uv0, "TEXCOORD_1": uv1}
    g.mesh("Quad", [{"attributes": attributes, "indices": indices, "material": 0, "mode": td.TRIANGLES},
                    {"attributes": {"POSITION": position}, "indices": strip, "material": 1,
                     "mode": td.TRIANGLE_STRIP}])
    png = png_rgb(2, 2, [(255, 0, 0), (0, 255, 0), (0, 0, 255), (255, 255, 255)])
    if image_in_buffer:
        image = {"name": "checker", "mimeType": "image/png", "bufferView": g.view(png)}
    else:
        image = {"name": "checker", "uri": "data:image/png;base64," + base64.b64encode(png).decode("ascii")}
    g.doc["images"] = [image]
    g.doc["samplers"] = [{"wrapS": 33071, "wrapT": 33648}]  # clamp, mirrored repeat
    g.doc["textures"] = [{"sampler": 0, "source": 0}]
    g.doc["materials"] = [
        {"name": "Checker", "doubleSided": True,
         "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1.0], "baseColorTexture": {
             "index": 0, "texCoord": 0,
             "extensions": {"KHR_texture_transform": {"offset": [0.5, 0], "rotation": 0.3,
                                                      "scale": [2, 2]}}}}},
        {"name": "Glow", "alphaMode": "MASK", "alphaCutoff": 0.3, "emissiveFactor": [1.0, 0.5, 0.25],
         "emissiveTexture": {"index": 0, "texCoord": 1},
         "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4.0}}},
    ]
    # Nodes: 0 Root (matrix) -> 1 Quad (TRS, mesh) ; 2 Spot ; 3 Sun ; 4 Spinner (animated).
    g.node({"name": "Root", "children": [1],
            "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0.5, 0, 1]})
    g.node({"name": "Quad", "mesh": 0, "translation": [0, 0, 0.1],
            "rotation": [0, 0.0871557, 0, 0.9961947], "scale": [1, 1, 2]}, root=False)
    g.doc["extensionsUsed"] = ["KHR_lights_punctual", "KHR_materials_emissive_strength",
                               "KHR_texture_transform", "KHR_mesh_quantization"]
    g.doc["extensionsRequired"] = ["KHR_mesh_quantization"]
    g.doc["extensions"] = {"KHR_lights_punctual": {"lights": [
        {"name": "spot", "type": "spot", "color": [1, 0.9, 0.8], "intensity": 50, "range": 10,
         "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.6}},
        {"name": "moon", "type": "directional", "intensity": 0.5},
    ]}}
    g.node({"name": "Spot", "translation": [0, 2, 0], "rotation": [-0.7071068, 0, 0, 0.7071068],
            "extensions": {"KHR_lights_punctual": {"light": 0}}})
    g.node({"name": "Sun", "extensions": {"KHR_lights_punctual": {"light": 1}},
            "extras": {"svit": {"dynamic": False}}})
    g.node({"name": "Spinner", "mesh": 0, "translation": [0, 1, 0], "extras": {"svit": {"dynamic": True}}})
    times = g.view(struct.pack("<2f", 0.0, 1.0))
    time_acc = g.accessor(times, td.FLOAT, 2, "SCALAR")
    g.doc["accessors"][time_acc]["min"], g.doc["accessors"][time_acc]["max"] = [0.0], [1.0]
    moves = g.accessor(g.view(struct.pack("<6f", 0, 1, 0, 0, 2, 0)), td.FLOAT, 2, "VEC3")
    turns = g.accessor(g.view(struct.pack("<8f", 0, 0, 0, 1, 0, 0.7071068, 0, 0.7071068)), td.FLOAT, 2, "VEC4")
    cubic = g.accessor(g.view(struct.pack("<18f", *([0, 0, 0, 1, 1, 1, 0, 0, 0] * 2))), td.FLOAT, 6, "VEC3")
    spinner = len(g.doc["nodes"]) - 1
    g.doc["animations"] = [{"name": "spin", "samplers": [
        {"input": time_acc, "output": moves},
        {"input": time_acc, "output": turns, "interpolation": "STEP"},
        {"input": time_acc, "output": cubic, "interpolation": "CUBICSPLINE"}], "channels": [
        {"sampler": 0, "target": {"node": spinner, "path": "translation"}},
        {"sampler": 1, "target": {"node": spinner, "path": "rotation"}},
        {"sampler": 2, "target": {"node": spinner, "path": "scale"}}]}]
    return g


def glb(g):
    """`g` as GLB 2.0: JSON chunk (space-padded) and BIN chunk."""
    doc = g.finish()
    blob = bytes(g.blob)
    doc["buffers"] = [{"byteLength": len(blob)}]
    json_chunk = json.dumps(doc, separators=(",", ":")).encode("utf-8")
    json_chunk += b" " * (-len(json_chunk) % 4)
    bin_chunk = td.pad4(blob)
    total = 12 + 8 + len(json_chunk) + 8 + len(bin_chunk)
    return (struct.pack("<4sII", b"glTF", 2, total)
            + struct.pack("<I4s", len(json_chunk), b"JSON") + json_chunk
            + struct.pack("<I4s", len(bin_chunk), b"BIN\0") + bin_chunk)


def quad_gltf(make):
    """A tests/data case builder that returns the Gltf before finish()."""
    g = td.quad()
    doc = make()
    g.doc = {k: v for k, v in doc.items() if k != "buffers"}
    for key in ("meshes", "accessors", "bufferViews", "materials"):
        g.doc.setdefault(key, [])
    return g


def rich_level():
    return {
        "gltf": "dynamic_subtree.gltf",
        "description": "fuzz seed: every level.json feature on the dynamic_subtree glTF",
        "sun": {"direction_to_sun": [0.3, 1, 0.2], "illuminance_lux": 50000, "angular_radius_rad": 0.01},
        "sky": {"model": "uniform", "zenith_luminance": 3000},
        "exclude": ["Floor"],
        "objects": [
            {"name": "ball", "shape": "sphere", "radius_m": 0.2, "segments": 6, "albedo": [0.7, 0.2, 0.1],
             "translation": [0, 0.5, 0], "rotation": [0, 0, 0, 1], "dynamic": True},
            {"name": "lantern", "shape": "box", "size_m": [0.1, 0.04, 0.1], "albedo": 0.1,
             "emissive_luminance": 5, "double_sided": True, "translation": [0.3, 1.2, 0.3]},
        ],
        "lights": [
            {"name": "carried", "type": "point", "node": "lantern", "position": [0, -0.08, 0], "intensity_cd": 30},
            {"name": "spot", "type": "spot", "position": [0, 2, 0], "direction": [0, -1, 0],
             "intensity_cd": 500, "inner_cone_rad": 0.3, "outer_cone_rad": 0.5, "dynamic": True},
            {"name": "moon", "type": "directional", "direction": [0, -1, 0.2], "illuminance_lux": 0.3},
        ],
        "dynamic": ["Hand", 0],
        "paths": [
            {"node": "Mover", "loop": True, "keys": [
                {"t_s": 0, "translation": [0, 1, 0]},
                {"t_s": 4, "translation": [0.3, 1, 0], "rotation": [0, 0.259, 0, 0.966], "scale": [1, 2, 1]}]},
            {"node": "ball", "loop": False, "keys": [{"t_s": 0}, {"t_s": 1, "translation": [0, 1, 0]}]},
        ],
        "camera_paths": [{"name": "main", "keys": [{"t_s": 0, "position": [0, 1, 3], "look_at": [0, 1, 0]}]}],
    }


def write(target, name, content):
    directory = os.path.join(CORPUS, target)
    os.makedirs(directory, exist_ok=True)
    if isinstance(content, dict):
        content = td.dumps(content)
    if isinstance(content, str):
        content = content.encode("utf-8")
    with open(os.path.join(directory, name), "wb") as f:
        f.write(content)


def copy_data(target, suffix):
    for name in sorted(os.listdir(DATA)):
        if name.endswith(suffix):
            shutil.copyfile(os.path.join(DATA, name), os.path.join(CORPUS, target, name))


def bake_seeds(tool):
    for level, name in (("good_emissive_quad.gltf", "static"), ("good_level.json", "runtime")):
        with tempfile.TemporaryDirectory() as out:
            subprocess.run([tool, os.path.join(DATA, level), "-o", out, "--seed", "1", "--threads", "1",
                            "--texels-per-m", "4", "--quality", "0.1", "--quiet"], check=True)
            with open(os.path.join(out, "bake.svit"), "rb") as f:
                write("fuzz_bake_file", name + ".svit", f.read())
            with open(os.path.join(out, "lightmap-0.exr"), "rb") as f:
                write("fuzz_lightmap_exr", name + ".exr", f.read())


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bake-tool", help="svit-bake, to bake the bake-file and EXR seeds afresh")
    args = parser.parse_args()
    for target in ("fuzz_gltf", "fuzz_glb", "fuzz_level_json"):
        shutil.rmtree(os.path.join(CORPUS, target), ignore_errors=True)
        os.makedirs(os.path.join(CORPUS, target))
    copy_data("fuzz_gltf", ".gltf")
    write("fuzz_gltf", "rich.gltf", rich().finish())
    copy_data("fuzz_glb", ".glb")
    write("fuzz_glb", "good_quad.glb", glb(td.quad()))
    write("fuzz_glb", "good_emissive_quad.glb", glb(quad_gltf(td.good_emissive_quad)))
    write("fuzz_glb", "dynamic_subtree.glb", glb(quad_gltf(td.dynamic_subtree)))
    write("fuzz_glb", "rich.glb", glb(rich(image_in_buffer=True)))
    copy_data("fuzz_level_json", ".json")
    write("fuzz_level_json", "rich.level.json", rich_level())
    if args.bake_tool:
        bake_seeds(args.bake_tool)
    total = sum(os.path.getsize(os.path.join(d, f)) for d, _, files in os.walk(CORPUS) for f in files)
    if total > MAX_CORPUS_BYTES:
        raise SystemExit("corpus is %d bytes, the limit is %d" % (total, MAX_CORPUS_BYTES))
    print("corpus: %d bytes in %s" % (total, CORPUS))


if __name__ == "__main__":
    main()
