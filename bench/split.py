#!/usr/bin/env python3
"""Where each renderer's render time goes, side by side: ray traversal against everything else.

`bench/run.py` compares whole renders and `bench/rays.py` the accelerators alone, one batch of
rays at a time; neither says how much of Mitsuba's render its traversal takes inside the render,
where Mitsuba's wavefront hands Embree rays in packets of 16 lanes that belong to one pixel's
samples. This script measures, for one scene (256², 64 spp by default), in one run:

1. ophis: `ophis render --stats --threads 1`, the stage shares: traversal (the trace and shadow
   stages) and the rest, and the render's CPU seconds.
2. Mitsuba (`--variant`, default `llvm_ad_spectral`), one Dr.Jit thread: the CPU seconds of a
   warm render (JIT compiled and cached by a first one), and of the same samples rendered as
   `--spp` passes of one sample each, whose lanes are then neighbouring pixels rather than one
   pixel's samples: how much the pixel-coherent packets are worth to it (the passes also pay
   a launch each, so this is an upper bound).
3. Where `perf` works (Linux, `perf record` allowed): a sampling profile of Mitsuba's process
   over three warm renders, its samples split into Embree's traversal (`BVHNIntersector*`),
   Embree's build, the JIT-compiled kernels and the rest; the traversal's and the kernels'
   CPU seconds estimated from their shares of the render's samples.

Both renderers run on one thread, so that CPU seconds compare directly.

usage: python3 bench/split.py [--scene cornell-mesh|cornell-box] [--spp 64] [--res 256]
                              [--variant llvm_ad_spectral] [--no-perf]
Needs pip install mitsuba (the llvm variants need Debian's libllvm19).
"""
import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MESH = os.path.join(ROOT, "target", "bench", "blob.ply")

# Run in a fresh interpreter: prints "render CPU_S" for a warm render and "passes CPU_S" for the
# same samples in one-sample passes, or with "profile" renders three times for perf.
MITSUBA = r"""
import json, resource, sys
import drjit as dr
import mitsuba as mi
variant, scene, mode = sys.argv[1], sys.argv[2], sys.argv[3]
params = json.loads(sys.argv[4])
mi.set_variant(variant)
dr.set_thread_count(1)
sc = mi.load_file(scene, **params)
spp = params["spp"]
def cpu():
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime
dr.eval(mi.render(sc, spp=spp, seed=0))
if mode == "profile":
    for s in range(3):
        dr.eval(mi.render(sc, spp=spp, seed=1 + s))
    sys.exit(0)
c = cpu()
dr.eval(mi.render(sc, spp=spp, seed=1))
print("render %.4f" % (cpu() - c))
dr.eval(mi.render(sc, spp=1, seed=1000))
c = cpu()
for s in range(spp):
    dr.eval(mi.render(sc, spp=1, seed=2000 + s))
print("passes %.4f" % (cpu() - c))
"""


def ophis(scene, spp, res, defines):
    exe = os.path.join(ROOT, "target", "release", "ophis")
    out = os.path.join(tempfile.gettempdir(), "ophis-split.exr")
    cmd = [exe, "render", scene, "--threads", "1", "-Dspp=%d" % spp, "-Dres=%d" % res, "-o", out,
           "--quiet", "--stats"] + ["-D%s=%s" % kv for kv in defines.items()]
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit("ophis failed:\n" + p.stderr)
    cpu = float(re.search(r" s, ([0-9.]+) CPU s,", p.stderr).group(1))
    line = next(l for l in p.stderr.splitlines() if l.startswith("stats: wavefront stages"))
    pairs = re.findall(r"([a-z ]+) ([0-9.]+) %", line.split(": ", 2)[2])
    shares = {k.strip(): float(v) for k, v in pairs}
    return cpu, shares


def mitsuba(variant, scene, mode, params, prefix=()):
    import json
    cmd = list(prefix) + [sys.executable, "-c", MITSUBA, variant, scene, mode,
                          json.dumps(params)]
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError((p.stderr.strip().splitlines() or ["failed"])[-1])
    found = re.findall(r"^(render|passes) ([0-9.]+)$", p.stdout, re.M)
    return dict((k, float(v)) for k, v in found)


def classify(sym, dso):
    if "BVHNIntersector" in sym or "intersect16" in sym or "occluded16" in sym:
        return "embree traversal"
    if "embree" in dso:
        return "embree build and other"
    if dso.startswith("[JIT]"):
        return "JIT kernels"
    return "other (Python, loading, kernel)"


def profile(variant, scene, params):
    """Shares of perf samples of a Mitsuba process over three warm renders, by class."""
    if shutil.which("perf") is None:
        return None
    data = os.path.join(tempfile.gettempdir(), "ophis-split.perf")
    try:
        mitsuba(variant, scene, "profile", params,
                ["perf", "record", "-q", "-F", "1000", "-o", data, "--"])
    except RuntimeError as e:
        print("  (perf record failed: %s)" % e)
        return None
    p = subprocess.run(["perf", "report", "-i", data, "--no-children", "--stdio",
                        "--sort", "dso,sym", "--percent-limit", "0"],
                       capture_output=True, text=True)
    shares = {}
    for line in p.stdout.splitlines():
        m = re.match(r"\s*([0-9.]+)%\s+(\S.*?)\s{2,}\[.\]\s+(.*)$", line)
        if m:
            k = classify(m.group(3), m.group(2))
            shares[k] = shares.get(k, 0.0) + float(m.group(1))
    return shares


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scene", default="cornell-mesh", choices=["cornell-mesh", "cornell-box"])
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--res", type=int, default=256)
    ap.add_argument("--variant", default="llvm_ad_spectral")
    ap.add_argument("--no-perf", action="store_true")
    a = ap.parse_args()
    scene = os.path.join(ROOT, "scenes", a.scene + ".xml")
    defines = {"mesh": MESH} if a.scene == "cornell-mesh" else {}
    if defines and not os.path.exists(MESH):
        subprocess.run([sys.executable, os.path.join(ROOT, "bench", "make_mesh.py"), MESH],
                       check=True)
    params = dict(spp=a.spp, res=a.res, **defines)
    print("%s, %d² at %d spp, one thread each:" % (a.scene, a.res, a.spp))

    cpu, st = ophis(scene, a.spp, a.res, defines)
    trav = st.get("trace", 0.0) + st.get("shadow rays", 0.0)
    print("  ophis: render %.2f CPU s; traversal (trace and shadow stages) %.1f %% = %.2f s, "
          "the rest %.2f s" % (cpu, trav, cpu * trav / 100, cpu * (1 - trav / 100)))

    try:
        t = mitsuba(a.variant, scene, "times", params)
    except RuntimeError as e:
        sys.exit("  mitsuba %s: %s" % (a.variant, e))
    print("  mitsuba %s: render %.2f CPU s; as %d one-sample passes %.2f s (%.2fx)"
          % (a.variant, t["render"], a.spp, t["passes"], t["passes"] / t["render"]))

    shares = None if a.no_perf else profile(a.variant, scene, params)
    if shares:
        order = ["embree traversal", "JIT kernels", "embree build and other",
                 "other (Python, loading, kernel)"]
        print("  mitsuba's perf samples over three warm renders and its load: " +
              ", ".join("%s %.1f %%" % (k, shares.get(k, 0.0)) for k in order))
        render = shares.get("embree traversal", 0.0) + shares.get("JIT kernels", 0.0)
        if render > 0:
            tr = shares.get("embree traversal", 0.0) / render
            print("  of the render's samples (traversal and kernels): traversal %.1f %% = %.2f s,"
                  " kernels %.2f s" % (100 * tr, t["render"] * tr, t["render"] * (1 - tr)))
            print("  ophis ÷ mitsuba, CPU time: traversal %.2fx, the rest %.2fx, whole %.2fx"
                  % ((t["render"] * tr) / (cpu * trav / 100),
                     (t["render"] * (1 - tr)) / (cpu * (1 - trav / 100)), t["render"] / cpu))


if __name__ == "__main__":
    main()
