#!/usr/bin/env python3
"""Writes assets/scenes/cornell-box.gltf: the Cornell box as Cornell's graphics group publishes it
(https://www.graphics.cornell.edu/online/box/data.html), in millimetres: floor, ceiling, back wall, the red
(left) and green (right) walls and the short and tall blocks, each face the published quad split in two
triangles with its own flat normal. Materials are named white, red and green (assets/scenes/cornell-box.json
gives them their reflectances). The light is not geometry here: the JSON scene makes it a rect light of the
published size. Run from the repository root: python3 tools/cornell-box.py"""
import base64
import json
import struct

WHITE, RED, GREEN = 0, 1, 2
QUADS = [
    # floor, ceiling, back wall
    (WHITE, [(552.8, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 559.2), (549.6, 0.0, 559.2)]),
    (WHITE, [(556.0, 548.8, 0.0), (556.0, 548.8, 559.2), (0.0, 548.8, 559.2), (0.0, 548.8, 0.0)]),
    (WHITE, [(549.6, 0.0, 559.2), (0.0, 0.0, 559.2), (0.0, 548.8, 559.2), (556.0, 548.8, 559.2)]),
    # right wall (green), left wall (red)
    (GREEN, [(0.0, 0.0, 559.2), (0.0, 0.0, 0.0), (0.0, 548.8, 0.0), (0.0, 548.8, 559.2)]),
    (RED, [(552.8, 0.0, 0.0), (549.6, 0.0, 559.2), (556.0, 548.8, 559.2), (556.0, 548.8, 0.0)]),
    # short block
    (WHITE, [(130.0, 165.0, 65.0), (82.0, 165.0, 225.0), (240.0, 165.0, 272.0), (290.0, 165.0, 114.0)]),
    (WHITE, [(290.0, 0.0, 114.0), (290.0, 165.0, 114.0), (240.0, 165.0, 272.0), (240.0, 0.0, 272.0)]),
    (WHITE, [(130.0, 0.0, 65.0), (130.0, 165.0, 65.0), (290.0, 165.0, 114.0), (290.0, 0.0, 114.0)]),
    (WHITE, [(82.0, 0.0, 225.0), (82.0, 165.0, 225.0), (130.0, 165.0, 65.0), (130.0, 0.0, 65.0)]),
    (WHITE, [(240.0, 0.0, 272.0), (240.0, 165.0, 272.0), (82.0, 165.0, 225.0), (82.0, 0.0, 225.0)]),
    # tall block
    (WHITE, [(423.0, 330.0, 247.0), (265.0, 330.0, 296.0), (314.0, 330.0, 456.0), (472.0, 330.0, 406.0)]),
    (WHITE, [(423.0, 0.0, 247.0), (423.0, 330.0, 247.0), (472.0, 330.0, 406.0), (472.0, 0.0, 406.0)]),
    (WHITE, [(472.0, 0.0, 406.0), (472.0, 330.0, 406.0), (314.0, 330.0, 456.0), (314.0, 0.0, 456.0)]),
    (WHITE, [(314.0, 0.0, 456.0), (314.0, 330.0, 456.0), (265.0, 330.0, 296.0), (265.0, 0.0, 296.0)]),
    (WHITE, [(265.0, 0.0, 296.0), (265.0, 330.0, 296.0), (423.0, 330.0, 247.0), (423.0, 0.0, 247.0)]),
]


def sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def unit(v):
    n = sum(x * x for x in v) ** 0.5
    return tuple(x / n for x in v)


def main():
    meshes, accessors, views, blob = [], [], [], bytearray()

    def add(data, fmt, count, kind, target, extra=None):
        offset = len(blob)
        blob.extend(struct.pack("<" + fmt * (len(data) // len(fmt)), *data))
        while len(blob) % 4:
            blob.append(0)
        views.append({"buffer": 0, "byteOffset": offset, "byteLength": len(blob) - offset, "target": target})
        acc = {"bufferView": len(views) - 1, "componentType": 5126 if fmt == "f" else 5125, "count": count,
               "type": kind}
        acc.update(extra or {})
        accessors.append(acc)
        return len(accessors) - 1

    for material in (WHITE, RED, GREEN):
        positions, normals, indices = [], [], []
        for m, quad in QUADS:
            if m != material:
                continue
            # The published quads all face into the box (or out of the blocks) counter-clockwise from there.
            n = unit(cross(sub(quad[1], quad[0]), sub(quad[2], quad[0])))
            base = len(positions) // 3
            for p in quad:
                positions.extend(p)
                normals.extend(n)
            indices.extend([base, base + 1, base + 2, base, base + 2, base + 3])
        lo = [min(positions[i::3]) for i in range(3)]
        hi = [max(positions[i::3]) for i in range(3)]
        pos = add(positions, "f", len(positions) // 3, "VEC3", 34962, {"min": lo, "max": hi})
        nor = add(normals, "f", len(normals) // 3, "VEC3", 34962)
        idx = add(indices, "I", len(indices), "SCALAR", 34963)
        meshes.append({"name": ["white", "red", "green"][material],
                       "primitives": [{"attributes": {"POSITION": pos, "NORMAL": nor}, "indices": idx,
                                       "material": material}]})
    gltf = {
        "asset": {"version": "2.0", "generator": "tools/cornell-box.py (Cornell's published box data)"},
        "scene": 0,
        "scenes": [{"nodes": [0, 1, 2]}],
        "nodes": [{"mesh": i, "name": meshes[i]["name"]} for i in range(3)],
        "meshes": meshes,
        "materials": [{"name": name, "pbrMetallicRoughness": {"baseColorFactor": color + [1.0], "metallicFactor": 0.0,
                                                              "roughnessFactor": 1.0}}
                      for name, color in (("white", [0.725, 0.71, 0.68]), ("red", [0.63, 0.065, 0.05]),
                                          ("green", [0.14, 0.45, 0.091]))],
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": len(blob),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(blob)).decode()}],
    }
    with open("assets/scenes/cornell-box.gltf", "w") as f:
        json.dump(gltf, f, indent=1)
        f.write("\n")


if __name__ == "__main__":
    main()
