#!/usr/bin/env python3
"""End-to-end benchmark: ophis vs Mitsuba 3 on the same XML scenes, in one run.

Renders scenes/cornell-box.xml (diffuse, glass and rough-gold spheres) and scenes/cornell-mesh.xml
(the same room with a ~1M-triangle mesh) with ophis, and — where `import mitsuba` works — with
Mitsuba 3's `llvm_ad_spectral` and `scalar_spectral` variants, at the same resolution, samples per
pixel and path depth. Prints samples per second for each and the ratios, plus each image's mean
linear-sRGB colour so that a mismatch in the scenes shows.

Times are render times: ophis's own summary line (after loading and BVH build); Mitsuba's
`mi.render` call, run twice with the second one timed so that LLVM's JIT compilation is excluded
(the first time is printed too).

usage: python3 bench/run.py [--spp 64] [--res 256] [--no-build] [--no-mitsuba]
Mitsuba's llvm variants need Debian's libllvm19 (apt-get install libllvm19).
"""
import argparse
import os
import re
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = os.path.join(ROOT, "target", "bench")


def ophis_render(scene, spp, res, defines, out):
    exe = os.path.join(ROOT, "target", "release", "ophis")
    cmd = [exe, "render", scene, "-Dspp=%d" % spp, "-Dres=%d" % res, "-o", out, "--quiet"]
    cmd += ["-D%s=%s" % kv for kv in defines.items()]
    t0 = time.time()
    p = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.time() - t0
    if p.returncode != 0:
        sys.exit("ophis failed:\n" + p.stderr)
    m = re.search(r"spp, ([0-9.]+) s,", p.stderr)
    secs = float(m.group(1)) if m else wall
    return secs, wall


def mean_rgb_exr(path):
    try:
        import mitsuba as mi  # noqa: F401  (Bitmap reads EXR)
        import numpy as np
        b = np.array(mi.Bitmap(path))
        return b[..., :3].reshape(-1, 3).mean(axis=0)
    except Exception:
        return None


def mitsuba_render(variant, scene, spp, res, defines, out):
    import mitsuba as mi
    import numpy as np
    mi.set_variant(variant)
    params = dict(spp=spp, res=res, **defines)
    sc = mi.load_file(scene, **params)
    t0 = time.time()
    img = mi.render(sc, spp=spp, seed=0)
    np.array(img)
    first = time.time() - t0
    t0 = time.time()
    img = mi.render(sc, spp=spp, seed=1)
    arr = np.array(img)
    second = time.time() - t0
    mi.Bitmap(img).write(out)
    return second, first, arr[..., :3].reshape(-1, 3).mean(axis=0)


def main():
    ap = argparse.ArgumentParser(description="ophis vs Mitsuba 3 benchmark")
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--res", type=int, default=256)
    ap.add_argument("--no-build", action="store_true")
    ap.add_argument("--no-mitsuba", action="store_true")
    a = ap.parse_args()
    os.makedirs(OUT, exist_ok=True)
    if not a.no_build:
        subprocess.run(["cargo", "build", "--release", "--quiet"], cwd=ROOT, check=True)
    mesh = os.path.join(OUT, "blob.ply")
    if not os.path.exists(mesh):
        subprocess.run([sys.executable, os.path.join(ROOT, "bench", "make_mesh.py"), mesh], check=True)

    have_mi = False
    if not a.no_mitsuba:
        try:
            import mitsuba  # noqa: F401
            have_mi = True
        except ImportError:
            print("(mitsuba not installed: pip install mitsuba — ophis only)")

    samples = a.res * a.res * a.spp
    print(f"resolution {a.res}x{a.res}, {a.spp} spp, {samples} samples per image, {os.cpu_count()} cores")
    print(f"{'scene':<14} {'renderer':<24} {'render s':>9} {'Msamples/s':>11} {'ophis ×':>8}  mean linear sRGB")
    for name, defines in [("cornell-box", {}), ("cornell-mesh", {"mesh": mesh})]:
        scene = os.path.join(ROOT, "scenes", name + ".xml")
        out = os.path.join(OUT, f"{name}-ophis.exr")
        secs, wall = ophis_render(scene, a.spp, a.res, defines, out)
        ophis_sps = samples / secs
        mean = mean_rgb_exr(out)
        ms = "" if mean is None else "(%.4f, %.4f, %.4f)" % tuple(mean)
        print(f"{name:<14} {'ophis':<24} {secs:9.2f} {ophis_sps / 1e6:11.3f} {'':>8}  {ms}   (wall {wall:.2f} s incl. load)")
        if not have_mi:
            continue
        for variant in ["llvm_ad_spectral", "scalar_spectral"]:
            try:
                secs_m, first, mean_m = mitsuba_render(variant, scene, a.spp, a.res, defines,
                                                       os.path.join(OUT, f"{name}-{variant}.exr"))
            except Exception as e:  # e.g. libLLVM missing
                print(f"{name:<14} {'mitsuba ' + variant:<24} failed: {str(e).splitlines()[0][:80]}")
                continue
            sps = samples / secs_m
            print(f"{name:<14} {'mitsuba ' + variant:<24} {secs_m:9.2f} {sps / 1e6:11.3f} {ophis_sps / sps:8.2f}  "
                  f"({mean_m[0]:.4f}, {mean_m[1]:.4f}, {mean_m[2]:.4f})   (first run {first:.2f} s)")


if __name__ == "__main__":
    main()
