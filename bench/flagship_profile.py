#!/usr/bin/env python3
"""Where the flagship's time goes: its samples per second and a profile split by subsystem.

    python3 bench/flagship_profile.py [--res 320x180] [--spp 16] [--repeats 2] [--freq 400]
                                      [--full] [-D NAME=VALUE ...]

1. Speed: the built-in scene (scenes/xenopeltis.xml) rendered on all threads, `--repeats`
   times at --res and --spp (`--full`: also once at 640×360 and 256 spp, the speed issue's
   setting; the scene's own default is 128 spp); prints
   samples per second, median (min–max).
2. Profile: one render on one thread under `perf record` (cpu-clock, DWARF call stacks, so
   inlined functions are seen), each sample given to the first subsystem found walking its
   call stack from the innermost frame outwards (C library copies and kernel frames are
   given to their caller). Film optics called from the layered walk count as film optics,
   the scales texture called by the bump map as the texture, and so on: the shares are
   exclusive and sum to 100 % (scene loading and the BVH build are counted apart). The time
   per sample of each subsystem is its share of the CPU time per sample of the same render on
   one thread without perf.

Needs `perf` (Debian: linux-perf) and a release build (`cargo build --release`).
"""
import argparse
import collections
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EXE = os.path.join(ROOT, "target", "release", "ophis")

# (subsystem, pattern) in the order they are tried on each frame, innermost frame first.
RULES = [
    ("scene load and BVH build", r"ophis::scene::build|ophis::scene::mitsuba|accel::build"),
    ("film optics (Airy sums, stacks)",
     r"ophis::optics::|\bfilm_r4\b|\bfilm_rt?\b|sincos4|filmfresnel|FilmFresnel|StackFresnel"
     r"|bsdf::filmstack"),
    ("scales texture", r"ophis::texture::scales|\bsearch_on\b"),
    ("other textures", r"ophis::texture::"),
    ("bump mapping", r"bsdf::bumpmap|\bperturbed_normal\b|\bshading_frame\b"),
    ("ray traversal (BVH, primitives)", r"ophis::accel::|\bclosest_n\b|\bany_n\b|intersect_raw"
     r"|intersect_prim|intersect_exact|intersect_watertight"),
    # The flagship's only lights are the sun and the sky: their radiance, their sampling
    # (the sky's 2-D distribution) and the choice between them.
    ("sun and sky (radiance, sampling)", r"ophis::light::|SunLight|SkyLight"),
    ("layered BSDF (random walk)", r"bsdf::layered|walk::Stack|LayeredBxdf"),
    ("microfacets and other BSDFs", r"ophis::bsdf::"),
    ("hit points (shapes, snake, litter)", r"ophis::shape::"),
    ("camera", r"ophis::camera::"),
    ("sampler and wavelengths", r"ophis::sampler::|ophis::spectrum::"),
    ("integrator (paths, wavefront, film)", r"ophis::integrator::|render_tile|ophis::film"
     r"|\bscalar_vertex\b|PathState"),
]
SKIP = re.compile(r"^(__mem|__libc|_int_|malloc|free|cfree|realloc|\[unknown\])|libc\.so|"
                  r"^(core|alloc|std)::|\(inlined\)$")


def render(args, threads, res, spp, extra=()):
    w, h = res
    cmd = [EXE, "render", f"-Dwidth={w}", f"-Dheight={h}", "--spp", str(spp),
           "--threads", str(threads), "-o", os.path.join(args.tmp, "flagship.exr"), "--quiet"]
    cmd += [f"-D{d}" for d in args.define]
    p = subprocess.run(list(extra) + cmd, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit("ophis failed:\n" + p.stderr)
    m = re.search(r"spp, ([0-9.]+) s, ([0-9.]+) CPU s, ([0-9.]+) Msamples/s", p.stderr)
    if not m:
        sys.exit("no summary line in ophis's output:\n" + p.stderr)
    return float(m.group(1)), float(m.group(2)), float(m.group(3))


def classify(frames):
    """The subsystem of one sample, from its call stack (innermost frame first)."""
    for _, pat in RULES[:1]:
        if any(re.search(pat, f) for f in frames):
            return RULES[0][0]
    for f in frames:
        for name, pat in RULES[1:]:
            if re.search(pat, f):
                return name
    return "other"


def profile(args, res, spp):
    data = os.path.join(args.tmp, "perf.data")
    rec = ["perf", "record", "-q", "-e", "cpu-clock", "-F", str(args.freq),
           "--call-graph", "dwarf,16384", "-o", data, "--"]
    render(args, 1, res, spp, rec)
    out = subprocess.run(["perf", "script", "-i", data, "-F", "ip,sym"], capture_output=True,
                         text=True, errors="replace").stdout
    counts = collections.Counter()
    for block in out.split("\n\n"):
        frames = []
        for line in block.splitlines():
            parts = line.strip().split(None, 1)
            if len(parts) == 2:
                frames.append(parts[1])
        if not frames:
            continue
        # Inlined frames keep their short names (film_r4, search_on); the innermost frame
        # that is not a library copy or a generic std adaptor decides.
        useful = [f for f in frames if not SKIP.search(f) or re.search(
            r"\b(film_r4|film_rt?|sincos4|search_on|perturbed_normal|shading_frame|closest_n|"
            r"any_n|scalar_vertex)\b", f)]
        counts[classify(useful or frames)] += 1
    return counts


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--res", default="320x180")
    ap.add_argument("--spp", type=int, default=16)
    ap.add_argument("--repeats", type=int, default=2)
    ap.add_argument("--freq", type=int, default=1000, help="perf samples per second")
    ap.add_argument("--full", action="store_true", help="also time 640x360 at 256 spp (the scene's default size, twice its default spp)")
    ap.add_argument("-D", dest="define", action="append", default=[], metavar="NAME=VALUE")
    args = ap.parse_args()
    if not os.path.exists(EXE):
        sys.exit(f"{EXE} is missing: run `cargo build --release` first")
    m = re.fullmatch(r"([1-9][0-9]*)x([1-9][0-9]*)", args.res)
    if not m:
        sys.exit(f"--res {args.res!r}: expected WIDTHxHEIGHT, e.g. 320x180")
    res = (int(m.group(1)), int(m.group(2)))
    date = time.strftime("%Y-%m-%d")
    with tempfile.TemporaryDirectory() as tmp:
        args.tmp = tmp
        speeds = [render(args, os.cpu_count() or 1, res, args.spp)[2] for _ in range(args.repeats)]
        print(f"{date}: the built-in scene at {res[0]}x{res[1]}, {args.spp} spp, "
              f"{os.cpu_count()} threads: {statistics.median(speeds):.3f} Msamples/s "
              f"({min(speeds):.3f}–{max(speeds):.3f}, {args.repeats} renders)")
        if args.full:
            wall, cpu, msps = render(args, os.cpu_count() or 1, (640, 360), 256)
            print(f"  at 640x360, 256 spp (default size, twice the default spp): {wall:.1f} s, "
                  f"{cpu:.1f} CPU s, "
                  f"{msps:.3f} Msamples/s")
        if not shutil.which("perf"):
            print("perf is not installed (Debian: apt-get install linux-perf): no profile")
            return
        _, cpu, msps = render(args, 1, res, args.spp)
        counts = profile(args, res, args.spp)
        setup = counts.pop(RULES[0][0], 0)
        total = sum(counts.values())
        ns_per_sample = cpu / (res[0] * res[1] * args.spp) * 1e9
        print(f"\none thread: {msps:.3f} Msamples/s, {ns_per_sample:.0f} ns of CPU per sample; "
              f"profile of the render: {total} samples of the call stack (and {setup} in "
              "scene loading and the BVH build)")
        print(f"  {'subsystem':<46} {'share':>7} {'ns/sample':>10}")
        for name, n in counts.most_common():
            print(f"  {name:<46} {100 * n / total:6.1f}% {ns_per_sample * n / total:10.0f}")

if __name__ == "__main__":
    main()
