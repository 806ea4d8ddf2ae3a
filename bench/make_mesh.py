#!/usr/bin/env python3
"""Writes a ~1,000,000-triangle binary PLY mesh for the benchmark scene cornell-mesh.xml.

The mesh is a lumpy blob: a UV sphere (n_theta x n_phi quads) whose radius is modulated by a few
sines, placed on the Cornell box floor. Pure Python + the standard library, ~10 s.

usage: make_mesh.py OUT.ply [--triangles N]
"""
import argparse
import math
import os
import struct


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out")
    ap.add_argument("--triangles", type=int, default=1_000_000)
    a = ap.parse_args()
    # A UV sphere with nt rows and nphi columns has 2*nphi*(nt-1) triangles.
    nphi = int(math.sqrt(a.triangles / 1.0))
    nt = a.triangles // (2 * nphi) + 1
    cx, cy, cz, r0 = 0.0, -0.55, 0.0, 0.42
    verts = []
    for i in range(nt + 1):
        th = math.pi * i / nt
        for j in range(nphi):
            ph = 2 * math.pi * j / nphi
            r = r0 * (1 + 0.08 * math.sin(5 * th) * math.cos(4 * ph) + 0.03 * math.sin(17 * th + 3 * ph))
            x = r * math.sin(th) * math.cos(ph)
            y = r * math.cos(th)
            z = r * math.sin(th) * math.sin(ph)
            verts.append((cx + x, cy + 0.9 * y, cz + z))
    faces = []
    for i in range(nt):
        for j in range(nphi):
            a0 = i * nphi + j
            a1 = i * nphi + (j + 1) % nphi
            b0 = a0 + nphi
            b1 = a1 + nphi
            if i != 0:
                faces.append((a0, a1, b1))
            if i != nt - 1:
                faces.append((a0, b1, b0))
    os.makedirs(os.path.dirname(os.path.abspath(a.out)), exist_ok=True)
    tmp = a.out + ".tmp"
    with open(tmp, "wb") as f:
        f.write(b"ply\nformat binary_little_endian 1.0\n")
        f.write(b"comment ophis benchmark blob\n")
        f.write(f"element vertex {len(verts)}\n".encode())
        f.write(b"property float x\nproperty float y\nproperty float z\n")
        f.write(f"element face {len(faces)}\n".encode())
        f.write(b"property list uchar int vertex_indices\nend_header\n")
        f.write(b"".join(struct.pack("<3f", *v) for v in verts))
        f.write(b"".join(struct.pack("<B3i", 3, *t) for t in faces))
    os.replace(tmp, a.out)
    print(f"{a.out}: {len(verts)} vertices, {len(faces)} triangles")


if __name__ == "__main__":
    main()
