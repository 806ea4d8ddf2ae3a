#!/usr/bin/env python3
"""Counts fireflies in ophis EXR renders: pixels whose luminance exceeds `--factor` (default 8)
times the median of their 5×5 neighbourhood and is above `--floor` (default 0.05), i.e. isolated
spikes a denoiser or the eye would call fireflies, not edges or highlights (which have bright
neighbours).

    python3 tools/fireflies.py render.exr [more.exr …]

Used for the flagship's firefly check (issue 14): see scenes/xenopeltis.xml for the cause found.
"""

import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from exr_read import read_exr  # noqa: E402


def fireflies(lum, factor, floor, radius=2):
    h, w = lum.shape
    pad = np.pad(lum, radius, mode="edge")
    stack = [
        pad[dy : dy + h, dx : dx + w]
        for dy in range(2 * radius + 1)
        for dx in range(2 * radius + 1)
        if (dy, dx) != (radius, radius)
    ]
    med = np.median(np.stack(stack), axis=0)
    return (lum > factor * med) & (lum > floor)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("exr", nargs="+")
    ap.add_argument("--factor", type=float, default=8.0)
    ap.add_argument("--floor", type=float, default=0.05)
    args = ap.parse_args()
    for path in args.exr:
        p, _ = read_exr(path)
        lum = 0.2126 * p["R"] + 0.7152 * p["G"] + 0.0722 * p["B"]
        f = fireflies(lum, args.factor, args.floor)
        print(f"{path}: {int(f.sum())} fireflies in {lum.size} pixels "
              f"(luminance > {args.factor:g}× the 5×5 median and > {args.floor:g})")


if __name__ == "__main__":
    main()
