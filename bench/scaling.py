#!/usr/bin/env python3
"""Scaling benchmark: threads, mesh size, BVH build and PLY load, peak memory (ophis vs Mitsuba 3).

Prints, each as median (min–max) over `--repeats`:

1. Threads: render time of scenes/cornell-box.xml (at --thread-res, 256² by default) on 1 and
   on 2 threads, and the speed-up (per repeat, the two runs back to back).
2. Mesh size: scenes/cornell-mesh.xml with a lumpy blob of 10k, 1M and 4M triangles
   (bench/make_mesh.py, cached in target/bench/): render time and Msamples/s; with a BVH the time
   should grow like log n, so from 10k to 4M (×400) by a small factor only.
3. BVH build and PLY load of the 1M mesh on all threads, and the build on one thread
   (`cargo run --release --example bench_accel`).
4. Peak memory (peak resident set of the whole process: parse, build, render, write) for each
   mesh, and per triangle from the growth between the 10k and the 4M mesh, side by side with
   Mitsuba's `scalar_spectral` and `llvm_ad_spectral` on the same scenes where `import mitsuba`
   works.

usage: python3 bench/scaling.py [--res 128] [--spp 16] [--repeats 3] [--no-build] [--no-mitsuba]
"""
import argparse
import json
import os
import re
import resource
import statistics
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = os.path.join(ROOT, "target", "bench")
OPHIS = os.path.join(ROOT, "target", "release", "ophis")
SIZES = [("10k", 10_000), ("1M", 1_000_000), ("4M", 4_000_000)]

# A child that runs a command and prints its peak resident set in KiB (its only child's).
PEAK = r"""
import resource, subprocess, sys
r = subprocess.run(sys.argv[1:], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
if r.returncode != 0:
    sys.stderr.write(r.stderr)
    sys.exit(r.returncode)
sys.stderr.write(r.stderr)
print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)
"""

MITSUBA = r"""
import sys, json
import mitsuba as mi
variant, scene, out = sys.argv[1], sys.argv[2], sys.argv[3]
params = json.loads(sys.argv[4])
mi.set_variant(variant)
sc = mi.load_file(scene, **params)
img = mi.render(sc, spp=params["spp"], seed=0)
mi.Bitmap(img).write(out)
"""


def spread(xs, fmt="{:.2f}"):
    if not xs:
        return "-"
    med = statistics.median(xs)
    if len(xs) == 1:
        return fmt.format(med)
    return (fmt + " ({}–{})").format(med, fmt.format(min(xs)), fmt.format(max(xs)))


def peak_run(cmd):
    """(peak RSS in MB, wall seconds, stderr) of one process."""
    t0 = time.time()
    p = subprocess.run([sys.executable, "-c", PEAK] + cmd, capture_output=True, text=True)
    wall = time.time() - t0
    if p.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd[:3])}… failed: {p.stderr.strip()[-300:]}")
    return int(p.stdout.split()[-1]) / 1024.0, wall, p.stderr


def ophis(scene, res, spp, defines, threads=None):
    """(render seconds, peak MB, process seconds)."""
    cmd = [OPHIS, "render", scene, f"-Dres={res}", f"-Dspp={spp}", "--quiet",
           "-o", os.path.join(OUT, "scaling.exr")]
    cmd += [f"-D{k}={v}" for k, v in defines.items()]
    if threads:
        cmd += ["--threads", str(threads)]
    peak, wall, err = peak_run(cmd)
    m = re.search(r"spp, ([0-9.]+) s,", err)
    return (float(m.group(1)) if m else wall), peak, wall


def mesh_file(label, n):
    path = os.path.join(OUT, "blob.ply" if n == 1_000_000 else f"blob-{label}.ply")
    if not os.path.exists(path):
        subprocess.run([sys.executable, os.path.join(ROOT, "bench", "make_mesh.py"), path,
                        "--triangles", str(n)], check=True)
    return path


def main():
    ap = argparse.ArgumentParser(description="ophis scaling benchmark")
    ap.add_argument("--res", type=int, default=128)
    ap.add_argument("--spp", type=int, default=16)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--thread-res", type=int, default=256,
                    help="resolution of the threads test (at 128² its 16 tiles leave a thread idle)")
    ap.add_argument("--no-build", action="store_true")
    ap.add_argument("--no-mitsuba", action="store_true")
    a = ap.parse_args()
    os.makedirs(OUT, exist_ok=True)
    if not a.no_build:
        subprocess.run(["cargo", "build", "--release", "--quiet", "--bin", "ophis",
                        "--example", "bench_accel"], cwd=ROOT, check=True)
    variants = []
    if not a.no_mitsuba:
        try:
            import mitsuba  # noqa: F401
            variants = ["scalar_spectral", "llvm_ad_spectral"]
        except ImportError:
            print("(mitsuba not installed: pip install mitsuba — ophis only)")
    simd = "AVX-512" if "avx512f" in open("/proc/cpuinfo").read() else "AVX2 or less"
    print(f"{time.strftime('%Y-%m-%d')}: {a.res}x{a.res}, {a.spp} spp, {os.cpu_count()} cores ({simd}), "
          f"{a.repeats} repeats: median (min–max)")
    samples = a.res * a.res * a.spp

    # 1. Threads.
    box = os.path.join(ROOT, "scenes", "cornell-box.xml")
    t1, t2, sp = [], [], []
    for _ in range(a.repeats):
        x = ophis(box, a.thread_res, 2 * a.spp, {}, threads=1)[0]
        y = ophis(box, a.thread_res, 2 * a.spp, {}, threads=2)[0]
        t1.append(x)
        t2.append(y)
        sp.append(x / y)
    print(f"\n1. threads (cornell-box, {a.thread_res}², {2 * a.spp} spp): 1 thread {spread(t1)} s, 2 threads {spread(t2)} s, "
          f"speed-up {spread(sp)}×")

    # 2 and 4. Mesh size and memory.
    scene = os.path.join(ROOT, "scenes", "cornell-mesh.xml")
    print(f"\n2. mesh size (cornell-mesh) and 4. peak memory of the whole process")
    print(f"  {'triangles':>9} {'ophis render s':>20} {'Msamples/s':>20} {'ophis peak MB':>14}"
          + "".join(f" {v + ' MB':>22}" for v in variants))
    peaks = {}
    for label, n in SIZES:
        mesh = mesh_file(label, n)
        rs, pk = [], []
        for _ in range(a.repeats):
            r, p, _ = ophis(scene, a.res, a.spp, {"mesh": mesh})
            rs.append(r)
            pk.append(p)
        peaks.setdefault("ophis", []).append(min(pk))
        row = (f"  {label:>9} {spread(rs):>20} {spread([samples / max(r, 1e-3) / 1e6 for r in rs], '{:.3f}'):>20} "
               f"{min(pk):14.0f}")
        for v in variants:
            params = json.dumps(dict(res=a.res, spp=a.spp, mesh=mesh))
            try:
                p, _, _ = peak_run([sys.executable, "-c", MITSUBA, v, scene,
                                    os.path.join(OUT, "scaling-mi.exr"), params])
                peaks.setdefault(v, []).append(p)
                row += f" {p:22.0f}"
            except RuntimeError as e:
                row += f" {'failed':>22}"
                print(e, file=sys.stderr)
        print(row, flush=True)
    dn = SIZES[-1][1] - SIZES[0][1]
    print("  bytes per triangle (peak growth from 10k to 4M): "
          + ", ".join(f"{k} {(v[-1] - v[0]) * 1024 * 1024 / dn:.0f}" for k, v in peaks.items()
                      if len(v) == len(SIZES)))

    # 3. BVH build and PLY load.
    exe = os.path.join(ROOT, "target", "release", "examples", "bench_accel")
    p = subprocess.run([exe, mesh_file("1M", 1_000_000), "--side", "32", "--repeat", str(a.repeats)],
                       capture_output=True, text=True, cwd=ROOT)
    load = re.search(r"PLY read ([0-9.]+) ms, mesh ([0-9.]+) ms", p.stdout)
    build = re.search(r"BVH build ([0-9.]+) ms on 1 thread, ([0-9.]+) ms on (\d+) \(([0-9.]+)x\)", p.stdout)
    print("\n3. 1M-triangle mesh (best of the repeats):")
    if load and build:
        print(f"  PLY load {load.group(1)} ms + mesh setup {load.group(2)} ms; BVH build {build.group(2)} ms "
              f"on {build.group(3)} threads, {build.group(1)} ms on 1 ({build.group(4)}×)")
    else:
        print("  bench_accel printed no timings:\n" + p.stdout + p.stderr)


if __name__ == "__main__":
    main()
