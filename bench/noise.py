#!/usr/bin/env python3
"""Time to equal noise: samplers and settings of one scene compared side by side in one run.

For each configuration (a sampler type, optionally more `-D` values), the scene is rendered twice
with different seeds; the two images are independent estimates of the same image, so half the
mean squared difference of the pair estimates each one's variance, with no converged reference:

    relVar = mean over pixels and channels of (a − b)² / 2 / (((a + b) / 2)² + ε),  ε = 1e-2

The efficiency is 1 / (relVar × render seconds); the script prints each configuration's
samples per second, relVar × spp (noise per sample; lower is better), and its efficiency
relative to the first configuration, which is how much faster it reaches equal noise (median
and range over `--repeats` pairs).

usage: python3 bench/noise.py [SCENE.xml] [--res 320x180] [--spp 32] [--repeats 2] [--cpu]
           [--config independent --config stratified --config "stratified:rr=1" ...]
`--cpu` times each render by its CPU seconds (all threads) instead of its wall-clock seconds:
on a shared machine a steadier measure of the work, for renders long enough that the
summary's 10 ms resolution does not matter (its Msamples/s are then per CPU second).
A configuration is SAMPLER[:NAME=VALUE,...]; the sampler is set through --sampler ophis's
command line does not have, so the scene must read `$sampler` (the built-in scene does).
Without SCENE the built-in scene (scenes/xenopeltis.xml) is used. Two names are not `-D`
values: `exe=PATH` renders that configuration with another ophis binary (an older build, to
measure a speed-up at equal noise) and `scene=PATH` with another scene file; a SAMPLER of `-`
leaves the scene's own sampler.

`--where` also says where the first configuration's noise lies: the share of its relVar held by
the noisiest 1, 5 and 20 % of pixels, and how much lower the mean relVar would be at the same
number of samples if each pixel's samples were in proportion to its eight neighbours' noise
(their root relVar, the pixel itself left out so that its own samples do not decide its count,
floored at a fifth of the mean): the allocation taken from one pair of renders and judged on
the next, assuming each pixel's variance falls as 1/samples (needs --repeats 2 or more). That is
the gain adaptive sampling could bring, before counting that noisy pixels may cost more per
sample.
"""
import argparse
import os
import re
import statistics
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = os.path.join(ROOT, "target", "bench", "noise")
sys.path.insert(0, os.path.join(ROOT, "tools"))


def read_rgb(path):
    import numpy as np
    from exr_read import read_exr
    ch, _ = read_exr(path)
    return np.stack([ch["R"], ch["G"], ch["B"]], axis=-1).astype(np.float64)


CPU_TIME = False


def render(scene, res, spp, seed, defines, out):
    defines = dict(defines)
    exe = defines.pop("exe", os.path.join(ROOT, "target", "release", "ophis"))
    scene = defines.pop("scene", scene)
    if defines.get("sampler") == "-":
        del defines["sampler"]
    w, h = res
    cmd = [exe, "render"] + ([scene] if scene else []) + [
        f"-Dwidth={w}", f"-Dheight={h}", f"-Dres={w}", "--spp", str(spp), "--seed", str(seed),
        "-o", out, "--quiet"]
    cmd += [f"-D{k}={v}" for k, v in defines.items()]
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit("ophis failed:\n" + p.stderr)
    return render_seconds(p.stderr)


def render_seconds(summary):
    """The render time from ophis's summary line: its seconds are printed to 10 ms, too coarse
    for renders of a tenth of a second, so it is recomputed from the samples-per-second figure
    (four significant digits) and the samples (width × height × spp)."""
    if CPU_TIME:
        m = re.search(r"spp, [0-9.]+ s, ([0-9.]+) CPU s,", summary)
        if not m:
            sys.exit("ophis printed no CPU time:\n" + summary)
        return float(m.group(1))
    m = re.search(r"(\d+)x(\d+), (\d+) spp, ([0-9.]+) s, .*?([0-9.]+) Msamples/s", summary)
    if not m:
        sys.exit("ophis printed no time:\n" + summary)
    w, h, spp, secs, rate = m.groups()
    if float(rate) > 0:
        return int(w) * int(h) * int(spp) / (float(rate) * 1e6)
    return float(secs)


def spread(xs, fmt="{:.3g}"):
    med = statistics.median(xs)
    if len(xs) == 1:
        return fmt.format(med)
    return (fmt + " ({}–{})").format(med, fmt.format(min(xs)), fmt.format(max(xs)))


def main():
    ap = argparse.ArgumentParser(description="time to equal noise")
    ap.add_argument("scene", nargs="?")
    ap.add_argument("--res", default="320x180")
    ap.add_argument("--spp", type=int, default=32)
    ap.add_argument("--repeats", type=int, default=2)
    ap.add_argument("--eps", type=float, default=1e-2)
    ap.add_argument("--config", action="append")
    ap.add_argument("--no-build", action="store_true")
    ap.add_argument("--cpu", action="store_true", help="time renders by CPU seconds")
    ap.add_argument("--where", action="store_true", help="where the first configuration's noise lies")
    a = ap.parse_args()
    global CPU_TIME
    CPU_TIME = a.cpu
    import numpy as np
    configs = a.config or ["independent", "stratified"]
    res = tuple(int(v) for v in a.res.split("x"))
    os.makedirs(OUT, exist_ok=True)
    if not a.no_build:
        subprocess.run(["cargo", "build", "--release", "--quiet", "--bin", "ophis"], cwd=ROOT, check=True)
    parsed = []
    for c in configs:
        sampler, _, rest = c.partition(":")
        d = {"sampler": sampler}
        for kv in filter(None, rest.split(",")):
            k, _, v = kv.partition("=")
            d[k] = v
        parsed.append((c, d))
    samples = res[0] * res[1] * a.spp
    print(f"{time.strftime('%Y-%m-%d')}: {a.scene or 'built-in scene'}, {res[0]}x{res[1]}, {a.spp} spp, "
          f"{os.cpu_count()} cores, {a.repeats} pairs per configuration: median (min–max)")
    stats = {c: {"t": [], "rv": []} for c, _ in parsed}
    for r in range(a.repeats):
        for c, d in parsed:  # interleaved, so that load changes hit every configuration alike
            imgs, ts = [], []
            for k in range(2):
                out = os.path.join(OUT, f"n{len(stats[c]['t'])}-{k}.exr")
                ts.append(render(a.scene, res, a.spp, 1 + 2 * r + k, d, out))
                imgs.append(read_rgb(out))
            x, y = imgs
            m = 0.5 * (x + y)
            per_pixel = np.mean((x - y) ** 2 / 2.0 / (m * m + a.eps), axis=-1)
            stats[c]["t"].append(sum(ts) / 2)
            stats[c]["rv"].append(float(np.mean(per_pixel)))
            stats[c].setdefault("maps", []).append(per_pixel)
    base = configs[0]
    unit = "CPU s" if a.cpu else "render s"
    print(f"  {'configuration':<32} {unit:>20} {'Msamples/s':>20} {'relVar × spp':>24} "
          f"{'equal-noise speed-up':>24}")
    for c, _ in parsed:
        t, rv = stats[c]["t"], stats[c]["rv"]
        eff = [1.0 / (tb * rb) for tb, rb in zip(t, rv)]
        base_eff = [1.0 / (tb * rb) for tb, rb in zip(stats[base]["t"], stats[base]["rv"])]
        gain = [e / b for e, b in zip(eff, base_eff)]
        print(f"  {c:<32} {spread(t):>20} {spread([samples / s / 1e6 for s in t]):>20} "
              f"{spread([v * a.spp for v in rv]):>24} {spread(gain):>24}")
    if a.where:
        where(stats[base]["maps"], base)


def neighbours_noise(rv):
    """Each pixel's sample share under the allocation `--where` describes (mean 1)."""
    import numpy as np
    s = np.sqrt(rv)
    h, w = s.shape
    p = np.pad(s, 1, mode="edge")
    around = sum(p[1 + dy:1 + dy + h, 1 + dx:1 + dx + w]
                 for dy in (-1, 0, 1) for dx in (-1, 0, 1) if (dy, dx) != (0, 0)) / 8.0
    around = np.maximum(around, 0.2 * around.mean())
    return around / around.mean()


def where(maps, name):
    import numpy as np
    flat = np.sort(maps[0].ravel())[::-1]
    shares = [flat[:max(1, int(f * flat.size))].sum() / flat.sum() for f in (0.01, 0.05, 0.2)]
    print(f"where the noise of {name} lies: the noisiest 1 / 5 / 20 % of pixels hold "
          + " / ".join(f"{100 * v:.0f}" for v in shares) + " % of its relVar")
    gains = [b.mean() / (b / neighbours_noise(a)).mean() for a, b in zip(maps, maps[1:])]
    if gains:
        print("  samples in proportion to the neighbours' noise: mean relVar ÷ "
              + spread(gains) + " at the same number of samples (allocation from one pair, "
              "judged on the next)")


if __name__ == "__main__":
    main()
