#!/usr/bin/env python3
"""End-to-end benchmark: ophis vs Mitsuba 3 on the same XML scenes, side by side in one run.

Renders scenes/cornell-box.xml (diffuse, glass and rough-gold spheres) and scenes/cornell-mesh.xml
(the same room with a ~1M-triangle mesh) with ophis, and — where `import mitsuba` works — with
Mitsuba 3's `llvm_ad_spectral` and `scalar_spectral` variants, at the same resolution, samples per
pixel and path depth, interleaved, `--repeats` times. Prints, per scene and renderer, the median
and the range (min–max) over the repeats of:

- render: the render alone. ophis: its summary line (after parsing and BVH build). Mitsuba: the
  `mi.render` call, run twice in one process with the second one timed, so that LLVM's JIT
  compilation is excluded.
- process: the whole process, parse + BVH build + render + write (Mitsuba: a fresh Python that
  imports mitsuba, loads, renders once, JIT included, and writes the EXR).
- render CPU s: the CPU time of all the process's threads over the render (ophis: its summary
  line; Mitsuba: getrusage around the timed `mi.render`). On a shared machine the wall time
  depends on what else runs; the CPU time much less, so it measures the work done.
- Msamples/s from the render time, and ophis ÷ Mitsuba per repeat (> 1: ophis is faster), for
  render, render CPU and process times.

and each image's mean linear-sRGB colour so that a mismatch between the scenes shows; then where
ophis's render time went (`ophis render --stats`: each wavefront stage's share of the threads'
time, rays per sample, time per traced ray), medians over the repeats.

usage: python3 bench/run.py [--spp 64] [--res 256] [--repeats 3] [--no-build] [--no-mitsuba]
                            [--scenes cornell-box,cornell-mesh] [--variants llvm_ad_spectral,...]
Mitsuba's llvm variants need Debian's libllvm19 (apt-get install libllvm19).
"""
import argparse
import os
import re
import statistics
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = os.path.join(ROOT, "target", "bench")

# Run in a fresh interpreter: one whole Mitsuba process (import, load, render, write).
MITSUBA_PROCESS = r"""
import sys, json
import mitsuba as mi
variant, scene, out = sys.argv[1], sys.argv[2], sys.argv[3]
params = json.loads(sys.argv[4])
mi.set_variant(variant)
sc = mi.load_file(scene, **params)
img = mi.render(sc, spp=params["spp"], seed=0)
mi.Bitmap(img).write(out)
"""


def ophis_render(scene, spp, res, defines, out):
    exe = os.path.join(ROOT, "target", "release", "ophis")
    cmd = [exe, "render", scene, "-Dspp=%d" % spp, "-Dres=%d" % res, "-o", out, "--quiet",
           "--stats"]
    cmd += ["-D%s=%s" % kv for kv in defines.items()]
    t0 = time.time()
    p = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.time() - t0
    if p.returncode != 0:
        sys.exit("ophis failed:\n" + p.stderr)
    m = re.search(r"spp, ([0-9.]+) s,", p.stderr)
    secs = float(m.group(1)) if m else wall
    c = re.search(r" s, ([0-9.]+|NaN) CPU s,", p.stderr)
    cpu = float(c.group(1)) if c else float("nan")
    STAGES.append(parse_stages(p.stderr))
    return secs, cpu, wall


# The `--stats` report of every ophis render of the current scene.
STAGES = []


def parse_stages(stderr):
    """The stage shares (%) and per-sample ray counts of `ophis render --stats`, or None."""
    line = next((l for l in stderr.splitlines() if l.startswith("stats: wavefront stages")), None)
    rays = re.search(r"per sample ([0-9.]+) rays and ([0-9.]+) shadow rays; ([0-9.]+) ns per "
                     r"traced ray", stderr)
    if line is None or rays is None:
        return None
    listed = re.findall(r"([a-z ]+) ([0-9.]+) %", line.split(": ", 2)[2])
    shares = {k.strip(): float(v) for k, v in listed}
    return shares, tuple(float(x) for x in rays.groups())


def mean_rgb_exr(path):
    try:
        import mitsuba as mi  # noqa: F401  (Bitmap reads EXR)
        import numpy as np
        b = np.array(mi.Bitmap(path))
        return b[..., :3].reshape(-1, 3).mean(axis=0)
    except Exception:
        return None


def mitsuba_render(variant, scene, spp, res, defines, out):
    """Render time of a warm second render (JIT excluded) in this process, and the mean."""
    import mitsuba as mi
    import numpy as np
    mi.set_variant(variant)
    params = dict(spp=spp, res=res, **defines)
    sc = mi.load_file(scene, **params)
    img = mi.render(sc, spp=spp, seed=0)
    np.array(img)
    t0, c0 = time.time(), cpu_seconds()
    img = mi.render(sc, spp=spp, seed=1)
    arr = np.array(img)
    secs, cpu = time.time() - t0, cpu_seconds() - c0
    mi.Bitmap(img).write(out)
    return secs, cpu, arr[..., :3].reshape(-1, 3).mean(axis=0)


def cpu_seconds():
    """CPU seconds of this process so far, all threads (user + system)."""
    import resource
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


def mitsuba_process(variant, scene, spp, res, defines, out):
    import json
    params = dict(spp=spp, res=res, **defines)
    t0 = time.time()
    p = subprocess.run([sys.executable, "-c", MITSUBA_PROCESS, variant, scene, out, json.dumps(params)],
                       capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError(p.stderr.strip().splitlines()[-1] if p.stderr.strip() else "failed")
    return time.time() - t0


def spread(xs, fmt="{:.2f}"):
    """median (min–max) of a list."""
    if not xs:
        return "-"
    med = statistics.median(xs)
    if len(xs) == 1:
        return fmt.format(med)
    return (fmt + " ({}–{})").format(med, fmt.format(min(xs)), fmt.format(max(xs)))


def main():
    ap = argparse.ArgumentParser(description="ophis vs Mitsuba 3 benchmark")
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--res", type=int, default=256)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--scenes", default="cornell-box,cornell-mesh")
    ap.add_argument("--variants", default="llvm_ad_spectral,scalar_spectral")
    ap.add_argument("--no-build", action="store_true")
    ap.add_argument("--no-mitsuba", action="store_true")
    a = ap.parse_args()
    os.makedirs(OUT, exist_ok=True)
    if not a.no_build:
        subprocess.run(["cargo", "build", "--release", "--quiet"], cwd=ROOT, check=True)
    mesh = os.path.join(OUT, "blob.ply")
    if not os.path.exists(mesh):
        subprocess.run([sys.executable, os.path.join(ROOT, "bench", "make_mesh.py"), mesh], check=True)

    variants = []
    if not a.no_mitsuba:
        try:
            import mitsuba  # noqa: F401
            variants = [v for v in a.variants.split(",") if v]
        except ImportError:
            print("(mitsuba not installed: pip install mitsuba — ophis only)")

    samples = a.res * a.res * a.spp
    simd = "AVX-512" if "avx512f" in open("/proc/cpuinfo").read() else "AVX2 or less"
    print(f"{time.strftime('%Y-%m-%d')}: resolution {a.res}x{a.res}, {a.spp} spp, {samples} samples per "
          f"image, {os.cpu_count()} cores ({simd}), {a.repeats} repeats: median (min–max)")
    scenes = {"cornell-box": {}, "cornell-mesh": {"mesh": mesh}}
    for name in a.scenes.split(","):
        defines = scenes[name]
        scene = os.path.join(ROOT, "scenes", name + ".xml")
        rows = {"ophis": {"render": [], "cpu": [], "process": []}}
        for v in variants:
            rows[v] = {"render": [], "cpu": [], "process": []}
        means = {}
        failed = {}
        STAGES.clear()
        for _ in range(a.repeats):
            out = os.path.join(OUT, f"{name}-ophis.exr")
            secs, cpu, wall = ophis_render(scene, a.spp, a.res, defines, out)
            rows["ophis"]["render"].append(secs)
            rows["ophis"]["cpu"].append(cpu)
            rows["ophis"]["process"].append(wall)
            means["ophis"] = mean_rgb_exr(out)
            for v in variants:
                if v in failed:
                    continue
                out = os.path.join(OUT, f"{name}-{v}.exr")
                try:
                    secs, cpu, means[v] = mitsuba_render(v, scene, a.spp, a.res, defines, out)
                    proc = mitsuba_process(v, scene, a.spp, a.res, defines, out)
                except Exception as e:  # e.g. libLLVM missing
                    failed[v] = str(e).splitlines()[0][:80]
                    continue
                rows[v]["render"].append(secs)
                rows[v]["cpu"].append(cpu)
                rows[v]["process"].append(proc)
        print(f"\n{name}")
        print(f"  {'renderer':<24} {'render s':>18} {'Msamples/s':>20} {'render CPU s':>20} "
              f"{'process s':>18} {'ophis × (render)':>20} {'ophis × (CPU)':>20} "
              f"{'ophis × (process)':>20}  mean linear sRGB")
        o = rows["ophis"]
        for r, t in rows.items():
            if r in failed:
                print(f"  {'mitsuba ' + r:<24} failed: {failed[r]}")
                continue
            sps = [samples / s / 1e6 for s in t["render"]]
            label = r if r == "ophis" else "mitsuba " + r
            ratio_r = ratio_c = ratio_p = ""
            if r != "ophis":
                ratio_r = spread([m / x for x, m in zip(o["render"], t["render"])])
                ratio_c = spread([m / x for x, m in zip(o["cpu"], t["cpu"])])
                ratio_p = spread([m / x for x, m in zip(o["process"], t["process"])])
            m = means.get(r)
            ms = "" if m is None else "(%.4f, %.4f, %.4f)" % tuple(m)
            print(f"  {label:<24} {spread(t['render']):>18} {spread(sps, '{:.3f}'):>20} "
                  f"{spread(t['cpu']):>20} {spread(t['process']):>18} {ratio_r:>20} "
                  f"{ratio_c:>20} {ratio_p:>20}  {ms}")
        st = [x for x in STAGES if x is not None]
        if st:
            names = list(st[0][0])
            shares = ", ".join(f"{k} {statistics.median(x[0].get(k, 0.0) for x in st):.1f} %"
                               for k in names)
            rays, shadows, ns = (statistics.median(x[1][i] for x in st) for i in range(3))
            print(f"  ophis's time by stage (median of {len(st)}): {shares}; per sample {rays:.2f} "
                  f"rays and {shadows:.2f} shadow rays, {ns:.0f} ns per traced ray")


if __name__ == "__main__":
    main()
