#!/usr/bin/env python3
"""Writes the sample house: a grid of rooms as house.gltf + house.bin + level.json.

    make_house.py [--rooms-x N] [--rooms-z M] [--out DIR]

Rooms are 4 x 4 m inside and 3 m high, separated by 0.2 m walls. Every wall
between two rooms has a 1 x 2.1 m doorway with a door leaf, a separate dynamic
node hinged at one jamb (at rest it stands open at right angles to the wall,
so the camera can walk through). Each room has two ceiling lamps
(KHR_lights_punctual point lights, so 8 x 8 rooms give 128 lamps) and a
dynamic table. level.json adds a camera path
that walks through up to eight rooms, one door that swings shut and open again
and a table that slides.

Light-tightness: each room is the inside of a box (floor, ceiling and four
walls facing into the room, single-sided), and each doorway a short tunnel
through the wall joining the two rooms' doorway holes. All faces meet at shared
corner vertices (no T-junctions), so the only way from one room to the next is
through a doorway; the space inside the walls is closed and empty. Rooms and
doorways are separate meshes, so the baker's clusters never span two rooms.
Door leaves and tables are closed boxes.

Python 3 standard library only. The output is deterministic (same arguments,
same bytes). docs/level-format.md describes level.json; samples/levels/README.md
lists the levels.
"""

import argparse
import json
import math
import os
import struct
import sys

PITCH_M = 4.2          # wall centre to wall centre
WALL_M = 0.2           # wall thickness
HEIGHT_M = 3.0         # floor to ceiling
DOOR_WIDTH_M = 1.0     # doorway
DOOR_HEIGHT_M = 2.1
LEAF_WIDTH_M = 0.9     # door leaf
LEAF_THICKNESS_M = 0.04
LAMP_HEIGHT_M = 2.7    # 0.3 m below the ceiling
LAMP_OFFSET_M = 1.0    # lamps at (-1, -1) and (+1, +1) from the room centre
LAMP_INTENSITY_CD = 120.0   # ~1500 lm each, a 100 W incandescent bulb
LAMP_COLOR = [1.0, 0.86, 0.68]
EYE_HEIGHT_M = 1.6
WALK_SPEED_M_S = 1.2
MAX_WALK_ROOMS = 8

MATERIALS = [  # name, linear albedo
    ("plaster", [0.80, 0.78, 0.74]),
    ("floor_wood", [0.45, 0.32, 0.20]),
    ("ceiling", [0.85, 0.85, 0.85]),
    ("door", [0.55, 0.38, 0.22]),
    ("table", [0.60, 0.45, 0.30]),
]
MATERIAL = {name: i for i, (name, _) in enumerate(MATERIALS)}


def to_json(value, indent=0):
    """JSON with one line per object member or array item, but arrays of
    numbers and objects without nested containers on one line each."""
    def flat(v):
        if isinstance(v, list):
            return all(not isinstance(x, (list, dict)) for x in v)
        if isinstance(v, dict):
            return all(not isinstance(x, dict) and (not isinstance(x, list) or flat(x)) for x in v.values())
        return True
    if flat(value):
        return json.dumps(value)
    pad, inner = " " * indent, " " * (indent + 1)
    if isinstance(value, list):
        return "[\n" + ",\n".join(inner + to_json(v, indent + 1) for v in value) + "\n" + pad + "]"
    return "{\n" + ",\n".join(inner + json.dumps(k) + ": " + to_json(v, indent + 1)
                               for k, v in value.items()) + "\n" + pad + "}"


def f32(value):
    """The float32 nearest to value, as stored in the buffer."""
    return struct.unpack("<f", struct.pack("<f", value))[0]


def quad(corners, normal):
    """Two triangles over four corners (in order around the quad) facing `normal`:
    (positions, normals, indices)."""
    a, b, c = corners[0], corners[1], corners[2]
    u = [b[k] - a[k] for k in range(3)]
    v = [c[k] - a[k] for k in range(3)]
    cross = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
    indices = [0, 1, 2, 0, 2, 3]  # counter-clockwise seen from the front
    if sum(cross[k] * normal[k] for k in range(3)) < 0:
        indices = [0, 2, 1, 0, 3, 2]
    return [list(p) for p in corners], [list(normal)] * 4, indices


def merge(geometries):
    positions, normals, indices = [], [], []
    for p, n, i in geometries:
        indices += [len(positions) + k for k in i]
        positions += p
        normals += n
    return positions, normals, indices


def box(lo, hi):
    """Closed box between corners lo and hi, faces pointing out of it."""
    faces = []
    for axis in range(3):
        for side in (lo, hi):
            u, v = (axis + 1) % 3, (axis + 2) % 3
            corners = []
            for cu, cv in ((0, 0), (1, 0), (1, 1), (0, 1)):
                p = [0.0, 0.0, 0.0]
                p[axis] = side[axis]
                p[u] = hi[u] if cu else lo[u]
                p[v] = hi[v] if cv else lo[v]
                corners.append(p)
            normal = [0.0, 0.0, 0.0]
            normal[axis] = 1.0 if side is hi else -1.0
            faces.append(quad(corners, normal))
    return merge(faces)


class Gltf:
    """Collects meshes, nodes and lights and writes .gltf + .bin."""

    def __init__(self):
        self.blob = bytearray()
        self.buffer_views, self.accessors, self.meshes, self.nodes = [], [], [], []
        self.lights = []

    def _view(self, data, target):
        while len(self.blob) % 4:
            self.blob.append(0)
        self.buffer_views.append({"buffer": 0, "byteOffset": len(self.blob), "byteLength": len(data),
                                  "target": target})
        self.blob += data
        return len(self.buffer_views) - 1

    def _accessor(self, view, component, count, kind, extra=None):
        accessor = {"bufferView": view, "componentType": component, "count": count, "type": kind}
        accessor.update(extra or {})
        self.accessors.append(accessor)
        return len(self.accessors) - 1

    def mesh(self, name, parts):
        """parts: list of (material name, (positions, normals, indices)); one primitive each."""
        primitives = []
        for material, (positions, normals, indices) in parts:
            flat = [c for p in positions for c in p]
            lo = [f32(min(p[k] for p in positions)) for k in range(3)]
            hi = [f32(max(p[k] for p in positions)) for k in range(3)]
            pos = self._accessor(self._view(struct.pack("<%df" % len(flat), *flat), 34962), 5126,
                                 len(positions), "VEC3", {"min": lo, "max": hi})
            nflat = [c for n in normals for c in n]
            nor = self._accessor(self._view(struct.pack("<%df" % len(nflat), *nflat), 34962), 5126,
                                 len(normals), "VEC3")
            idx = self._accessor(self._view(struct.pack("<%dH" % len(indices), *indices), 34963), 5123,
                                 len(indices), "SCALAR")
            primitives.append({"attributes": {"POSITION": pos, "NORMAL": nor}, "indices": idx,
                               "material": MATERIAL[material], "mode": 4})
        self.meshes.append({"name": name, "primitives": primitives})
        return len(self.meshes) - 1

    def node(self, name, mesh=None, translation=None, rotation=None, dynamic=False, light=None):
        node = {"name": name}
        if mesh is not None:
            node["mesh"] = mesh
        if translation is not None:
            node["translation"] = [round(c, 6) for c in translation]
        if rotation is not None:
            node["rotation"] = [round(c, 8) for c in rotation]
        if dynamic:
            node["extras"] = {"svit": {"dynamic": True}}
        if light is not None:
            node["extensions"] = {"KHR_lights_punctual": {"light": light}}
        self.nodes.append(node)
        return len(self.nodes) - 1

    def point_light(self, name, intensity_cd, color):
        self.lights.append({"name": name, "type": "point", "intensity": intensity_cd, "color": color})
        return len(self.lights) - 1

    def write(self, directory, stem):
        while len(self.blob) % 4:
            self.blob.append(0)
        document = {
            "asset": {"version": "2.0", "generator": "svit samples/levels/house/make_house.py"},
            "extensionsUsed": ["KHR_lights_punctual"],
            "extensions": {"KHR_lights_punctual": {"lights": self.lights}},
            "scene": 0,
            "scenes": [{"name": "house", "nodes": list(range(len(self.nodes)))}],
            "nodes": self.nodes,
            "meshes": self.meshes,
            "materials": [{"name": name, "doubleSided": False,
                           "pbrMetallicRoughness": {"baseColorFactor": albedo + [1.0], "metallicFactor": 0.0,
                                                    "roughnessFactor": 1.0}}
                          for name, albedo in MATERIALS],
            "buffers": [{"uri": stem + ".bin", "byteLength": len(self.blob)}],
            "bufferViews": self.buffer_views,
            "accessors": self.accessors,
        }
        with open(os.path.join(directory, stem + ".bin"), "wb") as f:
            f.write(self.blob)
        with open(os.path.join(directory, stem + ".gltf"), "w") as f:
            f.write(to_json(document) + "\n")


def y_rotation(angle_rad):
    """Quaternion (x, y, z, w) turning by angle_rad about +Y."""
    return [0.0, math.sin(angle_rad / 2), 0.0, math.cos(angle_rad / 2)]


def room_centre(i, j):
    return ((i + 0.5) * PITCH_M, (j + 0.5) * PITCH_M)


def interior(k):
    """Inside faces of room k along one axis (metres): walls are centred on k * PITCH."""
    return k * PITCH_M + WALL_M / 2, (k + 1) * PITCH_M - WALL_M / 2


def room_geometry(i, j, doors_on):
    """The inside of room (i, j) as an inward-facing box: floor, ceiling and
    walls as separate (positions, normals, indices), with a doorway hole in
    each wall named in doors_on ('-x', '+x', '-z', '+z').

    Every face is cut at the same lines (the doorway jambs of both axes, the
    doorway height), whether or not its wall has a doorway, so neighbouring
    faces share their corner vertices exactly: no T-junctions, no cracks."""
    (x0, x1), (z0, z1) = interior(i), interior(j)
    xc, zc = room_centre(i, j)
    d = DOOR_WIDTH_M / 2
    xs, zs, ys = [x0, xc - d, xc + d, x1], [z0, zc - d, zc + d, z1], [0.0, DOOR_HEIGHT_M, HEIGHT_M]

    def grid(us, vs, point, normal, hole=None):
        quads = []
        for a in range(len(us) - 1):
            for b in range(len(vs) - 1):
                if (a, b) == hole:
                    continue
                corners = [point(us[a], vs[b]), point(us[a + 1], vs[b]), point(us[a + 1], vs[b + 1]),
                           point(us[a], vs[b + 1])]
                quads.append(quad(corners, normal))
        return merge(quads)

    door_cell = (1, 0)  # the middle column, the lower row
    floor = grid(xs, zs, lambda x, z: (x, 0.0, z), (0, 1, 0))
    ceiling = grid(xs, zs, lambda x, z: (x, HEIGHT_M, z), (0, -1, 0))
    walls = merge([
        grid(zs, ys, lambda z, y: (x0, y, z), (1, 0, 0), door_cell if "-x" in doors_on else None),
        grid(zs, ys, lambda z, y: (x1, y, z), (-1, 0, 0), door_cell if "+x" in doors_on else None),
        grid(xs, ys, lambda x, y: (x, y, z0), (0, 0, 1), door_cell if "-z" in doors_on else None),
        grid(xs, ys, lambda x, y: (x, y, z1), (0, 0, -1), door_cell if "+z" in doors_on else None),
    ])
    return floor, ceiling, walls


def doorway_geometry(a0, a1, centre, along_axis):
    """The reveal of a doorway through a wall from a0 to a1 across it (the two
    rooms' wall planes), centred at `centre` along `along_axis` ('x' or 'z'):
    threshold, soffit and jambs, facing into the opening. Returns (threshold,
    the rest)."""
    d = DOOR_WIDTH_M / 2
    lo, hi = centre - d, centre + d

    def point(across, y, along):
        return (across, y, along) if along_axis == "z" else (along, y, across)

    def face(y0, y1, s0, s1, normal):
        return quad([point(a0, y0, s0), point(a1, y0, s0), point(a1, y1, s1), point(a0, y1, s1)], normal)

    def axis_vector(sign):
        return (0, 0, sign) if along_axis == "z" else (sign, 0, 0)

    threshold = face(0.0, 0.0, lo, hi, (0, 1, 0))
    soffit = face(DOOR_HEIGHT_M, DOOR_HEIGHT_M, lo, hi, (0, -1, 0))
    jamb_lo = face(0.0, DOOR_HEIGHT_M, lo, lo, axis_vector(1))
    jamb_hi = face(0.0, DOOR_HEIGHT_M, hi, hi, axis_vector(-1))
    return threshold, merge([soffit, jamb_lo, jamb_hi])


def walk_route(nx, nz):
    """Rooms of a serpentine walk: row 0 left to right, row 1 back, ...; at most MAX_WALK_ROOMS."""
    route = []
    for j in range(nz):
        row = range(nx) if j % 2 == 0 else range(nx - 1, -1, -1)
        route += [(i, j) for i in row]
    return route[:MAX_WALK_ROOMS]


def door_between(a, b):
    """Name of the door between neighbouring rooms a and b."""
    (i0, j0), (i1, j1) = sorted([a, b])
    if j0 == j1:
        return "door_x%d_%d" % (i1, j0)   # in the wall x = i1 * PITCH, row j0
    return "door_z%d_%d" % (j1, i0)       # in the wall z = j1 * PITCH, column i0


def build(nx, nz):
    g = Gltf()
    doors = {}  # name -> (hinge xz, closed rotation, open rotation)

    # One mesh per room, the inside of its box, and one per doorway: rooms
    # share no object, so the solver's clusters (which spread sparse hits over
    # an object) never carry light from one room to the next. The space inside
    # the walls is empty and closed; nothing faces into it.
    for j in range(nz):
        for i in range(nx):
            doors_on = [side for side, present in (("-x", i > 0), ("+x", i < nx - 1), ("-z", j > 0),
                                                   ("+z", j < nz - 1)) if present]
            floor, ceiling, walls = room_geometry(i, j, doors_on)
            name = "room_%d_%d" % (i, j)
            g.node(name, g.mesh(name, [("floor_wood", floor), ("ceiling", ceiling), ("plaster", walls)]))
    for i in range(1, nx):
        for j in range(nz):
            threshold, rest = doorway_geometry(interior(i - 1)[1], interior(i)[0], room_centre(i, j)[1], "z")
            name = "doorway_x%d_%d" % (i, j)
            g.node(name, g.mesh(name, [("floor_wood", threshold), ("plaster", rest)]))
    for j in range(1, nz):
        for i in range(nx):
            threshold, rest = doorway_geometry(interior(j - 1)[1], interior(j)[0], room_centre(i, j)[0], "x")
            name = "doorway_z%d_%d" % (j, i)
            g.node(name, g.mesh(name, [("floor_wood", threshold), ("plaster", rest)]))

    # Doors on the walls x = i * PITCH between rooms (i - 1, j) and (i, j).
    for i in range(1, nx):
        for j in range(nz):
            # Hinge on the wall's centre plane at the -z jamb; the leaf runs
            # along local +z. Closed: in the wall. Open: turned +90 degrees
            # about Y, so it lies along +x in room (i, j).
            hinge = (i * PITCH_M, room_centre(i, j)[1] - LEAF_WIDTH_M / 2)
            doors["door_x%d_%d" % (i, j)] = (hinge, 0.0, math.pi / 2)
    # Doors on the walls z = j * PITCH between rooms (i, j - 1) and (i, j).
    for j in range(1, nz):
        for i in range(nx):
            # Hinge at the -x jamb. Closed: local +z turned onto +x (+90
            # degrees). Open: unturned, the leaf lies along +z in room (i, j).
            hinge = (room_centre(i, j)[0] - LEAF_WIDTH_M / 2, j * PITCH_M)
            doors["door_z%d_%d" % (j, i)] = (hinge, math.pi / 2, 0.0)

    # Door leaves: 1 cm above the floor, 4 cm clear of the lintel.
    t = LEAF_THICKNESS_M / 2
    leaf = g.mesh("door_leaf", [("door", box([-t, 0.01, 0.0], [t, DOOR_HEIGHT_M - 0.04, LEAF_WIDTH_M]))])
    for name in sorted(doors):
        (hx, hz), _, open_rad = doors[name]
        g.node(name, leaf, translation=[hx, 0.0, hz], rotation=y_rotation(open_rad), dynamic=True)

    # Tables: 1.2 x 0.8 m top at 0.75 m, in the (+x, -z) quarter of each room
    # (the camera walks the centre lines, the lamps hang over the other diagonal).
    legs = []
    for sx in (-1, 1):
        for sz in (-1, 1):
            cx, cz = sx * 0.53, sz * 0.33
            legs.append(([cx - 0.03, 0.0, cz - 0.03], [cx + 0.03, 0.74, cz + 0.03]))  # into the top
    table = g.mesh("table", [("table", merge([box([-0.6, 0.72, -0.4], [0.6, 0.77, 0.4])] +
                                             [box(lo, hi) for lo, hi in legs]))])
    for j in range(nz):
        for i in range(nx):
            cx, cz = room_centre(i, j)
            g.node("table_%d_%d" % (i, j), table, translation=[cx + 1.0, 0.0, cz - 1.0], dynamic=True)

    # Two ceiling lamps per room.
    for j in range(nz):
        for i in range(nx):
            cx, cz = room_centre(i, j)
            for tag, s in (("a", -1), ("b", 1)):
                name = "lamp_%d_%d_%s" % (i, j, tag)
                light = g.point_light(name, LAMP_INTENSITY_CD, LAMP_COLOR)
                g.node(name, translation=[cx + s * LAMP_OFFSET_M, LAMP_HEIGHT_M, cz + s * LAMP_OFFSET_M],
                       light=light)
    return g, doors


def level(nx, nz, doors):
    route = walk_route(nx, nz)
    # Waypoints: room centres with the doorways between them.
    points = [room_centre(*route[0])]
    route_doors = set()
    for a, b in zip(route, route[1:]):
        (ax, az), (bx, bz) = room_centre(*a), room_centre(*b)
        points += [((ax + bx) / 2, (az + bz) / 2), (bx, bz)]
        route_doors.add(door_between(a, b))
    if len(points) == 1:  # a single room: walk to the opposite corner
        cx, cz = points[0]
        points.append((cx - 1.2, cz + 1.2))
    keys, t = [], 0.0
    for k, (x, z) in enumerate(points):
        if k > 0:
            px, pz = points[k - 1]
            t += math.hypot(x - px, z - pz) / WALK_SPEED_M_S
        if k + 1 < len(points):
            lx, lz = points[k + 1]
        else:  # keep looking the way we came in
            px, pz = points[k - 1]
            lx, lz = x + (x - px), z + (z - pz)
        key = {"t_s": round(t, 3), "position": [round(x, 4), EYE_HEIGHT_M, round(z, 4)],
               "look_at": [round(lx, 4), EYE_HEIGHT_M - 0.1, round(lz, 4)]}
        if k == 0:
            key["yfov_rad"] = 1.1
        keys.append(key)

    paths = []
    # One door off the walk swings shut and opens again.
    spare = [d for d in sorted(doors) if d not in route_doors]
    if spare:
        name = spare[0]
        (hx, hz), closed_rad, open_rad = doors[name]
        paths.append({"node": name, "loop": True, "keys": [
            {"t_s": 0, "rotation": [round(c, 8) for c in y_rotation(open_rad)]},
            {"t_s": 3, "rotation": [round(c, 8) for c in y_rotation(closed_rad)]},
            {"t_s": 6, "rotation": [round(c, 8) for c in y_rotation(closed_rad)]},
            {"t_s": 9, "rotation": [round(c, 8) for c in y_rotation(open_rad)]}]})
    # The first room's table is pushed 0.7 m along -x and back (it stays off
    # the walk, which runs along z = cz there).
    cx, cz = room_centre(0, 0)
    paths.append({"node": "table_0_0", "loop": True, "keys": [
        {"t_s": 0, "translation": [round(cx + 1.0, 4), 0.0, round(cz - 1.0, 4)]},
        {"t_s": 4, "translation": [round(cx + 0.3, 4), 0.0, round(cz - 1.0, 4)]},
        {"t_s": 8, "translation": [round(cx + 1.0, 4), 0.0, round(cz - 1.0, 4)]}]})

    return {
        "description": "A house of %d x %d rooms (4 x 4 x 3 m) with doors, two ceiling lamps and a table per "
                       "room; written by make_house.py --rooms-x %d --rooms-z %d." % (nx, nz, nx, nz),
        "gltf": "house.gltf",
        "paths": paths,
        "camera_paths": [{"name": "main", "loop": False, "keys": keys}],
    }


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--rooms-x", type=int, default=2, help="rooms along x (1..64, default 2)")
    parser.add_argument("--rooms-z", type=int, default=2, help="rooms along z (1..64, default 2)")
    parser.add_argument("--out", default=os.path.dirname(os.path.abspath(__file__)),
                        help="output directory (default: this script's directory)")
    args = parser.parse_args(argv)
    for name, value in (("--rooms-x", args.rooms_x), ("--rooms-z", args.rooms_z)):
        if not 1 <= value <= 64:
            parser.error("%s must be in 1..64, got %d" % (name, value))
    os.makedirs(args.out, exist_ok=True)
    g, doors = build(args.rooms_x, args.rooms_z)
    g.write(args.out, "house")
    with open(os.path.join(args.out, "level.json"), "w") as f:
        f.write(to_json(level(args.rooms_x, args.rooms_z, doors)) + "\n")
    print("%s: %d x %d rooms, %d lamps, %d doors, %d meshes, %d bytes of buffer" % (
        args.out, args.rooms_x, args.rooms_z, len(g.lights), len(doors), len(g.meshes), len(g.blob)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
