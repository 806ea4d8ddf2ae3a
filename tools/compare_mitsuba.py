#!/usr/bin/env python3
"""Renders the Mitsuba-style test scenes with ophis and with Mitsuba 3 (scalar_spectral) and
compares them against Mitsuba's own noise.

For every scene (default: all of tests/data/mitsuba/*.xml) both renderers make K independent
renders (seeds 0..K-1) at the same samples per pixel. Printed per scene:

- the mean linear-sRGB colour of the image, ophis and Mitsuba (mean of the K renders);
- the relative difference per channel, and z = difference / combined standard error, where
  each renderer's standard error comes from the spread of its K image means;
- the largest |z| over a 4 x 4 grid of image blocks and the channels (a mirrored texture or a
  misplaced shape keeps the image mean but moves block means).

With --noise SCENE (default veach_mis_v3.xml when it is among the scenes), it also prints the
per-pixel noise (standard deviation across the K renders) of ophis relative to Mitsuba's in
regions of the Veach-style scene: the highlight of each small light on the plates, and the
backdrop lit by the big light.

    python3 tools/compare_mitsuba.py                      # all scenes, 64 spp, K = 6
    python3 tools/compare_mitsuba.py --spp 16 --seeds 8 tests/data/mitsuba/cbox_v06.xml
    python3 tools/compare_mitsuba.py --ophis /path/to/other/ophis   # e.g. an older build

Needs `import mitsuba` and numpy; ophis is target/release/ophis unless --ophis says otherwise.
"""

import argparse
import glob
import os
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, ".."))
DATA = os.path.join(ROOT, "tests", "data", "mitsuba")


def render_ophis(ophis, scene, spp, seed, tmp):
    out = os.path.join(tmp, f"ophis_{seed}.exr")
    cmd = [ophis, "render", scene, "--spp", str(spp), "--seed", str(seed), "-q", "-o", out]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        raise RuntimeError(f"ophis failed on {scene}:\n{r.stderr}")
    import mitsuba as mi
    return np.array(mi.Bitmap(out), dtype=np.float64)[..., :3]


def render_mitsuba(scene_obj, spp, seed):
    import mitsuba as mi
    return np.array(mi.render(scene_obj, spp=spp, seed=seed), dtype=np.float64)[..., :3]


def blocks(img, n=4):
    h, w, _ = img.shape
    out = np.zeros((n, n, 3))
    for by in range(n):
        for bx in range(n):
            out[by, bx] = img[by * h // n:(by + 1) * h // n, bx * w // n:(bx + 1) * w // n].mean(axis=(0, 1))
    return out


def stats(renders):
    """Mean and standard error of the image mean and of the block means, over renders."""
    k = len(renders)
    means = np.array([r.mean(axis=(0, 1)) for r in renders])
    bl = np.array([blocks(r) for r in renders])
    return (means.mean(0), means.std(0, ddof=1) / np.sqrt(k),
            bl.mean(0), bl.std(0, ddof=1) / np.sqrt(k))


def z_scores(a, sa, b, sb):
    se = np.sqrt(sa ** 2 + sb ** 2)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(se > 0, (a - b) / se, np.where(a == b, 0.0, np.inf))


def noise_report(o_renders, m_renders):
    """Per-pixel standard deviation across renders, ophis over Mitsuba, by region."""
    so = np.stack(o_renders).std(0, ddof=1).mean(-1)
    sm = np.stack(m_renders).std(0, ddof=1).mean(-1)
    h, w = so.shape
    # Image geometry of veach_mis_v3.xml (fov 35 along x, camera 10 away): world (x, y) on the
    # plates' plane maps to column (x / 3.15 + 1) w / 2 and row (1 - y / 2.36) h / 2.
    col = lambda x: int(round((x / 3.153 + 1) * w / 2))
    row = lambda y: int(round((1 - y / 2.364) * h / 2))
    plate_rows = np.zeros(h, bool)
    for yc in (1.2, 0.4, -0.4, -1.2):
        plate_rows[row(yc + 0.25):row(yc - 0.25)] = True
    # Each light's highlight lies near x = 2/3 of the light's x (the mirror image seen from
    # the camera); bands split halfway between neighbouring highlights.
    centres = [-2.0, -0.667, 0.667, 2.0]
    edges = [-2.9, -1.333, 0.0, 1.333, 2.9]
    names = ["r=0.03", "r=0.10", "r=0.20", "r=0.35"]
    print("  per-pixel noise, ophis / Mitsuba (RMS of the standard deviation over a region):")
    for k, name in enumerate(names):
        c0, c1 = col(edges[k]), col(edges[k + 1])
        mask = np.zeros((h, w), bool)
        mask[plate_rows, c0:c1] = True
        ratio = np.sqrt((so[mask] ** 2).mean() / (sm[mask] ** 2).mean())
        print(f"    highlights of the light {name} (x = {centres[k] * 1.5:+.0f}): {ratio:5.2f}")
    mask = np.zeros((h, w), bool)
    mask[:row(1.75), :] = True
    ratio = np.sqrt((so[mask] ** 2).mean() / (sm[mask] ** 2).mean())
    print(f"    backdrop lit by the big light:           {ratio:5.2f}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("scenes", nargs="*", help="scene files (default: tests/data/mitsuba/*.xml)")
    ap.add_argument("--ophis", default=os.path.join(ROOT, "target", "release", "ophis"))
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--seeds", type=int, default=6, help="independent renders per renderer")
    ap.add_argument("--noise", default=None, help="scene for the noise report")
    args = ap.parse_args()
    scenes = args.scenes or sorted(glob.glob(os.path.join(DATA, "*.xml")))
    if args.seeds < 2:
        sys.exit("--seeds must be at least 2 (the noise comes from the spread between renders)")
    noise_scene = args.noise or next((s for s in scenes if s.endswith("veach_mis_v3.xml")), None)

    import mitsuba as mi
    mi.set_variant("scalar_spectral")
    print(f"ophis: {args.ophis}; Mitsuba {mi.__version__} scalar_spectral; "
          f"{args.spp} spp x {args.seeds} seeds each")
    print(f"{'scene':24} {'ophis mean RGB':>26} {'Mitsuba mean RGB':>26} "
          f"{'rel. diff %':>20} {'z':>17} {'max|z| blocks':>13}")
    worst = 0.0
    failed = 0
    for scene in scenes:
        name = os.path.basename(scene)
        with tempfile.TemporaryDirectory() as tmp:
            try:
                o = [render_ophis(args.ophis, scene, args.spp, s, tmp) for s in range(args.seeds)]
            except RuntimeError as e:
                # The first error line says where and why it does not load.
                msg = next((l for l in str(e).splitlines() if l.startswith("error")), str(e))
                print(f"{name:24} ophis does not load it: {msg.strip()[:150]}")
                failed += 1
                continue
        m_scene = mi.load_file(scene)
        m = [render_mitsuba(m_scene, args.spp, s) for s in range(args.seeds)]
        om, ose, ob, obse = stats(o)
        mm, mse, mb, mbse = stats(m)
        rel = 100 * (om - mm) / np.maximum(np.abs(mm), 1e-12)
        z = z_scores(om, ose, mm, mse)
        zbs = np.abs(z_scores(ob, obse, mb, mbse))
        zb = zbs.max()
        by, bx, bc = np.unravel_index(np.argmax(zbs), zbs.shape)
        worst = max(worst, np.abs(z).max(), zb)
        fmt = lambda v, p: " ".join(f"{x:{p}}" for x in v)
        print(f"{name:24} {fmt(om, '8.4f'):>26} {fmt(mm, '8.4f'):>26} {fmt(rel, '+6.1f'):>20} "
              f"{fmt(z, '+5.1f'):>17} {zb:13.1f}")
        if zb > 4:
            print(f"  worst block: column {bx}, row {by} (of 4 x 4), channel {'RGB'[bc]}: "
                  f"ophis {ob[by, bx, bc]:.4f}, Mitsuba {mb[by, bx, bc]:.4f} "
                  f"({100 * (ob[by, bx, bc] / mb[by, bx, bc] - 1):+.1f} %)")
        if scene == noise_scene:
            noise_report(o, m)
    print(f"largest |z|: {worst:.1f} (|z| > 4 is a difference beyond both renderers' noise); "
          f"{failed} of {len(scenes)} scenes did not load in ophis")


if __name__ == "__main__":
    main()
