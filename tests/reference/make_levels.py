#!/usr/bin/env python3
"""Writes the reference's levels into tests/reference/levels/ (committed;
rerun only to change them):
- cornell_double_sided.gltf: samples/levels/cornell with every material but
  the lamp's `doubleSided: true`, as Blender and most exporters write it
  (issue 46). The lamp stays one-sided: Mitsuba's area lights emit on one
  side, and svit's double-sided emitters on both.
- furnace.gltf: a closed 2 m cube, faces inward, every face double-sided,
  albedo 0.9 and emitting 10 cd/m2: irradiance everywhere inside is
  pi * 10 / (1 - 0.9) = 314.16 lux, a closed form the Mitsuba reference is
  checked against too.
"""

import base64
import json
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


def cornell():
    src = os.path.join(ROOT, "samples/levels/cornell/CornellBox-Original.gltf")
    with open(src) as f:
        g = json.load(f)
    for m in g["materials"]:
        if not any(m.get("emissiveFactor", [0, 0, 0])):
            m["doubleSided"] = True
    for b in g["buffers"]:
        b["uri"] = "../../../samples/levels/cornell/" + b["uri"]
    g["asset"]["extras"] = {"svit": "tests/reference/make_levels.py: the Cornell box, double-sided"}
    return g


def furnace():
    s = 1.0
    corners = [(x, y, z) for x in (-s, s) for y in (0.0, 2 * s) for z in (-s, s)]
    # Each face's quad, counter-clockwise seen from inside the cube.
    faces = [(0, 4, 6, 2), (1, 3, 7, 5), (0, 1, 5, 4), (2, 6, 7, 3), (0, 2, 3, 1), (4, 5, 7, 6)]
    positions, indices = [], []
    for quad in faces:
        base = len(positions)
        positions += [corners[i] for i in quad]
        indices += [base, base + 1, base + 2, base, base + 2, base + 3]
    data = b"".join(struct.pack("<3f", *p) for p in positions)
    index_offset = len(data)
    data += b"".join(struct.pack("<H", i) for i in indices)
    return {
        "asset": {"version": "2.0", "extras": {"svit": "tests/reference/make_levels.py: furnace"}},
        "extensionsUsed": ["KHR_materials_emissive_strength"],
        "scene": 0, "scenes": [{"nodes": [0]}],
        "nodes": [{"name": "furnace", "mesh": 0}],
        "meshes": [{"name": "furnace", "primitives": [
            {"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]}],
        "materials": [{"name": "glowing", "doubleSided": True,
                       "pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.9, 0.9, 1],
                                                "metallicFactor": 0, "roughnessFactor": 1},
                       "emissiveFactor": [1, 1, 1],
                       "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 10}}}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": len(positions), "type": "VEC3",
             "min": [-s, 0, -s], "max": [s, 2 * s, s]},
            {"bufferView": 1, "componentType": 5123, "count": len(indices), "type": "SCALAR"}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": index_offset},
                        {"buffer": 0, "byteOffset": index_offset,
                         "byteLength": len(data) - index_offset}],
        "buffers": [{"byteLength": len(data), "uri": "data:application/octet-stream;base64," +
                     base64.b64encode(data).decode()}]}


def main():
    for name, level in (("cornell_double_sided", cornell()), ("furnace", furnace())):
        path = os.path.join(HERE, "levels", name + ".gltf")
        with open(path, "w") as f:
            json.dump(level, f, indent=1)
        print(path)


if __name__ == "__main__":
    main()
