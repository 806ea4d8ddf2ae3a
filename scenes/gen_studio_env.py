#!/usr/bin/env python3
"""Writes scenes/studio.hdr: a small procedural "photo studio" environment for the thin-film
scenes (no dependencies). Latitude-longitude, ophis/Mitsuba convention: v = θ/π from +y (up),
u = φ/2π with direction (sin φ sin θ, cos θ, −cos φ sin θ), so u = 0.5 is +z, behind a camera
that sits on +z looking at the origin: the softboxes there are what a sphere reflects back.

Content: a dark blue-grey room (0.02–0.05), a warm-grey floor below the horizon (0.08), two
rectangular softboxes (key: 8, fill: 3). Iridescence is
seen best as coloured bright reflections on a dark surround.
Run: python3 scenes/gen_studio_env.py  (writes scenes/studio.hdr, 128×64, flat RGBE, 32 KiB).
"""
import math
import os

W, H = 128, 64


def radiance(u, v):
    th = math.pi * v
    ph = 2 * math.pi * u
    d = (math.sin(ph) * math.sin(th), math.cos(th), -math.cos(ph) * math.sin(th))
    # Room and floor.
    if d[1] < 0:
        c = [0.08, 0.07, 0.06]
    else:
        g = 0.02 + 0.03 * d[1]
        c = [g, g * 1.1, g * 1.4]
    # Softboxes as (centre u, centre v, half width u, half height v, value).
    for cu, cv, hu, hv, val in [(0.42, 0.30, 0.08, 0.12, 8.0), (0.60, 0.40, 0.06, 0.10, 3.0)]:
        if abs(u - cu) < hu and abs(v - cv) < hv:
            c = [val, val, val]
    return c


def rgbe(c):
    m = max(c)
    if m < 1e-32:
        return bytes([0, 0, 0, 0])
    f, e = math.frexp(m)
    s = f * 256.0 / m
    return bytes([int(c[0] * s), int(c[1] * s), int(c[2] * s), e + 128])


def main():
    out = os.path.join(os.path.dirname(os.path.abspath(__file__)), "studio.hdr")
    with open(out, "wb") as f:
        f.write(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n")
        f.write(f"-Y {H} +X {W}\n".encode())
        for y in range(H):
            for x in range(W):
                f.write(rgbe(radiance((x + 0.5) / W, (y + 0.5) / H)))
    print("wrote", out)


if __name__ == "__main__":
    main()
