# Blender side of the Cycles comparison (tests/bench/cycles_compare.sh).
# Run inside Blender:  blender -b --factory-startup -P tests/bench/cycles_lightmap.py -- COMMAND ARGS
#
#   prepare IN.gltf OUT.gltf [--size 256] [--margin-texels 1.5]
#       Imports IN, gives every mesh lightmap UVs from Blender's Lightmap Pack
#       (all objects packed together into one [0, 1] layout, each face box
#       inset by --margin-texels at --size texels, so neighbouring boxes are
#       2 x margin apart) and writes OUT with those UVs as TEXCOORD_1 (the
#       exporter writes the only UV map as TEXCOORD_0; the attribute is renamed
#       afterwards so TEXCOORD_0 stays absent, as in IN). Materials (with
#       KHR_materials_emissive_strength) go through Blender's glTF exporter.
#   bake GLTF OUT_DIR --samples 1,4,16 [--size 256] [--seed 1] [--threads 0]
#       Imports GLTF, bakes Cycles "Diffuse" with Direct + Indirect and no
#       Color (the light arriving, irradiance / pi) into one float image on
#       the TEXCOORD_1 UV map for each sample count, and writes
#       OUT_DIR/cycles-sNNNNN.exr and OUT_DIR/cycles_timings.json (wall time
#       of each bpy.ops.object.bake). CPU, all threads, no denoiser, no
#       adaptive sampling, no clamping, 128 diffuse / max bounces.
#   texels GLTF OUT.npz [--size 256]
#       Which object owns each texel (texel centre inside one of its
#       TEXCOORD_1 triangles), which texels are hidden (under a box, in the
#       gap above the light) and which lie on a triangle that is in the scene
#       twice: see texels() below.
#   to-npy OUT_DIR [NAME=]FILE.exr...
#       Writes each EXR's RGB as OUT_DIR/NAME.npy (float32, H x W x 3, row 0 =
#       the file's first row, i.e. the image's top; NAME defaults to the file
#       name) and, for RGBA files, the alpha as OUT_DIR/NAME.alpha.npy.
#
# Materials for baking: the glTF importer builds Principled BSDFs, whose
# specular lobe (0.5) and Disney diffuse are not Lambertian, and Cycles'
# emission is two-sided. For a like-for-like comparison with svit (Lambertian
# surfaces, one-sided emitters) every material is rebuilt as a Diffuse BSDF
# (roughness 0 = Lambert) of the base colour, plus, for emitters, an Emission
# of emissive x strength that is zero on back faces.

import json
import math
import os
import sys
import time

import numpy as np

# Debian's Blender 3.4 glTF add-on uses aliases that NumPy 1.24 removed
# (np.bool etc.); restore them before the add-on runs.
for _name, _type in (("bool", bool), ("int", int), ("float", float), ("object", object)):
    if _name not in np.__dict__:
        setattr(np, _name, _type)

import bpy  # noqa: E402


def argv_after_dashes():
    argv = sys.argv
    return argv[argv.index("--") + 1:] if "--" in argv else []


def option(args, name, default):
    if name in args:
        i = args.index(name)
        value = args[i + 1]
        del args[i:i + 2]
        return value
    return default


def fail(message):
    print("cycles_lightmap.py: " + message, file=sys.stderr)
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(1)


def reset_and_import(path):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    result = bpy.ops.import_scene.gltf(filepath=path)
    if result != {"FINISHED"}:
        fail("importing %s failed" % path)
    meshes = [o for o in bpy.context.scene.objects if o.type == "MESH"]
    if not meshes:
        fail("%s has no meshes" % path)
    return meshes


def select_only(objects):
    bpy.ops.object.select_all(action="DESELECT")
    for o in objects:
        o.select_set(True)
    bpy.context.view_layer.objects.active = objects[0]


def prepare(args):
    size = int(option(args, "--size", "256"))
    margin_texels = float(option(args, "--margin-texels", "1.5"))
    if len(args) != 2:
        fail("prepare needs IN.gltf OUT.gltf")
    source, target = args
    meshes = reset_and_import(source)
    for o in meshes:
        if o.data.uv_layers:
            fail("%s: mesh %s already has UVs; this script expects none" % (source, o.name))
        o.data.uv_layers.new(name="lightmap")
    select_only(meshes)
    # The glTF importer brings triangles; join each planar quad's pair back
    # into a quad so Lightmap Pack makes one box per wall face.
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.select_all(action="SELECT")
    bpy.ops.mesh.tris_convert_to_quads()
    bpy.ops.object.mode_set(mode="OBJECT")
    # Lightmap Pack, called below the operator: the operator collects the
    # meshes in a set, whose order (and so the layout) changes from run to
    # run; a list sorted by name makes the layout reproducible. The margin:
    # each face box is inset by 1 / PREF_MARGIN_DIV of the UV square per side.
    from bl_operators.uvcalc_lightmap import lightmap_uvpack
    lightmap_uvpack(sorted((o.data for o in meshes), key=lambda m: m.name), PREF_SEL_ONLY=False,
                    PREF_NEW_UVLAYER=False, PREF_PACK_IN_ONE=True, PREF_APPLY_IMAGE=False, PREF_IMG_PX_SIZE=size,
                    PREF_BOX_DIV=12, PREF_MARGIN_DIV=int(round(size / margin_texels)))
    lo, hi = 1.0, 0.0
    for o in meshes:
        uv = np.empty(len(o.data.loops) * 2, dtype=np.float32)
        o.data.uv_layers["lightmap"].data.foreach_get("uv", uv)
        lo, hi = min(lo, float(uv.min())), max(hi, float(uv.max()))
    print("prepare: lightmap UVs in [%.4f, %.4f], margin %.2f texels per side at %d x %d" % (lo, hi, margin_texels, size, size))
    result = bpy.ops.export_scene.gltf(filepath=target, export_format="GLTF_SEPARATE", use_selection=False,
                                       export_texcoords=True, export_normals=True, export_materials="EXPORT",
                                       export_cameras=False, export_lights=False, export_apply=False,
                                       export_yup=True)
    if result != {"FINISHED"}:
        fail("exporting %s failed" % target)
    # Move the (only) UV set to TEXCOORD_1: lightmap UVs, TEXCOORD_0 absent.
    with open(target) as f:
        gltf = json.load(f)
    for mesh in gltf.get("meshes", []):
        for primitive in mesh["primitives"]:
            attributes = primitive["attributes"]
            if "TEXCOORD_0" not in attributes or "TEXCOORD_1" in attributes:
                fail("%s: mesh %s: expected exactly one UV set from the exporter" % (target, mesh.get("name")))
            attributes["TEXCOORD_1"] = attributes.pop("TEXCOORD_0")
    gltf.setdefault("asset", {})["extras"] = {
        "svit_bench": "CornellBox-Original with Blender Lightmap Pack UVs as TEXCOORD_1 (tests/bench/cycles_lightmap.py)"}
    with open(target, "w") as f:
        json.dump(gltf, f, indent=1)
    print("prepare: wrote %s" % target)


def lambert_materials():
    """Rebuilds every material as Diffuse BSDF (+ one-sided Emission)."""
    for material in bpy.data.materials:
        if not material.use_nodes:
            continue
        tree = material.node_tree
        principled = next((n for n in tree.nodes if n.type == "BSDF_PRINCIPLED"), None)
        if principled is None:
            fail("material %s has no Principled BSDF" % material.name)
        if principled.inputs["Base Color"].is_linked:
            fail("material %s: textured base colour not supported here" % material.name)
        base = tuple(principled.inputs["Base Color"].default_value)
        emission = tuple(principled.inputs["Emission"].default_value)
        strength = principled.inputs["Emission Strength"].default_value
        tree.nodes.clear()
        out = tree.nodes.new("ShaderNodeOutputMaterial")
        diffuse = tree.nodes.new("ShaderNodeBsdfDiffuse")
        diffuse.inputs["Color"].default_value = base
        diffuse.inputs["Roughness"].default_value = 0.0
        shader = diffuse.outputs["BSDF"]
        if strength * max(emission[:3]) > 0:
            emit = tree.nodes.new("ShaderNodeEmission")
            emit.inputs["Color"].default_value = emission
            geometry = tree.nodes.new("ShaderNodeNewGeometry")
            front = tree.nodes.new("ShaderNodeMath")
            front.operation = "SUBTRACT"
            front.inputs[0].default_value = 1.0
            tree.links.new(geometry.outputs["Backfacing"], front.inputs[1])
            scaled = tree.nodes.new("ShaderNodeMath")
            scaled.operation = "MULTIPLY"
            scaled.inputs[1].default_value = strength
            tree.links.new(front.outputs["Value"], scaled.inputs[0])
            tree.links.new(scaled.outputs["Value"], emit.inputs["Strength"])
            add = tree.nodes.new("ShaderNodeAddShader")
            tree.links.new(diffuse.outputs["BSDF"], add.inputs[0])
            tree.links.new(emit.outputs["Emission"], add.inputs[1])
            shader = add.outputs["Shader"]
            print("bake: material %s emits %s x %g (front faces only)" % (material.name, emission[:3], strength))
        tree.links.new(shader, out.inputs["Surface"])


def import_lightmap_uvs(source):
    """Imports GLTF with its TEXCOORD_1 as the meshes' only UV map."""
    # Blender's importer reads TEXCOORD_n only from n = 0 up, so it would skip
    # a lone TEXCOORD_1: import a copy (beside the original, sharing its
    # buffers) where the lightmap UVs are TEXCOORD_0.
    with open(source) as f:
        gltf = json.load(f)
    for mesh in gltf.get("meshes", []):
        for primitive in mesh["primitives"]:
            attributes = primitive["attributes"]
            if "TEXCOORD_1" not in attributes:
                fail("%s: mesh %s has no TEXCOORD_1" % (source, mesh.get("name")))
            attributes.pop("TEXCOORD_0", None)
            attributes["TEXCOORD_0"] = attributes.pop("TEXCOORD_1")
    copy = os.path.splitext(source)[0] + ".uv1-as-uv0.gltf"
    with open(copy, "w") as f:
        json.dump(gltf, f)
    meshes = reset_and_import(copy)
    os.remove(copy)
    for o in meshes:
        if len(o.data.uv_layers) != 1:
            fail("%s: mesh %s has %d UV maps, expected 1 (TEXCOORD_1)" % (source, o.name, len(o.data.uv_layers)))
    return meshes


def bake(args):
    size = int(option(args, "--size", "256"))
    samples = [int(s) for s in option(args, "--samples", "1,4,16").split(",")]
    seed = int(option(args, "--seed", "1"))
    threads = int(option(args, "--threads", "0"))
    if len(args) != 2:
        fail("bake needs GLTF OUT_DIR")
    source, out_dir = args
    os.makedirs(out_dir, exist_ok=True)
    meshes = import_lightmap_uvs(source)
    lambert_materials()

    scene = bpy.context.scene
    world = bpy.data.worlds.new("black")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0, 0, 0, 1)
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
    scene.world = world
    scene.render.engine = "CYCLES"
    cycles = scene.cycles
    cycles.device = "CPU"
    cycles.use_adaptive_sampling = False
    cycles.use_denoising = False
    cycles.max_bounces = 128
    cycles.diffuse_bounces = 128
    cycles.glossy_bounces = 0
    cycles.transmission_bounces = 0
    cycles.volume_bounces = 0
    cycles.transparent_max_bounces = 0
    cycles.sample_clamp_direct = 0.0
    cycles.sample_clamp_indirect = 0.0
    cycles.seed = seed
    cycles.use_animated_seed = False
    if threads > 0:
        scene.render.threads_mode = "FIXED"
        scene.render.threads = threads
    else:
        scene.render.threads_mode = "AUTO"
    scene.render.bake.use_pass_direct = True
    scene.render.bake.use_pass_indirect = True
    scene.render.bake.use_pass_color = False
    scene.render.bake.margin = 0
    scene.render.bake.use_clear = False
    scene.render.bake.target = "IMAGE_TEXTURES"

    settings = scene.render.image_settings
    settings.file_format = "OPEN_EXR"
    settings.color_mode = "RGBA"
    settings.color_depth = "32"
    settings.exr_codec = "ZIP"
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 0.0
    scene.view_settings.gamma = 1.0
    image = bpy.data.images.new("lightmap", width=size, height=size, alpha=True, float_buffer=True)
    image.colorspace_settings.name = "Non-Color"
    for material in bpy.data.materials:
        if not material.use_nodes:
            continue
        node = material.node_tree.nodes.new("ShaderNodeTexImage")
        node.image = image
        material.node_tree.nodes.active = node
    select_only(meshes)

    timings = {"size": size, "seed": seed, "threads": scene.render.threads, "blender": bpy.app.version_string,
               "bakes": []}
    for count in samples:
        cycles.samples = count
        # Unbaked texels keep alpha 0: that is the coverage mask.
        image.pixels.foreach_set(np.zeros(size * size * 4, dtype=np.float32))
        start = time.perf_counter()
        result = bpy.ops.object.bake(type="DIFFUSE", pass_filter={"DIRECT", "INDIRECT"}, margin=0, use_clear=False,
                                     target="IMAGE_TEXTURES")
        seconds = time.perf_counter() - start
        if result != {"FINISHED"}:
            fail("bake with %d samples failed" % count)
        name = "cycles-s%05d.exr" % count
        path = os.path.join(out_dir, name)
        image.save_render(path, scene=scene)
        timings["bakes"].append({"samples": count, "seconds": seconds, "file": name})
        print("bake: %5d samples  %8.2f s  -> %s" % (count, seconds, path))
        sys.stdout.flush()
        with open(os.path.join(out_dir, "cycles_timings.json"), "w") as f:
            json.dump(timings, f, indent=1)


def texels(args):
    """Per texel of the page: object index, 'hidden' and 'duplicate' flags.

    A texel belongs to the triangle containing its centre (what Cycles bakes).
    From the surface point there, 64 rays over the cosine hemisphere look for
    back faces: a point under a box (floor beneath it) or in the 1 cm gap
    above the light sees back faces in most directions and no viewer in the
    room can see it. Hidden: more than half of the rays hit a back face.
    Duplicate: the texel's triangle has the same three corners as another
    triangle (CornellBox-Original.obj's "Bottom Face" of each box indexes the
    box's right face again, so that face is there twice); what lands on a
    face coinciding with another depends on how a ray tracer treats a hit at
    distance 0, so the two bakers legitimately differ there.
    """
    from mathutils import Vector
    from mathutils.bvhtree import BVHTree
    size = int(option(args, "--size", "256"))
    if len(args) != 2:
        fail("texels needs GLTF OUT.npz")
    source, target = args
    meshes = import_lightmap_uvs(source)
    meshes.sort(key=lambda o: o.name)
    verts, polys, tris = [], [], []
    for index, o in enumerate(meshes):
        mesh = o.data
        matrix = o.matrix_world
        base = len(verts)
        verts.extend(matrix @ v.co for v in mesh.vertices)
        mesh.calc_loop_triangles()
        uv = mesh.uv_layers[0].data
        for tri in mesh.loop_triangles:
            polys.append([base + v for v in tri.vertices])
            # Blender's v is glTF's 1 - v; page rows run with glTF's v.
            uvs = [(uv[l].uv[0], 1.0 - uv[l].uv[1]) for l in tri.loops]
            tris.append((index, [verts[base + v] for v in tri.vertices], uvs))
    tree = BVHTree.FromPolygons(verts, polys, all_triangles=True)
    owner = np.full((size, size), -1, dtype=np.int32)
    hidden = np.zeros((size, size), dtype=bool)
    duplicate = np.zeros((size, size), dtype=bool)
    corner_key = [frozenset(tuple(round(c, 5) for c in corner) for corner in corners) for _, corners, _ in tris]
    copies = {}
    for key in corner_key:
        copies[key] = copies.get(key, 0) + 1
    # A fixed cosine-weighted direction set (Fibonacci spiral on the disc).
    count = 64
    golden = math.pi * (3.0 - math.sqrt(5.0))
    local = []
    for i in range(count):
        r = math.sqrt((i + 0.5) / count)
        phi = i * golden
        local.append((r * math.cos(phi), r * math.sin(phi), math.sqrt(max(0.0, 1.0 - r * r))))
    for (index, corners, uvs), key in zip(tris, corner_key):
        (x0, y0), (x1, y1), (x2, y2) = [(u * size, v * size) for u, v in uvs]
        d = (y1 - y2) * (x0 - x2) + (x2 - x1) * (y0 - y2)
        if d == 0:
            continue
        normal = (corners[1] - corners[0]).cross(corners[2] - corners[0]).normalized()
        helper = Vector((1, 0, 0)) if abs(normal.x) < 0.9 else Vector((0, 1, 0))
        tangent = normal.cross(helper).normalized()
        bitangent = normal.cross(tangent)
        directions = [tangent * a + bitangent * b + normal * c for a, b, c in local]
        for ty in range(max(0, int(min(y0, y1, y2))), min(size, int(max(y0, y1, y2)) + 1)):
            for tx in range(max(0, int(min(x0, x1, x2))), min(size, int(max(x0, x1, x2)) + 1)):
                px, py = tx + 0.5, ty + 0.5
                l0 = ((y1 - y2) * (px - x2) + (x2 - x1) * (py - y2)) / d
                l1 = ((y2 - y0) * (px - x2) + (x0 - x2) * (py - y2)) / d
                l2 = 1.0 - l0 - l1
                if l0 < 0 or l1 < 0 or l2 < 0:
                    continue
                owner[ty, tx] = index
                duplicate[ty, tx] = copies[key] > 1
                point = corners[0] * l0 + corners[1] * l1 + corners[2] * l2 + normal * 1e-4
                back = 0
                for direction in directions:
                    location, hit_normal, _, _ = tree.ray_cast(point, direction)
                    if location is not None and hit_normal.dot(direction) > 0:
                        back += 1
                hidden[ty, tx] = back * 2 > count
    np.savez_compressed(target, owner=owner, hidden=hidden, duplicate=duplicate,
                        names=np.array([o.name for o in meshes]))

    def by_object(flags):
        return ", ".join("%s %d" % (o.name, (flags & (owner == i)).sum()) for i, o in enumerate(meshes)
                         if (flags & (owner == i)).any())
    print("texels: %d covered, %d hidden (%s), %d on duplicated triangles (%s)" % (
        (owner >= 0).sum(), hidden.sum(), by_object(hidden), duplicate.sum(), by_object(duplicate)))


def to_npy(args):
    if len(args) < 2:
        fail("to-npy needs OUT_DIR [NAME=]FILE.exr...")
    out_dir, files = args[0], args[1:]
    os.makedirs(out_dir, exist_ok=True)
    for item in files:
        name, _, path = item.rpartition("=")
        name = name or os.path.splitext(os.path.basename(path))[0]
        image = bpy.data.images.load(os.path.abspath(path), check_existing=False)
        image.colorspace_settings.name = "Non-Color"
        w, h = image.size
        channels = image.channels
        pixels = np.empty(w * h * channels, dtype=np.float32)
        image.pixels.foreach_get(pixels)
        # Blender keeps row 0 at the bottom; flip to the file's row order.
        array = pixels.reshape(h, w, channels)[::-1]
        rgb = np.ascontiguousarray(array[:, :, :3])
        np.save(os.path.join(out_dir, name + ".npy"), rgb)
        if channels == 4:
            np.save(os.path.join(out_dir, name + ".alpha.npy"), np.ascontiguousarray(array[:, :, 3]))
        bpy.data.images.remove(image)
        print("to-npy: %s (%d x %d, %d channels)" % (name, w, h, channels))


def main():
    args = argv_after_dashes()
    if not args:
        fail("usage: blender -b -P cycles_lightmap.py -- prepare|bake|texels|to-npy ARGS")
    command, rest = args[0], args[1:]
    try:
        {"prepare": prepare, "bake": bake, "texels": texels, "to-npy": to_npy}.get(command, lambda _: fail("unknown command " + command))(rest)
    except Exception as error:  # Blender would carry on and exit 0
        import traceback
        traceback.print_exc()
        fail("%s failed: %s" % (command, error))
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(0)


main()
