"""World-space triangles of a glTF 2.0 level, read with the standard library
and numpy only (so the reference needs no svit code): every mesh primitive of
mode TRIANGLES reached from the default scene's nodes, node transforms
applied, with its material's linear base colour, emission (emissiveFactor x
KHR_materials_emissive_strength, cd/m2 per channel, as svit reads it) and
doubleSided. Textures are not read: the levels the reference serves use
factors only, and load() refuses a textured material rather than ignore it.
"""

import base64
import json
import os
import struct

import numpy as np

_COMPONENT = {5120: "b", 5121: "B", 5122: "h", 5123: "H", 5125: "I", 5126: "f"}
_WIDTH = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT4": 16}


def _buffers(gltf, folder):
    out = []
    for b in gltf["buffers"]:
        uri = b["uri"]
        if uri.startswith("data:"):
            out.append(base64.b64decode(uri.split(",", 1)[1]))
        else:
            with open(os.path.join(folder, uri), "rb") as f:
                out.append(f.read())
    return out


def _accessor(gltf, buffers, index):
    a = gltf["accessors"][index]
    view = gltf["bufferViews"][a["bufferView"]]
    fmt = _COMPONENT[a["componentType"]]
    width = _WIDTH[a["type"]]
    size = struct.calcsize(fmt)
    stride = view.get("byteStride", size * width)
    start = view.get("byteOffset", 0) + a.get("byteOffset", 0)
    data = buffers[view["buffer"]]
    rows = [struct.unpack_from("<" + fmt * width, data, start + i * stride) for i in range(a["count"])]
    return np.array(rows, dtype=np.float64 if fmt == "f" else np.int64).reshape(a["count"], width)


def _local(node):
    if "matrix" in node:
        return np.array(node["matrix"], dtype=np.float64).reshape(4, 4).T
    t = np.array(node.get("translation", [0, 0, 0]), dtype=np.float64)
    x, y, z, w = node.get("rotation", [0, 0, 0, 1])
    r = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                  [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                  [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])
    s = np.array(node.get("scale", [1, 1, 1]), dtype=np.float64)
    m = np.eye(4)
    m[:3, :3] = r * s
    m[:3, 3] = t
    return m


def _material(gltf, index, path):
    if index is None:
        return {"base_color": [1.0, 1.0, 1.0], "emission": [0.0, 0.0, 0.0], "double_sided": False}
    m = gltf["materials"][index]
    pbr = m.get("pbrMetallicRoughness", {})
    if "baseColorTexture" in pbr or "emissiveTexture" in m:
        raise SystemExit(f"{path}: material {index} '{m.get('name', '')}' has a texture; "
                         "the reference reads factors only")
    strength = m.get("extensions", {}).get("KHR_materials_emissive_strength", {}).get(
        "emissiveStrength", 1.0)
    return {"base_color": list(pbr.get("baseColorFactor", [1, 1, 1, 1])[:3]),
            "emission": [c * strength for c in m.get("emissiveFactor", [0, 0, 0])],
            "double_sided": bool(m.get("doubleSided", False))}


def load(path):
    """A list of {'triangles': (n, 3, 3) world metres, 'material': {...}}."""
    with open(path) as f:
        gltf = json.load(f)
    buffers = _buffers(gltf, os.path.dirname(os.path.abspath(path)))
    out = []

    def visit(index, parent):
        node = gltf["nodes"][index]
        world = parent @ _local(node)
        if "mesh" in node:
            for prim in gltf["meshes"][node["mesh"]]["primitives"]:
                if prim.get("mode", 4) != 4:
                    continue
                p = _accessor(gltf, buffers, prim["attributes"]["POSITION"])
                p = (world @ np.c_[p, np.ones(len(p))].T).T[:, :3]
                idx = (_accessor(gltf, buffers, prim["indices"]).reshape(-1)
                       if "indices" in prim else np.arange(len(p)))
                out.append({"triangles": p[idx.reshape(-1, 3)],
                            "material": _material(gltf, prim.get("material"), path)})
        for child in node.get("children", []):
            visit(child, world)

    scene = gltf["scenes"][gltf.get("scene", 0)]
    for root in scene["nodes"]:
        visit(root, np.eye(4))
    return out
