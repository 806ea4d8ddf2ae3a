#!/usr/bin/env python3
"""Ray throughput of ophis's BVH against Mitsuba 3's (Embree's, in the `llvm_*` variants) on the
same scene, one thread each: how much of a mesh scene's render gap is the accelerator.

Both trace, through `scenes/cornell-mesh.xml` (the Cornell room around the 1M-triangle
`target/bench/blob.ply`; `python3 bench/make_mesh.py target/bench/blob.ply` writes it):

- camera: one ray through the centre of each pixel of a `--side`² grid, through the scene's camera;
- bounce: from each camera hit, a ray in a cosine-distributed direction about the normal
  (incoherent);
- shadow: from each camera hit, a ray to a uniform point in the scene's bounds (any hit).

ophis: `examples/bench_accel.rs --scene` (its "in batches" rows: 1024 rays per call, as the
wavefront integrator traces them; the best of `--repeat` CPU times of the thread). Mitsuba:
`Scene.ray_intersect_preliminary` / `ray_test` on the whole wavefront with one Dr.Jit thread, the
best of `--repeat` CPU times after a warm-up call (JIT compilation excluded). The rays are drawn
independently by each program from the same distributions, not bit for bit the same rays.

The two are timed in turn, `--rounds` times (absolute speeds on a shared machine drift by up to
2× within minutes); the ratio of each round's pair is printed as the median and range.

`--scene cornell-box` traces the same rays through the room with three spheres instead.

usage: python3 bench/rays.py [--side 512] [--repeat 3] [--rounds 3] [--variant llvm_ad_rgb]
                             [--scene cornell-mesh|cornell-box]
"""
import argparse
import os
import re
import statistics
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENES = {"cornell-mesh": "cornell-mesh (1M triangles)",
          "cornell-box": "cornell-box (12 triangles, 3 spheres)"}
MESH = os.path.join(ROOT, "target", "bench", "blob.ply")


def mitsuba_setup(scene, variant, side):
    """The scene and its rays, loaded once; returns a function that times them."""
    import drjit as dr
    import mitsuba as mi
    mi.set_variant(variant)
    dr.set_thread_count(1)
    extra = {"mesh": MESH} if "mesh" in scene else {}
    sc = mi.load_file(scene, res=side, spp=1, **extra)
    n = side * side
    idx = dr.arange(mi.UInt32, n)
    x, y = mi.Float(idx % side) + 0.5, mi.Float(idx // side) + 0.5
    ray, _ = sc.sensors()[0].sample_ray(0.0, 0.5, mi.Point2f(x / side, y / side), mi.Point2f(0.5, 0.5))

    def best(f, repeat):
        r = f()
        dr.eval(r)
        dr.sync_thread()
        t_min = float("inf")
        for _ in range(repeat):
            t = time.process_time()
            r = f()
            dr.eval(r)
            dr.sync_thread()
            t_min = min(t_min, time.process_time() - t)
        return t_min, r

    si = sc.ray_intersect(ray)
    valid = si.is_valid()
    hits = dr.count(valid)[0]
    rng = mi.PCG32(size=n)
    d = mi.warp.square_to_cosine_hemisphere(mi.Point2f(rng.next_float32(), rng.next_float32()))
    bounce = si.spawn_ray(si.to_world(d))
    bb = sc.bbox()
    u = mi.Vector3f(rng.next_float32(), rng.next_float32(), rng.next_float32())
    target = bb.min + (bb.max - bb.min) * u
    shadow = si.spawn_ray_to(target)

    def measure(repeat):
        t_cam, _ = best(lambda: sc.ray_intersect_preliminary(ray), repeat)
        t_bounce, _ = best(lambda: sc.ray_intersect_preliminary(bounce, active=valid), repeat)
        t_shadow, _ = best(lambda: sc.ray_test(shadow, active=valid), repeat)
        return {"camera": n / t_cam / 1e6, "bounce": hits / t_bounce / 1e6,
                "shadow": hits / t_shadow / 1e6}
    return measure


def ophis(scene, side, repeat):
    exe = os.path.join(ROOT, "target", "release", "examples", "bench_accel")
    if not os.path.exists(exe):
        subprocess.run(["cargo", "build", "--release", "--quiet", "--example", "bench_accel"],
                       cwd=ROOT, check=True)
    p = subprocess.run([exe, "--scene", scene, "-D", f"mesh={MESH}", "--side", str(side),
                        "--repeat", str(repeat)], capture_output=True, text=True, cwd=ROOT)
    if p.returncode != 0:
        sys.exit("bench_accel failed:\n" + p.stderr)
    out = {}
    for line in p.stdout.splitlines():
        m = re.match(r"\s+(camera|bounce|shadow)\s+\d+ in batches\s+(.*)", line)
        if m:
            rates = [float(v) for v in re.findall(r"(\d+\.\d+) \(", m.group(2))]
            out[m.group(1)] = max(rates)  # the widest instruction set this CPU runs
    return out


def main():
    ap = argparse.ArgumentParser(description="ophis vs Mitsuba/Embree ray throughput")
    ap.add_argument("--side", type=int, default=512)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--variant", default="llvm_ad_rgb")
    ap.add_argument("--scene", default="cornell-mesh", choices=sorted(SCENES))
    a = ap.parse_args()
    scene = os.path.join(ROOT, "scenes", a.scene + ".xml")
    if not os.path.exists(MESH):
        subprocess.run([sys.executable, os.path.join(ROOT, "bench", "make_mesh.py"), MESH], check=True)
    measure = mitsuba_setup(scene, a.variant, a.side)
    kinds = ("camera", "bounce", "shadow")
    rounds = []
    for _ in range(a.rounds):
        rounds.append((ophis(scene, a.side, a.repeat), measure(a.repeat)))
    print(f"{time.strftime('%Y-%m-%d')}: {SCENES[a.scene]}, {a.side}² camera rays, one "
          f"thread, Mrays/s of CPU time (best of {a.repeat}), {a.rounds} rounds: median (min–max)")
    print(f"  {'rays':<8} {'ophis':>20} {'mitsuba ' + a.variant:>24} {'ophis ÷ mitsuba':>20}")

    def spread(xs):
        xs = sorted(xs)
        return f"{statistics.median(xs):.2f} ({xs[0]:.2f}–{xs[-1]:.2f})"
    for k in kinds:
        o = [r[0][k] for r in rounds]
        m = [r[1][k] for r in rounds]
        q = [r[0][k] / r[1][k] for r in rounds]
        print(f"  {k:<8} {spread(o):>20} {spread(m):>24} {spread(q):>20}")


if __name__ == "__main__":
    main()
