#!/usr/bin/env python3
"""Writes the small bad-input glTF and level.json files of tests/data/.

Each file is named after the defect it holds (README.md lists them). Python 3
standard library only and deterministic: running it twice writes the same
bytes, so the outputs are committed and the script is only rerun when a case
changes. Every file stays under 4 KB.

    python3 tests/data/make_test_data.py [output_dir]   # default: this folder

Geometry used throughout (metres, +Y up, front faces counter-clockwise seen
from +Y, so every face normal is +Y unless a case says otherwise):

    the quad      v0 (-1,0, 0.5)  v1 (1,0, 0.5)  v2 (1,0,-0.5)  v3 (-1,0,-0.5)
                  triangles (0,1,2) (0,2,3); 2 m x 1 m = 2 m^2

Buffer layout of the quad files (one buffer, 108 bytes):

    bufferView 0  indices    offset  0, 12 bytes (6 x unsigned short)
    bufferView 1  POSITION   offset 12, 48 bytes (4 x vec3 float)
    bufferView 2  NORMAL     offset 60, 48 bytes (4 x vec3 float)
    accessor 0 = POSITION (view 1), accessor 1 = NORMAL (view 2),
    accessor 2 = indices (view 0)

The index view comes first on purpose: an accessor that overruns its
bufferView (accessor_out_of_bounds.gltf) still lies inside the buffer, so only
a per-view bounds check catches it.
"""

import base64
import json
import math
import os
import struct
import sys

# glTF constants.
FLOAT = 5126
UNSIGNED_SHORT = 5123
ARRAY_BUFFER = 34962
ELEMENT_ARRAY_BUFFER = 34963
POINTS, LINES, TRIANGLES, TRIANGLE_STRIP, TRIANGLE_FAN = 0, 1, 4, 5, 6

MAX_FILE_BYTES = 4096

QUAD_POSITIONS = [(-1.0, 0.0, 0.5), (1.0, 0.0, 0.5), (1.0, 0.0, -0.5), (-1.0, 0.0, -0.5)]
QUAD_NORMALS = [(0.0, 1.0, 0.0)] * 4
QUAD_INDICES = [0, 1, 2, 0, 2, 3]


def pad4(data):
    """Pads to a multiple of 4 bytes (glTF accessor alignment)."""
    return data + b"\0" * (-len(data) % 4)


class Gltf:
    """A minimal glTF 2.0 document with one buffer, built in a fixed order."""

    def __init__(self):
        self.blob = bytearray()
        self.doc = {
            "asset": {"version": "2.0", "generator": "svit tests/data/make_test_data.py"},
            "scene": 0,
            "scenes": [{"nodes": []}],
            "nodes": [],
            "meshes": [],
            "materials": [{
                "name": "Grey",
                "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1.0],
                                         "metallicFactor": 0.0},
            }],
            "accessors": [],
            "bufferViews": [],
            "buffers": [],
        }

    def view(self, data, target=None):
        """Appends `data` (4-aligned) to the buffer; returns its bufferView index."""
        offset = len(self.blob)
        self.blob += pad4(bytes(data))
        bv = {"buffer": 0, "byteOffset": offset, "byteLength": len(data)}
        if target is not None:
            bv["target"] = target
        self.doc["bufferViews"].append(bv)
        return len(self.doc["bufferViews"]) - 1

    def accessor(self, view, component_type, count, type_, minmax=None):
        acc = {"bufferView": view, "componentType": component_type, "count": count, "type": type_}
        if minmax is not None:
            acc["min"], acc["max"] = minmax
        self.doc["accessors"].append(acc)
        return len(self.doc["accessors"]) - 1

    def vec3_view(self, values):
        return self.view(b"".join(struct.pack("<3f", *v) for v in values), ARRAY_BUFFER)

    def vec2_view(self, values):
        return self.view(b"".join(struct.pack("<2f", *v) for v in values), ARRAY_BUFFER)

    def index_view(self, indices):
        return self.view(struct.pack("<%dH" % len(indices), *indices), ELEMENT_ARRAY_BUFFER)

    def position_accessor(self, view, positions):
        # min/max are required by the spec for POSITION; computed from the
        # finite values only so that nan_position.gltf stays valid JSON.
        finite = [v for v in positions if all(math.isfinite(c) for c in v)]
        lo = [min(v[i] for v in finite) for i in range(3)]
        hi = [max(v[i] for v in finite) for i in range(3)]
        return self.accessor(view, FLOAT, len(positions), "VEC3", (lo, hi))

    def mesh(self, name, primitives):
        self.doc["meshes"].append({"name": name, "primitives": primitives})
        return len(self.doc["meshes"]) - 1

    def node(self, node, root=True):
        self.doc["nodes"].append(node)
        index = len(self.doc["nodes"]) - 1
        if root:
            self.doc["scenes"][0]["nodes"].append(index)
        return index

    def finish(self, uri=None, byte_length=None):
        """Returns the document with the buffer attached (none when nothing
        was added): embedded as a base64 data URI unless `uri` names an
        external file. `byte_length` overrides the true length
        (short_buffer.gltf)."""
        if self.blob or uri is not None:
            if uri is None:
                uri = ("data:application/octet-stream;base64,"
                       + base64.b64encode(bytes(self.blob)).decode("ascii"))
            length = len(self.blob) if byte_length is None else byte_length
            self.doc["buffers"] = [{"byteLength": length, "uri": uri}]
        # Drop empty top-level arrays: glTF requires arrays to have >= 1 item.
        for key in ("meshes", "accessors", "bufferViews", "buffers", "materials"):
            if not self.doc[key]:
                del self.doc[key]
        return self.doc


def quad(positions=QUAD_POSITIONS, normals=QUAD_NORMALS, indices=QUAD_INDICES, name="Quad"):
    """The standard quad in the layout described at the top of this file:
    accessor 0 POSITION, 1 NORMAL (absent when normals is None), last indices."""
    g = Gltf()
    index_view = g.index_view(indices)
    position_view = g.vec3_view(positions)
    normal_view = g.vec3_view(normals) if normals is not None else None
    attributes = {"POSITION": g.position_accessor(position_view, positions)}
    if normal_view is not None:
        attributes["NORMAL"] = g.accessor(normal_view, FLOAT, len(normals), "VEC3")
    index_acc = g.accessor(index_view, UNSIGNED_SHORT, len(indices), "SCALAR")
    g.mesh(name, [{"attributes": attributes, "indices": index_acc, "material": 0, "mode": TRIANGLES}])
    g.node({"name": name, "mesh": 0})
    return g


def add_lights(g, lights):
    """Adds KHR_lights_punctual `lights`, each on its own root node named
    after it, and lists the extension in extensionsUsed."""
    g.doc["extensionsUsed"] = g.doc.get("extensionsUsed", []) + ["KHR_lights_punctual"]
    g.doc["extensions"] = {"KHR_lights_punctual": {"lights": lights}}
    for i, light in enumerate(lights):
        g.node({"name": light["name"], "translation": [0.0, 2.0, 0.0],
                "extensions": {"KHR_lights_punctual": {"light": i}}})


# ---------------------------------------------------------------------------
# The cases. Each returns the file's text (str) or bytes.

def good_quad():
    return quad().finish()


def good_emissive_quad():
    # Luminance 1 x 10 = 10 cd/m2 on a single-sided 2 m^2 quad:
    # flux = pi * L * area = pi * 10 * 2 = 20 pi lm = 62.83 lm.
    g = quad()
    g.doc["materials"][0] = {
        "name": "Glow",
        "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1.0], "metallicFactor": 0.0},
        "emissiveFactor": [1.0, 1.0, 1.0],
        "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 10.0}},
    }
    g.doc["extensionsUsed"] = ["KHR_materials_emissive_strength"]
    return g.finish()


def truncated_gltf():
    text = dumps(good_quad())
    return text[: len(text) // 2]  # cut in the middle of the JSON


def bad_json():
    # Valid up to the missing comma after "scene": 0 (line 7 of the file).
    text = dumps(good_quad())
    bad = text.replace('"scene": 0,', '"scene": 0', 1)
    assert bad != text
    return bad


def truncated_glb():
    # GLB 2.0: 12-byte header (magic, version, total length), then a JSON
    # chunk and a BIN chunk, each with an 8-byte header (length, type). The
    # header is valid and claims the full length; the file stops half-way
    # through the BIN chunk.
    g = quad()
    doc = g.finish()
    blob = bytes(g.blob)
    doc["buffers"] = [{"byteLength": len(blob)}]  # GLB-stored buffer: no uri
    json_chunk = json.dumps(doc, separators=(",", ":")).encode("utf-8")
    json_chunk += b" " * (-len(json_chunk) % 4)  # JSON chunk pads with spaces
    bin_chunk = pad4(blob)
    total = 12 + 8 + len(json_chunk) + 8 + len(bin_chunk)
    data = (struct.pack("<4sII", b"glTF", 2, total)
            + struct.pack("<I4s", len(json_chunk), b"JSON") + json_chunk
            + struct.pack("<I4s", len(bin_chunk), b"BIN\0") + bin_chunk)
    assert len(data) == total
    return data[: total - len(bin_chunk) // 2]


def missing_buffer_file():
    # External buffer that is not shipped; the script deletes any stale copy.
    return quad().finish(uri="does_not_exist.bin")


def short_buffer():
    # The data URI holds 108 bytes; byteLength claims 216.
    g = quad()
    return g.finish(byte_length=2 * len(g.blob))


def index_out_of_range():
    # Triangle 1 of primitive 0 uses index 9; the mesh has 4 vertices.
    return quad(indices=[0, 1, 2, 0, 2, 9]).finish()


def accessor_out_of_bounds():
    # Accessor 2 (indices) claims 12 unsigned shorts = 24 bytes, but its
    # bufferView 0 holds 12 bytes. The overrun (bytes 12..23) is still inside
    # the buffer, so only the per-view check catches it.
    g = quad()
    g.doc["accessors"][2]["count"] = 12
    return g.finish()


def buffer_view_out_of_bounds():
    # bufferView 2 (normals): byteOffset 60 + byteLength 96 = 156 > 108 bytes
    # in buffer 0. Accessor 1 still fits inside the (bad) view.
    g = quad()
    g.doc["bufferViews"][2]["byteLength"] = 96
    return g.finish()


def nan_position():
    # POSITION of vertex 2 has x = NaN (bytes 00 00 c0 7f); used by both triangles.
    positions = list(QUAD_POSITIONS)
    positions[2] = (float("nan"), 0.0, -0.5)
    return quad(positions=positions).finish()


def inf_normal():
    # NORMAL of vertex 1 has y = +Inf (bytes 00 00 80 7f).
    normals = list(QUAD_NORMALS)
    normals[1] = (0.0, float("inf"), 0.0)
    return quad(normals=normals).finish()


def zero_area_face():
    # 5 vertices; vertex 4 repeats vertex 1's position. Triangles 0 and 1 are
    # the quad; triangle 2 = (1, 2, 4) has two identical corners (distinct
    # indices, equal positions), so its area is 0: skipped with a warning.
    positions = QUAD_POSITIONS + [QUAD_POSITIONS[1]]
    normals = QUAD_NORMALS + [(0.0, 1.0, 0.0)]
    return quad(positions=positions, normals=normals, indices=QUAD_INDICES + [1, 2, 4]).finish()


def missing_texture():
    # baseColorTexture -> texture 0 -> image 0 -> no_such_texture.png, which
    # is not shipped. Import warns, counts it, and uses baseColorFactor alone.
    g = Gltf()
    index_view = g.index_view(QUAD_INDICES)
    position_view = g.vec3_view(QUAD_POSITIONS)
    normal_view = g.vec3_view(QUAD_NORMALS)
    uv_view = g.vec2_view([(0.0, 1.0), (1.0, 1.0), (1.0, 0.0), (0.0, 0.0)])
    attributes = {
        "POSITION": g.position_accessor(position_view, QUAD_POSITIONS),
        "NORMAL": g.accessor(normal_view, FLOAT, 4, "VEC3"),
        "TEXCOORD_0": g.accessor(uv_view, FLOAT, 4, "VEC2"),
    }
    indices = g.accessor(index_view, UNSIGNED_SHORT, 6, "SCALAR")
    g.mesh("Quad", [{"attributes": attributes, "indices": indices, "material": 0, "mode": TRIANGLES}])
    g.node({"name": "Quad", "mesh": 0})
    g.doc["materials"][0] = {
        "name": "Brick",
        "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.2, 0.1, 1.0],
                                 "baseColorTexture": {"index": 0},
                                 "metallicFactor": 0.0},
    }
    g.doc["samplers"] = [{"wrapS": 10497, "wrapT": 10497}]
    g.doc["images"] = [{"name": "brick", "uri": "no_such_texture.png"}]
    g.doc["textures"] = [{"sampler": 0, "source": 0}]
    return g.finish()


def negative_light_intensity():
    g = quad()
    add_lights(g, [{"name": "Lamp", "type": "point", "color": [1.0, 1.0, 1.0], "intensity": -5.0}])
    return g.finish()


def nan_light_intensity():
    # JSON has no NaN or Infinity literal, so this case carries the nearest
    # thing a parser lets through: an intensity that is a finite double but
    # not a finite float. "intensity": 1e300 parses (nlohmann::json, which
    # tinygltf 2.7 uses, and Python's json) to the double 1e300; converted to
    # the float svit::Light::intensity it becomes +Inf (and the conversion is
    # undefined behaviour in ISO C++), so the importer must range-check the
    # double (finite and <= FLT_MAX) before narrowing it. Rejected options:
    #   1e999   nlohmann 3.11 throws out_of_range.406 "number overflow parsing
    #           '1e999'", so tinygltf fails the whole file as a JSON error and
    #           the light check is never reached (that is bad_json.gltf).
    #   "NaN"   a string, not a number: tinygltf's ParseNumberProperty
    #           silently keeps the default 1.0 for it. That is a different
    #           defect (a non-number), covered by nonnumeric_light_intensity.gltf.
    # The number is patched into the text so that it is written exactly as
    # 1e300 (json.dumps would write 1e+300, equally valid).
    g = quad()
    add_lights(g, [{"name": "Lamp", "type": "point", "color": [1.0, 1.0, 1.0], "intensity": 12345.0}])
    text = dumps(g.finish())
    bad = text.replace("12345.0", "1e300", 1)
    assert bad != text
    return bad


def patched(doc, placeholder, literal):
    """The document's text with the number `placeholder` (written by
    json.dumps as in the text) replaced by `literal`, e.g. 1e300: a finite
    double that no float can hold (see nan_light_intensity)."""
    text = dumps(doc)
    bad = text.replace(placeholder, literal, 1)
    assert bad != text, placeholder
    return bad


QUAD_UVS = [(0.0, 1.0), (1.0, 1.0), (1.0, 0.0), (0.0, 0.0)]


def quad_with_uvs(uv0, uv1):
    """The quad with TEXCOORD_0 and TEXCOORD_1 (accessors 2 and 3, indices 4)."""
    g = Gltf()
    index_view = g.index_view(QUAD_INDICES)
    position_view = g.vec3_view(QUAD_POSITIONS)
    normal_view = g.vec3_view(QUAD_NORMALS)
    uv0_view = g.vec2_view(uv0)
    uv1_view = g.vec2_view(uv1)
    attributes = {
        "POSITION": g.position_accessor(position_view, QUAD_POSITIONS),
        "NORMAL": g.accessor(normal_view, FLOAT, 4, "VEC3"),
        "TEXCOORD_0": g.accessor(uv0_view, FLOAT, 4, "VEC2"),
        "TEXCOORD_1": g.accessor(uv1_view, FLOAT, 4, "VEC2"),
    }
    indices = g.accessor(index_view, UNSIGNED_SHORT, 6, "SCALAR")
    g.mesh("Quad", [{"attributes": attributes, "indices": indices, "material": 0, "mode": TRIANGLES}])
    g.node({"name": "Quad", "mesh": 0})
    return g


def nan_texcoord():
    # TEXCOORD_0 of vertex 3 has u = NaN in the binary data.
    uvs = list(QUAD_UVS)
    uvs[3] = (float("nan"), 0.0)
    return quad_with_uvs(uvs, QUAD_UVS).finish()


def inf_texcoord1():
    # TEXCOORD_1 (authored lightmap UVs) of vertex 0 has v = -Inf.
    uvs = list(QUAD_UVS)
    uvs[0] = (0.0, float("-inf"))
    return quad_with_uvs(QUAD_UVS, uvs).finish()


def emissive_quad(factor, strength):
    g = quad()
    g.doc["materials"][0] = {
        "name": "Glow",
        "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1.0], "metallicFactor": 0.0},
        "emissiveFactor": factor,
        "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": strength}},
    }
    g.doc["extensionsUsed"] = ["KHR_materials_emissive_strength"]
    return g.finish()


def overflow_emissive_factor():
    # emissiveFactor[0] = 1e300: a finite double, +Inf as a float.
    return patched(emissive_quad([12345.0, 1.0, 1.0], 1.0), "12345.0", "1e300")


def overflow_emissive_strength():
    # KHR_materials_emissive_strength 1e300 times emissiveFactor 1: each
    # finite as a double, the luminance (a float) +Inf.
    return patched(emissive_quad([1.0, 1.0, 1.0], 12345.0), "12345.0", "1e300")


def overflow_base_color():
    g = quad()
    g.doc["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"] = [0.5, 12345.0, 0.5, 1.0]
    return patched(g.finish(), "12345.0", "1e300")


def overflow_node(key, value, placeholder="12345.0"):
    g = quad()
    g.doc["nodes"][0][key] = value
    return patched(g.finish(), placeholder, "1e300")


def overflow_translation():
    # Node 'Quad' translation x = 1e300 (+Inf as a float).
    return overflow_node("translation", [12345.0, 0.0, 0.0])


def overflow_scale():
    return overflow_node("scale", [1.0, 12345.0, 1.0])


def overflow_matrix():
    # A column-major matrix whose translation x (element 12) is 1e300.
    return overflow_node("matrix", [1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0,
                                    0.0, 0.0, 1.0, 0.0, 12345.0, 0.0, 0.0, 1.0])


def overflow_world_position():
    # Every number is a finite float and the transform is finite and
    # regular: the quad scaled by 3e38 in POSITION (x and z), node 'Quad'
    # scale [2, 1, 1], so its corners land at x = +-6e38 > FLT_MAX: +-Inf in
    # world space, from a finite transform and finite data. (A node scale of
    # 1e38 is no good: the loader takes a column of length > 1.8e19 for a
    # singular transform, since its length squared overflows.)
    positions = [(x * 3e38, y, z * 3e38) for (x, y, z) in QUAD_POSITIONS]
    g = quad(positions=positions)
    g.doc["nodes"][0]["scale"] = [2.0, 1.0, 1.0]
    return g.finish()


def overflow_light_color():
    g = quad()
    add_lights(g, [{"name": "Lamp", "type": "point", "color": [12345.0, 1.0, 1.0], "intensity": 10.0}])
    return patched(g.finish(), "12345.0", "1e300")


def overflow_spot_angle():
    g = quad()
    add_lights(g, [{"name": "Spot", "type": "spot", "color": [1.0, 1.0, 1.0], "intensity": 100.0,
                    "spot": {"innerConeAngle": 0.1, "outerConeAngle": 12345.0}}])
    return patched(g.finish(), "12345.0", "1e300")


def nonnumeric_light_intensity():
    # The other way to spell NaN in JSON: "intensity": "NaN", a string.
    # tinygltf's parsed Light keeps the default 1.0 for it without a word, so
    # the importer must read the extension's JSON itself and reject it.
    g = quad()
    add_lights(g, [{"name": "Lamp", "type": "point", "color": [1.0, 1.0, 1.0], "intensity": "NaN"}])
    return g.finish()


def bad_spot_cone():
    # glTF requires 0 <= innerConeAngle < outerConeAngle <= pi/2.
    g = quad()
    add_lights(g, [{"name": "Spot", "type": "spot", "color": [1.0, 1.0, 1.0], "intensity": 100.0,
                    "spot": {"innerConeAngle": 0.6, "outerConeAngle": 0.4}}])
    return g.finish()


def unsupported_required_extension():
    # The geometry is plain (not actually Draco-compressed): the file must be
    # rejected for the required extension alone.
    g = quad()
    g.doc["extensionsUsed"] = ["KHR_draco_mesh_compression"]
    g.doc["extensionsRequired"] = ["KHR_draco_mesh_compression"]
    return g.finish()


def empty_scene():
    # Valid glTF: nodes, a hierarchy, no meshes, no buffers -> no triangles.
    g = Gltf()
    g.doc["materials"] = []
    g.node({"name": "Root", "children": [1]})
    g.node({"name": "Child", "translation": [0.0, 1.0, 0.0]}, root=False)
    return g.finish()


def triangle_strip():
    # Non-indexed strip, 4 vertices -> 2 triangles, (0,1,2) and (1,3,2) per
    # the glTF strip rule {v_i, v_i+(1+i%2), v_i+(2-i%2)}; both face +Y.
    positions = [(-1.0, 0.0, 0.5), (1.0, 0.0, 0.5), (-1.0, 0.0, -0.5), (1.0, 0.0, -0.5)]
    g = Gltf()
    pv = g.vec3_view(positions)
    nv = g.vec3_view(QUAD_NORMALS)
    attributes = {"POSITION": g.position_accessor(pv, positions),
                  "NORMAL": g.accessor(nv, FLOAT, 4, "VEC3")}
    g.mesh("Strip", [{"attributes": attributes, "material": 0, "mode": TRIANGLE_STRIP}])
    g.node({"name": "Strip", "mesh": 0})
    return g.finish()


def triangle_fan():
    # Indexed fan, 5 vertices -> 3 triangles around v0 = (0,0,0), all facing
    # +Y; area 3 x 0.5 = 1.5 m^2.
    positions = [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 0.0, -1.0), (-1.0, 0.0, 0.0), (0.0, 0.0, 1.0)]
    g = Gltf()
    iv = g.index_view([0, 1, 2, 3, 4])
    pv = g.vec3_view(positions)
    nv = g.vec3_view([(0.0, 1.0, 0.0)] * 5)
    attributes = {"POSITION": g.position_accessor(pv, positions),
                  "NORMAL": g.accessor(nv, FLOAT, 5, "VEC3")}
    indices = g.accessor(iv, UNSIGNED_SHORT, 5, "SCALAR")
    g.mesh("Fan", [{"attributes": attributes, "indices": indices, "material": 0, "mode": TRIANGLE_FAN}])
    g.node({"name": "Fan", "mesh": 0})
    return g.finish()


def points_and_lines():
    # Mesh 'Quad': primitive 0 = the quad (2 triangles), primitive 1 = POINTS
    # on the 4 vertices, primitive 2 = LINES (0,1) (1,2). 1 and 2 are skipped
    # with a warning each.
    g = quad()
    line_view = g.index_view([0, 1, 1, 2])
    line_acc = g.accessor(line_view, UNSIGNED_SHORT, 4, "SCALAR")
    attributes = {"POSITION": 0}
    prims = g.doc["meshes"][0]["primitives"]
    prims.append({"attributes": dict(attributes), "material": 0, "mode": POINTS})
    prims.append({"attributes": dict(attributes), "indices": line_acc, "material": 0, "mode": LINES})
    return g.finish()


def no_normals():
    # The quad folded along its diagonal v0-v2 (v2 lifted to y = 1), without
    # NORMAL. The two faces are not coplanar, so smooth normals would differ
    # from the flat ones the glTF spec requires:
    #   triangle 0 (0,1,2): normal (0, 1, 1)/sqrt 2
    #   triangle 1 (0,2,3): normal (-1, 2, 0)/sqrt 5
    positions = list(QUAD_POSITIONS)
    positions[2] = (1.0, 1.0, -0.5)
    return quad(positions=positions, normals=None).finish()


def dynamic_subtree():
    # Hierarchy (root nodes Mover and Floor; all meshes are the quad, mesh 0):
    #   0 Mover  extras.svit.dynamic, translation (0,1,0), no mesh
    #   1   Arm  translation (1,0,0), mesh       -> dynamic (inherited)
    #   2     Hand translation (0,0,1), mesh     -> dynamic (inherited), world (1,1,1)
    #   3 Floor  mesh                            -> static
    g = quad()
    g.doc["nodes"] = []
    g.doc["scenes"][0]["nodes"] = []
    g.node({"name": "Mover", "children": [1], "translation": [0.0, 1.0, 0.0],
            "extras": {"svit": {"dynamic": True}}})
    g.node({"name": "Arm", "children": [2], "translation": [1.0, 0.0, 0.0], "mesh": 0}, root=False)
    g.node({"name": "Hand", "translation": [0.0, 0.0, 1.0], "mesh": 0}, root=False)
    g.node({"name": "Floor", "mesh": 0})
    return g.finish()


# ---------------------------------------------------------------------------
# level.json files. All name good_quad.gltf (relative to the level file)
# unless the case is about the glTF reference itself.

def good_level():
    return {
        "gltf": "good_quad.gltf",
        "sun": {
            "direction_to_sun": [0.0, 2.0, 0.0],  # normalised on load to (0,1,0)
            "illuminance_lux": 100000,
            "angular_radius_rad": 0.01,
            "color": [1.0, 0.96, 0.9],
        },
        "sky": {
            "model": "gradient",
            "zenith_luminance": [4000, 5000, 7000],
            "horizon_luminance": 6000,  # a single number means grey
            "ground_luminance": [100, 80, 60],
        },
        "lights": [
            {"name": "lamp", "type": "point", "position": [0, 1.5, 0], "color": [1, 0.9, 0.8],
             "intensity_cd": 120, "range_m": 0, "dynamic": True},
        ],
        "camera_paths": [
            {"name": "main", "loop": False, "keys": [
                {"t_s": 0, "position": [0, 1, 3.5], "look_at": [0, 1, 0], "yfov_rad": 0.69},
                {"t_s": 6, "position": [0.5, 1.2, 2.5], "look_at": [0, 0.8, 0]},  # default yfov
            ]},
        ],
    }


def unknown_node_level():
    return {"gltf": "good_quad.gltf", "dynamic": ["NoSuchNode"]}


def bad_level_json():
    # Missing comma at the end of line 2.
    return '{\n  "gltf": "good_quad.gltf"\n  "dynamic": []\n}\n'


def negative_level_light():
    return {"gltf": "good_quad.gltf", "lights": [
        {"name": "lamp", "type": "point", "position": [0, 1.5, 0], "intensity_cd": -3}]}


def unknown_field_level():
    # "lihgts" is a typo of "lights": unknown fields are errors.
    return {"gltf": "good_quad.gltf", "lihgts": [
        {"name": "lamp", "type": "point", "position": [0, 1.5, 0], "intensity_cd": 120}]}


def missing_gltf_level():
    return {"gltf": "no_such_scene.gltf"}


def level_text(level, placeholder, literal="1e39"):
    """level.json text with one number replaced by `literal`: 1e39 is a
    finite double beyond FLT_MAX (3.4e38), +Inf as the float it is stored in."""
    text = dumps(level)
    bad = text.replace(placeholder, literal, 1)
    assert bad != text, placeholder
    return bad


def overflow_sun_level():
    return level_text({"gltf": "good_quad.gltf", "sun": {
        "direction_to_sun": [0.0, 1.0, 0.0], "illuminance_lux": 12345}}, "12345")


def overflow_light_position_level():
    return level_text({"gltf": "good_quad.gltf", "lights": [
        {"name": "lamp", "type": "point", "position": [0, 12345, 0], "intensity_cd": 120}]}, "12345")


def overflow_sky_level():
    return level_text({"gltf": "good_quad.gltf", "sky": {
        "model": "uniform", "zenith_luminance": [4000, 12345, 7000]}}, "12345")


def overflow_camera_level():
    return level_text({"gltf": "good_quad.gltf", "camera_paths": [
        {"name": "main", "keys": [{"t_s": 0, "position": [0, 1, 3.5], "look_at": [0, 1, 12345]}]}]}, "12345")


CASES = [
    ("good_quad.gltf", good_quad),
    ("good_emissive_quad.gltf", good_emissive_quad),
    ("truncated.gltf", truncated_gltf),
    ("bad_json.gltf", bad_json),
    ("truncated.glb", truncated_glb),
    ("missing_buffer_file.gltf", missing_buffer_file),
    ("short_buffer.gltf", short_buffer),
    ("index_out_of_range.gltf", index_out_of_range),
    ("accessor_out_of_bounds.gltf", accessor_out_of_bounds),
    ("buffer_view_out_of_bounds.gltf", buffer_view_out_of_bounds),
    ("nan_position.gltf", nan_position),
    ("inf_normal.gltf", inf_normal),
    ("zero_area_face.gltf", zero_area_face),
    ("missing_texture.gltf", missing_texture),
    ("negative_light_intensity.gltf", negative_light_intensity),
    ("nan_light_intensity.gltf", nan_light_intensity),
    ("nonnumeric_light_intensity.gltf", nonnumeric_light_intensity),
    ("bad_spot_cone.gltf", bad_spot_cone),
    ("unsupported_required_extension.gltf", unsupported_required_extension),
    ("empty_scene.gltf", empty_scene),
    ("triangle_strip.gltf", triangle_strip),
    ("triangle_fan.gltf", triangle_fan),
    ("points_and_lines.gltf", points_and_lines),
    ("no_normals.gltf", no_normals),
    ("dynamic_subtree.gltf", dynamic_subtree),
    ("good_level.json", good_level),
    ("unknown_node.level.json", unknown_node_level),
    ("bad_level_json.json", bad_level_json),
    ("negative_level_light.level.json", negative_level_light),
    ("unknown_field.level.json", unknown_field_level),
    ("missing_gltf.level.json", missing_gltf_level),
    # NaN/Inf everywhere (tests/stability/stability_input_test.cpp).
    ("nan_texcoord.gltf", nan_texcoord),
    ("inf_texcoord1.gltf", inf_texcoord1),
    ("overflow_emissive_factor.gltf", overflow_emissive_factor),
    ("overflow_emissive_strength.gltf", overflow_emissive_strength),
    ("overflow_base_color.gltf", overflow_base_color),
    ("overflow_translation.gltf", overflow_translation),
    ("overflow_scale.gltf", overflow_scale),
    ("overflow_matrix.gltf", overflow_matrix),
    ("overflow_world_position.gltf", overflow_world_position),
    ("overflow_light_color.gltf", overflow_light_color),
    ("overflow_spot_angle.gltf", overflow_spot_angle),
    ("overflow_sun.level.json", overflow_sun_level),
    ("overflow_light_position.level.json", overflow_light_position_level),
    ("overflow_sky.level.json", overflow_sky_level),
    ("overflow_camera.level.json", overflow_camera_level),
]

# Files the cases refer to that must NOT exist next to them.
MUST_NOT_EXIST = ["does_not_exist.bin", "no_such_texture.png", "no_such_scene.gltf"]


def _format(value, depth):
    """JSON with one member per line, arrays of numbers/strings on one line.
    allow_nan=False: a NaN or Inf that slipped into a document would be
    written as the non-JSON literal NaN/Infinity; fail instead."""
    pad = "  " * (depth + 1)
    if isinstance(value, dict) and value:
        items = ["%s%s: %s" % (pad, json.dumps(k), _format(v, depth + 1)) for k, v in value.items()]
        return "{\n" + ",\n".join(items) + "\n" + "  " * depth + "}"
    if isinstance(value, list) and any(isinstance(v, (dict, list)) for v in value):
        items = [pad + _format(v, depth + 1) for v in value]
        return "[\n" + ",\n".join(items) + "\n" + "  " * depth + "]"
    return json.dumps(value, allow_nan=False, separators=(", ", ": "))


def dumps(doc):
    return _format(doc, 0) + "\n"


def main():
    out_dir = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__))
    os.makedirs(out_dir, exist_ok=True)
    for name, make in CASES:
        content = make()
        if isinstance(content, dict):
            content = dumps(content)
        if isinstance(content, str):
            content = content.encode("utf-8")
        if len(content) >= MAX_FILE_BYTES:
            raise SystemExit("%s: %d bytes, the limit is %d" % (name, len(content), MAX_FILE_BYTES))
        # newline-free binary write: identical bytes on every platform.
        with open(os.path.join(out_dir, name), "wb") as f:
            f.write(content)
    for name in MUST_NOT_EXIST:
        path = os.path.join(out_dir, name)
        if os.path.exists(path):
            os.remove(path)
    print("wrote %d files to %s" % (len(CASES), out_dir))


if __name__ == "__main__":
    main()
