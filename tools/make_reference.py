#!/usr/bin/env python3
"""Renders tests/data/reference.xml with Mitsuba 3 (an independent renderer) at a high sample
count and writes tests/data/reference-mitsuba.exr, the reference of tests/reference_image.rs.

usage: pip install mitsuba; python3 tools/make_reference.py [--spp 16384] [--variant scalar_spectral]
"""
import argparse
import os

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--spp", type=int, default=16384)
    ap.add_argument("--variant", default="scalar_spectral")
    a = ap.parse_args()
    import mitsuba as mi
    mi.set_variant(a.variant)
    scene = mi.load_file(os.path.join(ROOT, "tests", "data", "reference.xml"), spp=a.spp)
    img = mi.render(scene, spp=a.spp, seed=12345)
    out = os.path.join(ROOT, "tests", "data", "reference-mitsuba.exr")
    mi.Bitmap(img).convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32).write(out)
    print(f"wrote {out} ({a.variant}, {a.spp} spp)")


if __name__ == "__main__":
    main()
