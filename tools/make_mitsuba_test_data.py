#!/usr/bin/env python3
"""Writes the assets of the Mitsuba-compatibility scenes in tests/data/mitsuba/.

Everything is generated here (the project ships no one else's assets): textures (JPEG, with
PIL), an environment map (OpenEXR, with Mitsuba's Bitmap), meshes (PLY and OBJ as text,
Mitsuba's serialized format with zlib, following the layout in src/shape/serialized.rs), and a
UTF-16 copy of one scene. Deterministic: running it again rewrites the same files.

    python3 tools/make_mitsuba_test_data.py
"""

import math
import os
import struct
import zlib

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "..", "tests", "data", "mitsuba")


def path(*parts):
    p = os.path.join(OUT, *parts)
    os.makedirs(os.path.dirname(p), exist_ok=True)
    return p


# ---------------------------------------------------------------- textures

def textures():
    from PIL import Image

    # An orientation chart: warm checks in the top half, cool checks in the bottom half, a
    # white bar along the left edge. Mirroring it in u or v changes every block of a render.
    n = 64
    img = np.zeros((n, n, 3), np.uint8)
    for y in range(n):
        for x in range(n):
            check = ((x // 8) + (y // 8)) % 2
            if y < n // 2:
                img[y, x] = (220, 90, 40) if check else (120, 30, 20)
            else:
                img[y, x] = (40, 110, 220) if check else (20, 40, 110)
            if x < 6:
                img[y, x] = (240, 240, 240)
    Image.fromarray(img).save(path("textures", "chart.jpg"), quality=95, subsampling=0)

    # Four flat 8x8 blocks (one JPEG block each, so they decode almost exactly), for the
    # decoder test: baseline colour, progressive colour, greyscale.
    blocks = np.zeros((16, 16, 3), np.uint8)
    colours = [(200, 40, 30), (30, 180, 60), (20, 50, 210), (250, 250, 250)]
    for k, c in enumerate(colours):
        y, x = 8 * (k // 2), 8 * (k % 2)
        blocks[y:y + 8, x:x + 8] = c
    Image.fromarray(blocks).save(path("textures", "blocks.jpg"), quality=100, subsampling=0)
    Image.fromarray(blocks).save(path("textures", "blocks_progressive.jpg"), quality=100,
                                 subsampling=0, progressive=True)
    grey = np.zeros((16, 16), np.uint8)
    for k, v in enumerate([10, 90, 170, 250]):
        y, x = 8 * (k // 2), 8 * (k % 2)
        grey[y:y + 8, x:x + 8] = v
    Image.fromarray(grey, "L").save(path("textures", "blocks_grey.jpg"), quality=100)


def envmap():
    import mitsuba as mi
    mi.set_variant("scalar_rgb")
    w, h = 64, 32
    data = np.zeros((h, w, 3), np.float32)
    for y in range(h):
        theta = math.pi * (y + 0.5) / h
        for x in range(w):
            phi = 2 * math.pi * (x + 0.5) / w
            up = max(math.cos(theta), 0.0)
            sky = np.array([0.35, 0.55, 1.0]) * (0.3 + 0.7 * up)
            ground = np.array([0.25, 0.2, 0.15])
            c = sky if theta < math.pi / 2 else ground
            # Vertical stripes every eighth of the way round: blocky lookups show at their edges.
            if (x // 4) % 4 == 0 and theta < math.pi / 2:
                c = c * 1.8
            data[y, x] = c
    # A small bright sun.
    data[8, 20] = (40.0, 36.0, 30.0)
    data[8, 21] = (20.0, 18.0, 15.0)
    mi.Bitmap(data).write(path("envmap", "sky.exr"))


# ---------------------------------------------------------------- meshes

def write_ply(name, positions, faces, normals=None, uvs=None):
    lines = ["ply", "format ascii 1.0", f"element vertex {len(positions)}",
             "property float x", "property float y", "property float z"]
    if normals is not None:
        lines += ["property float nx", "property float ny", "property float nz"]
    if uvs is not None:
        lines += ["property float u", "property float v"]
    lines += [f"element face {len(faces)}", "property list uchar int vertex_indices",
              "end_header"]
    for i, p in enumerate(positions):
        row = list(p)
        if normals is not None:
            row += list(normals[i])
        if uvs is not None:
            row += list(uvs[i])
        lines.append(" ".join(f"{v:.6g}" for v in row))
    for f in faces:
        lines.append(" ".join(str(v) for v in [len(f)] + list(f)))
    with open(path("meshes", name), "w") as fh:
        fh.write("\n".join(lines) + "\n")


def quad():
    """A unit quad in z = 0 facing +z, uv (0, 0) at the lower-left corner (y = -1)."""
    p = [(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)]
    n = [(0, 0, 1)] * 4
    uv = [(0, 0), (1, 0), (1, 1), (0, 1)]
    return p, n, uv, [(0, 1, 2), (0, 2, 3)]


def meshes():
    p, n, uv, f = quad()
    write_ply("quad_uv.ply", p, f, n, uv)
    # The same quad as OBJ: Mitsuba flips OBJ's v, so store 1 - v to show the same image.
    with open(path("meshes", "quad_uv.obj"), "w") as fh:
        fh.write("# unit quad, texture v stored flipped\n")
        for q in p:
            fh.write("v %g %g %g\n" % q)
        for t in uv:
            fh.write("vt %g %g\n" % (t[0], 1 - t[1]))
        fh.write("vn 0 0 1\n")
        fh.write("f 1/1/1 2/2/1 3/3/1\nf 1/1/1 3/3/1 4/4/1\n")
    # A mesh of zero-area triangles only (collinear corners): loading skips it with a warning.
    write_ply("degenerate.ply", [(0, 0, 0), (1, 0, 0), (2, 0, 0), (3, 0, 0)],
              [(0, 1, 2), (1, 2, 3), (0, 0, 1)])


def icosphere(subdiv):
    t = (1 + 5 ** 0.5) / 2
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t),
         (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    v = [tuple(c / math.sqrt(sum(x * x for x in p)) for c in p) for p in v]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
         (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
         (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(subdiv):
        cache = {}

        def mid(a, b):
            key = (min(a, b), max(a, b))
            if key not in cache:
                m = [(x + y) / 2 for x, y in zip(v[a], v[b])]
                l = math.sqrt(sum(c * c for c in m))
                v.append(tuple(c / l for c in m))
                cache[key] = len(v) - 1
            return cache[key]
        nf = []
        for a, b, c in f:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            nf += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        f = nf
    return v, f


def box():
    """A cube of half-size 1 with per-face vertices and normals."""
    p, n, f = [], [], []
    for axis in range(3):
        for s in (-1, 1):
            base = len(p)
            u, w = [(axis + 1) % 3, (axis + 2) % 3]
            for a, b in [(-1, -1), (1, -1), (1, 1), (-1, 1)]:
                q = [0, 0, 0]
                q[axis], q[u], q[w] = s, a, b
                p.append(tuple(q))
                nn = [0, 0, 0]
                nn[axis] = s
                n.append(tuple(nn))
            if s > 0:
                f += [(base, base + 1, base + 2), (base, base + 2, base + 3)]
            else:
                f += [(base, base + 2, base + 1), (base, base + 3, base + 2)]
    return p, n, f


def serialized_mesh(version, name, positions, faces, normals=None, uvs=None, double=False,
                    colours=False):
    """One mesh: header plus its zlib stream (see src/shape/serialized.rs)."""
    flags = 0x2000 if double else 0x1000
    flags |= 0x1 if normals is not None else 0
    flags |= 0x2 if uvs is not None else 0
    flags |= 0x8 if colours else 0
    raw = struct.pack("<I", flags)
    if version == 4:
        raw += name.encode() + b"\0"
    raw += struct.pack("<QQ", len(positions), len(faces))
    fmt = "<d" if double else "<f"

    def reals(rows):
        return b"".join(struct.pack(fmt, float(x)) for r in rows for x in r)
    raw += reals(positions)
    if normals is not None:
        raw += reals(normals)
    if uvs is not None:
        raw += reals(uvs)
    if colours:
        raw += reals([(0.5, 0.5, 0.5)] * len(positions))
    raw += b"".join(struct.pack("<III", *t) for t in faces)
    return struct.pack("<HH", 0x041C, version) + zlib.compress(raw, 9)


def serialized_file(name, version, meshes):
    out, offsets = b"", []
    for m in meshes:
        offsets.append(len(out))
        out += m
    for o in offsets:
        out += struct.pack("<Q" if version == 4 else "<I", o)
    out += struct.pack("<I", len(meshes))
    with open(path("meshes", name), "wb") as fh:
        fh.write(out)


def serialized():
    bp, bn, bf = box()
    sp, sf = icosphere(2)
    # uv from the direction, so that a texture shows how uvs are read.
    suv = [(0.5 + math.atan2(p[0], -p[2]) / (2 * math.pi), math.acos(max(-1, min(1, p[1]))) / math.pi)
           for p in sp]
    # Version 4, single precision: a box with normals, then a sphere without normals (Mitsuba
    # shades it smoothly) but with uvs.
    serialized_file("two.serialized", 4, [
        serialized_mesh(4, "box", bp, bf, normals=bn),
        serialized_mesh(4, "ball", sp, sf, uvs=suv),
    ])
    # Version 3, double precision with vertex colours, three meshes: shape_index picks one.
    hp, hf = icosphere(1)
    serialized_file("legacy_v3.serialized", 3, [
        serialized_mesh(3, "", bp, bf, normals=bn, double=True, colours=True),
        serialized_mesh(3, "", hp, hf, double=True),
        serialized_mesh(3, "", [(0, 0, 0), (1, 0, 0), (0, 1, 0)], [(0, 1, 2)], double=True),
    ])


def utf16():
    with open(os.path.join(OUT, "utf8_spheres_v3.xml"), encoding="utf-8") as fh:
        text = fh.read()
    text = text.replace('<?xml version="1.0" encoding="utf-8"?>',
                        '<?xml version="1.0" encoding="UTF-16"?>')
    with open(os.path.join(OUT, "utf16_spheres_v3.xml"), "wb") as fh:
        fh.write(b"\xff\xfe" + text.encode("utf-16-le"))


if __name__ == "__main__":
    textures()
    envmap()
    meshes()
    serialized()
    utf16()
    print("wrote", os.path.normpath(OUT))
