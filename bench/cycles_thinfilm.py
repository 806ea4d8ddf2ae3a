#!/usr/bin/env python3
"""ophis vs Blender Cycles on a thin-film sphere, at equal error, in one run.

The scene (bench/thinfilm-sphere.xml for ophis; built here with bpy for Cycles): a unit sphere
seen from (0, 0, 5) with a 30° horizontal field of view, a film of index 1.56 and 500 nm on a
dielectric of index 1.5 with GGX roughness α = 0.05, over a dark diffuse base (albedo 0.02),
under a uniform grey sky (radiance 0.8) and a sun (irradiance 2 W/m², travelling along
(1, −1, −1)); box pixel filter, path depth 12.

Each renderer gets a converged reference of its own image (--ref-spp), then renders at
increasing sample counts, each one a separate process, timed, and compared with its reference:

    relMSE = mean over pixels and RGB channels of (x − ref)² / (ref² + ε),  ε = 1e-2 (--eps)

(also printed with ε = 1e-3, which weighs the dark sphere more), divided by 1 + n/N at n spp
against an N-spp reference, which removes the reference's own noise (E|x − ref|² = Var x +
Var ref). The time each needs to reach a
common target relMSE is interpolated on log-log axes between the measured points, per repeat,
at two targets inside both ranges (the middle of the overlap and its low end); the ratio is
Cycles' time over ophis's (> 1: ophis is faster). Timings: "render" is the
renderer's own render time (ophis: its summary line, after parsing; Cycles: the
bpy.ops.render.render call, which includes its scene sync and BVH build), "process" the whole
process from start to exit (bpy's import is about 1–3 s of it), "cpu" the process's user+system
CPU time, which a loaded machine disturbs less than wall-clock time. Both renderers run on the
CPU with the same number of threads, interleaved, in the same run.

ophis runs in several configurations (--ophis sampler:top[:rough_coat],...), each timed
against the same Cycles runs: its two samplers (`independent`; `stratified`, which like
`ldsampler` and `sobol` is Owen-scrambled Sobol in ophis) and three coats: the scene's
`roughthinfilm` (α = 0.05, the same material as Cycles') layered exactly by a random walk
(`walk`; `mixture`: the same walk, its directions sampled from a mixture of the coat's
reflection lobe and a cosine lobe and weighed by the walk's BSDF value, one reference for both)
or in closed form by the plastic approximation (`plastic`: microfacet reflection plus
a diffuse part through the smooth coat's transmittance, the kind of model Cycles' Principled
BSDF is; `multilayered`'s `rough_coat`), and the smooth `thinfilm` (α = 0: a slightly different
material, for which the layered stack has an exact closed form). ophis's references are
rendered with the Sobol sampler, one per coat.

How the two models differ (each is compared only with itself):
- Cycles renders RGB; ophis renders four hero wavelengths per path (360–830 nm) and converts to
  XYZ and linear sRGB, so ophis also carries colour noise from the wavelength choice.
- Film: ophis evaluates the exact Airy reflectance per wavelength on every microfacet; Cycles'
  Principled thin film evaluates the interference in a spectrally integrated RGB form.
- Layering: ophis's `multilayered` simulates the coat over the base by a random walk (all
  inter-reflections, a stochastic BSDF value) or, with `rough_coat` = `plastic`, sums a
  microfacet lobe and a Fresnel-weighted diffuse lobe in closed form; Cycles' Principled BSDF
  mixes its specular and diffuse lobes with albedo scaling. The converged images differ by ~10 %
  in the sphere's mean.
- Roughness: Cycles squares its Roughness input (α = r²), so Roughness = √0.05 ≈ 0.224 here;
  Cycles' distribution is set to GGX (its default, multiscatter GGX, adds energy ophis's
  single-scattering GGX lacks, negligible at α = 0.05).
- Geometry: ophis intersects an analytic sphere; Cycles gets an exact sphere too, as a one-point
  point cloud (a geometry-nodes Mesh to Points of radius 1).
- Sun: a delta light in both (ophis `directional`, Cycles Sun lamp with angle 0).
- Cycles settings that would bias the comparison are off: adaptive sampling, denoising, light
  clamping, Filter Glossy, the light threshold. Its sampling pattern is its default.

usage: python3 bench/cycles_thinfilm.py [--res 96] [--ref-spp 4096] [--spp 4,8,...,256]
                                        [--repeats 2] [--threads 2] [--no-build]
                                        [--ophis stratified:roughthinfilm:plastic,...] [--no-cycles]
                                        [--sun 2] [--base 0.02] [--film-nm 500]
(--sun, --base and --film-nm change the scene for both renderers: `--sun 0 --base 0 --film-nm 0`
leaves a bare rough dielectric under the grey sky, to compare the glossy lobes alone.)
Needs `pip install bpy` (Blender 5.0's Cycles) and numpy.
"""
import argparse
import math
import os
import re
import resource
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = os.path.join(ROOT, "target", "bench", "thinfilm")
SCENE = os.path.join(ROOT, "bench", "thinfilm-sphere.xml")
# The scene's parameters, shared by both renderers. --sun, --base and --film-nm change three of
# them for both (the Cycles worker, a separate process, reads them from the environment).
ALPHA, FILM_IOR, IOR, SKY = 0.05, 1.56, 1.5, 0.8
FILM_NM = float(os.environ.get("THINFILM_BENCH_FILM_NM", "500"))
BASE = float(os.environ.get("THINFILM_BENCH_BASE", "0.02"))
SUN = float(os.environ.get("THINFILM_BENCH_SUN", "2"))
SUN_DIR = (1.0, -1.0, -1.0)


# ---------------------------------------------------------------- Cycles (runs in a worker)

def build_cycles_scene(res, spp, seed, threads):
    """The benchmark scene in a fresh Blender file."""
    import bpy
    from mathutils import Vector
    bpy.ops.wm.read_factory_settings(use_empty=True)
    sc = bpy.context.scene
    sc.render.engine = "CYCLES"
    c = sc.cycles
    c.device = "CPU"
    c.samples = spp
    c.seed = seed
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.sample_clamp_direct = 0.0
    c.sample_clamp_indirect = 0.0
    c.blur_glossy = 0.0
    c.light_sampling_threshold = 0.0
    c.max_bounces = 12
    c.pixel_filter_type = "BOX"
    c.filter_width = 1.0
    sc.render.threads_mode = "FIXED"
    sc.render.threads = threads
    sc.render.resolution_x = sc.render.resolution_y = res
    sc.render.resolution_percentage = 100
    sc.view_settings.view_transform = "Standard"

    world = bpy.data.worlds.new("sky")
    sc.world = world
    world.use_nodes = True
    bg = world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = (SKY, SKY, SKY, 1.0)
    bg.inputs["Strength"].default_value = 1.0

    cam = bpy.data.cameras.new("camera")
    cam.sensor_fit = "HORIZONTAL"
    cam.angle = math.radians(30.0)
    cam_ob = bpy.data.objects.new("camera", cam)
    sc.collection.objects.link(cam_ob)
    cam_ob.location = (0.0, 0.0, 5.0)  # looks down −z with +y up, as the XML's lookat
    sc.camera = cam_ob

    sun = bpy.data.lights.new("sun", "SUN")
    sun.energy = SUN  # W/m², the irradiance on a surface facing the sun
    sun.angle = 0.0
    sun_ob = bpy.data.objects.new("sun", sun)
    sc.collection.objects.link(sun_ob)
    sun_ob.rotation_mode = "QUATERNION"
    sun_ob.rotation_quaternion = Vector(SUN_DIR).normalized().to_track_quat("-Z", "Y")

    mat = bpy.data.materials.new("film")
    mat.use_nodes = True
    p = mat.node_tree.nodes["Principled BSDF"]
    p.distribution = "GGX"
    p.inputs["Base Color"].default_value = (BASE, BASE, BASE, 1.0)
    p.inputs["Roughness"].default_value = math.sqrt(ALPHA)
    p.inputs["IOR"].default_value = IOR
    p.inputs["Thin Film Thickness"].default_value = FILM_NM
    p.inputs["Thin Film IOR"].default_value = FILM_IOR

    # An exact sphere: one mesh vertex turned into a point of radius 1 by geometry nodes.
    me = bpy.data.meshes.new("centre")
    me.from_pydata([(0.0, 0.0, 0.0)], [], [])
    ob = bpy.data.objects.new("sphere", me)
    sc.collection.objects.link(ob)
    g = bpy.data.node_groups.new("to_sphere", "GeometryNodeTree")
    g.interface.new_socket("Geometry", in_out="INPUT", socket_type="NodeSocketGeometry")
    g.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
    gi, go = g.nodes.new("NodeGroupInput"), g.nodes.new("NodeGroupOutput")
    pts = g.nodes.new("GeometryNodeMeshToPoints")
    pts.inputs["Radius"].default_value = 1.0
    sm = g.nodes.new("GeometryNodeSetMaterial")
    sm.inputs["Material"].default_value = mat
    g.links.new(gi.outputs[0], pts.inputs["Mesh"])
    g.links.new(pts.outputs[0], sm.inputs["Geometry"])
    g.links.new(sm.outputs[0], go.inputs[0])
    ob.modifiers.new("to_sphere", "NODES").node_group = g
    return sc


def cycles_worker(spp, seed, out, res, threads):
    import bpy
    sc = build_cycles_scene(res, spp, seed, threads)
    t0 = time.perf_counter()
    bpy.ops.render.render()
    secs = time.perf_counter() - t0
    sc.render.image_settings.file_format = "OPEN_EXR"
    sc.render.image_settings.color_depth = "32"
    bpy.data.images["Render Result"].save_render(out, scene=sc)
    print("CYCLES_RENDER %.6f %s" % (secs, sc.cycles.sampling_pattern))


# ---------------------------------------------------------------- the two renderers, timed

def timed(cmd):
    """Runs cmd; returns (stdout+stderr, wall seconds, CPU seconds of the child)."""
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    if p.returncode != 0:
        sys.exit("failed: %s\n%s%s" % (" ".join(cmd), p.stdout, p.stderr))
    cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
    return p.stdout + p.stderr, wall, cpu


def run_ophis(spp, seed, out, a, sampler, top, coat="walk"):
    exe = os.path.join(ROOT, "target", "release", "ophis")
    cmd = [exe, "render", SCENE, "-Dres=%d" % a.res, "-Dsampler=%s" % sampler, "-Dtop=%s" % top,
           "-Drough_coat=%s" % coat,
           "--spp", str(spp), "--seed", str(seed), "--threads", str(a.threads), "-q", "-o", out]
    cmd += ["-D" + d for d in a.define]
    text, wall, cpu = timed(cmd)
    # The summary's seconds have two decimals (10 ms: 8 % of a 32-spp render here); the time is
    # recomputed from its samples per second, which has four significant digits.
    m = re.search(r"(\d+)x(\d+), (\d+) spp, ([0-9.]+) s, .*?([0-9.]+) Msamples/s", text)
    if not m:
        sys.exit("ophis printed no time:\n" + text)
    w, h, n, secs, rate = m.groups()
    render = int(w) * int(h) * int(n) / (float(rate) * 1e6) if float(rate) > 0 else float(secs)
    return render, wall, cpu


def run_cycles(spp, seed, out, a):
    cmd = [sys.executable, os.path.abspath(__file__), "--cycles-worker",
           str(spp), str(seed), out, str(a.res), str(a.threads)]
    text, wall, cpu = timed(cmd)
    m = re.search(r"CYCLES_RENDER ([0-9.]+) (\S+)", text)
    if not m:
        sys.exit("Cycles worker printed no time:\n" + text)
    run_cycles.pattern = m.group(2)
    return float(m.group(1)), wall, cpu


# ---------------------------------------------------------------- images and errors

def load_exr(path):
    """Linear RGB as float64 (h, w, 3), read with Blender's image loader."""
    import bpy
    import numpy as np
    im = bpy.data.images.load(path, check_existing=False)
    w, h = im.size
    px = np.empty(w * h * 4, dtype=np.float32)
    im.pixels.foreach_get(px)
    bpy.data.images.remove(im)
    return px.reshape(h, w, 4)[::-1, :, :3].astype(np.float64)


def rel_mse(x, ref, eps):
    return float((((x - ref) ** 2) / (ref * ref + eps)).mean())


def time_to(points, target):
    """Time at which relMSE reaches `target`, by log-log interpolation between the measured
    (time, relMSE) points (extrapolated from the nearest two outside them; flagged)."""
    pts = sorted(points)
    lt = [math.log(t) for t, _ in pts]
    le = [math.log(e) for _, e in pts]
    lg = math.log(target)
    i = next((k for k in range(len(pts) - 1) if le[k] >= lg >= le[k + 1]), None)
    extrapolated = i is None
    if extrapolated:
        i = 0 if lg > le[0] else len(pts) - 2
    s = (lg - le[i]) / (le[i + 1] - le[i]) if le[i + 1] != le[i] else 0.0
    return math.exp(lt[i] + s * (lt[i + 1] - lt[i])), extrapolated


def median(v):
    v = sorted(v)
    n = len(v)
    return v[n // 2] if n % 2 else 0.5 * (v[n // 2 - 1] + v[n // 2])


def load_avg():
    return " ".join("%.2f" % x for x in os.getloadavg())


# ---------------------------------------------------------------- the benchmark

def renderers(a):
    """name → (render function(spp, seed, out), reference key). ophis's configurations share a
    reference per coat (the sampler does not change the converged image)."""
    out = {}
    for c in a.ophis.split(","):
        parts = c.split(":")
        if len(parts) not in (2, 3):
            sys.exit("--ophis: %r is not sampler:top or sampler:top:rough_coat" % c)
        sampler, top = parts[:2]
        coat = parts[2] if len(parts) == 3 else "walk"
        # The walk's two samplings render the same image: one reference (the walk's).
        ref_coat = "walk" if coat == "mixture" else coat
        out["ophis " + c] = ((lambda spp, seed, path, s=sampler, t=top, k=coat:
                              run_ophis(spp, seed, path, a, s, t, k)),
                             "ophis-%s-%s" % (top, ref_coat))
    if not a.no_cycles:
        out["cycles"] = ((lambda spp, seed, path: run_cycles(spp, seed, path, a)), "cycles")
    return out


def main():
    ap = argparse.ArgumentParser(description="ophis vs Cycles on a thin-film sphere at equal error")
    ap.add_argument("--res", type=int, default=96)
    ap.add_argument("--ref-spp", type=int, default=4096)
    ap.add_argument("--spp", default="4,8,16,32,64,128,256")
    ap.add_argument("--repeats", type=int, default=2)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--eps", type=float, default=1e-2)
    ap.add_argument("--ophis", default="independent:roughthinfilm,stratified:roughthinfilm,"
                    "stratified:roughthinfilm:mixture,stratified:roughthinfilm:plastic,"
                    "stratified:thinfilm",
                    help="ophis configurations, sampler:top[:rough_coat], comma-separated "
                    "(samplers: `independent`, or `stratified`/`ldsampler`/`sobol`, all "
                    "Owen-scrambled Sobol; tops: `roughthinfilm`, the scene's, or the smooth "
                    "`thinfilm`; rough_coat: `walk`, the default, `mixture` or `plastic`)")
    ap.add_argument("-D", dest="define", action="append", default=[],
                    help="extra scene parameter for ophis, name=value")
    ap.add_argument("--sun", type=float, help="the sun's irradiance, W/m² (default 2; 0: none)")
    ap.add_argument("--base", type=float, help="the base's albedo (default 0.02)")
    ap.add_argument("--film-nm", type=float,
                    help="the film's thickness, nm (default 500; 0: a bare rough dielectric)")
    ap.add_argument("--no-cycles", action="store_true", help="ophis only")
    ap.add_argument("--no-build", action="store_true")
    a = ap.parse_args()
    for opt, env, define in (("sun", "SUN", "sun"), ("base", "BASE", "base"),
                             ("film_nm", "FILM_NM", "thickness")):
        v = getattr(a, opt)
        if v is not None:
            if not (math.isfinite(v) and v >= 0.0):
                sys.exit("--%s %r: expected a finite value ≥ 0" % (opt.replace("_", "-"), v))
            os.environ["THINFILM_BENCH_" + env] = repr(v)
            a.define.append("%s=%r" % (define, v))
    spps = [int(s) for s in a.spp.split(",")]
    rend = renderers(a)
    names = list(rend)
    os.makedirs(OUT, exist_ok=True)
    if not a.no_build:
        subprocess.run(["cargo", "build", "--release", "--quiet"], cwd=ROOT, check=True)
    t_start = time.perf_counter()
    print("date %s, %d cores, load average %s" % (time.strftime("%Y-%m-%d %H:%M"),
                                                  os.cpu_count(), load_avg()))
    print("%d×%d px, reference %d spp, test spp %s, %d repeats, %d threads%s"
          % (a.res, a.res, a.ref_spp, spps, a.repeats, a.threads,
             "".join(" -D" + d for d in a.define)))

    refs = {}
    for n in names:
        render, key = rend[n]
        if key in refs:
            continue
        path = os.path.join(OUT, "%s-ref.exr" % key)
        # ophis's references use the Sobol sampler, which converges fastest.
        if key.startswith("ophis-"):
            _, top, coat = key.split("-")
            secs, wall, cpu = run_ophis(a.ref_spp, 0, path, a, "stratified", top, coat)
        else:
            secs, wall, cpu = render(a.ref_spp, 0, path)
        refs[key] = load_exr(path)
        print("reference %-20s %6d spp: render %7.1f s, process %7.1f s, cpu %7.1f s, mean RGB "
              "%s (sphere %s)" % (key, a.ref_spp, secs, wall, cpu,
                                  fmt_rgb(refs[key].mean(axis=(0, 1))),
                                  fmt_rgb(sphere_mean(refs[key]))))
    if "cycles" in names:
        print("Cycles sampling pattern: %s" % run_cycles.pattern)

    # runs[name][spp] = list of (render s, process s, cpu s, relMSE(eps), relMSE(1e-3)); the
    # errors are corrected for the reference's own noise (below).
    runs = {n: {s: [] for s in spps} for n in names}
    for r in range(a.repeats):
        for i, spp in enumerate(spps):
            # Rotate which renderer goes first so that load drifts hit all alike.
            k = (r * len(spps) + i) % len(names)
            for n in names[k:] + names[:k]:
                render, key = rend[n]
                path = os.path.join(OUT, "%s-%d.exr" % (n.replace(" ", "-").replace(":", "-"), spp))
                secs, wall, cpu = render(spp, 1 + r * 1000 + i, path)
                img, x = load_exr(path), refs[key]
                # E|x − ref|² = Var x + Var ref for independent images: at n spp against N,
                # the measured error is (1 + n/N) times the image's own.
                c = 1.0 + spp / a.ref_spp
                runs[n][spp].append((secs, wall, cpu, rel_mse(img, x, a.eps) / c,
                                     rel_mse(img, x, 1e-3) / c))
        print("repeat %d done, load average %s" % (r + 1, load_avg()))

    print("\n%-26s %5s %9s %17s %10s %9s %11s %11s" % ("", "spp", "render s", "(min–max)",
                                                       "process s", "cpu s", "relMSE", "ε=1e-3"))
    for n in names:
        for spp in spps:
            v = runs[n][spp]
            rs = [x[0] for x in v]
            print("%-26s %5d %9.3f %17s %10.3f %9.3f %11.4g %11.4g" % (
                n, spp, median(rs), "(%.3f–%.3f)" % (min(rs), max(rs)), median([x[1] for x in v]),
                median([x[2] for x in v]), mean([x[3] for x in v]), mean([x[4] for x in v])))
        # relMSE × spp: the variance per sample (flat for a 1/n estimator, falling for a
        # low-discrepancy one); and samples per second.
        v = [mean([x[3] for x in runs[n][s]]) * s for s in spps]
        sps = a.res * a.res * spps[-1] / median([x[0] for x in runs[n][spps[-1]]]) / 1e6
        print("%-26s relMSE×spp %s; %.2f M samples/s at %d spp" % (
            n, " ".join("%.3g" % x for x in v), sps, spps[-1]))
    if "cycles" in names and len(names) > 1:
        report_ratios(runs, spps, a)
    print("\ntotal %.0f s, load average %s" % (time.perf_counter() - t_start, load_avg()))


def report_ratios(runs, spps, a):
    """For each ophis configuration against Cycles: the time each needs to reach a common
    relMSE, at two targets inside both measured ranges (the geometric middle of the overlap,
    and its low end, the lowest error both reached), and Cycles' time over ophis's."""
    curves = {n: [mean([x[3] for x in runs[n][s]]) for s in spps] for n in runs}

    def times(n, col, target):
        out = []
        for r in range(a.repeats):
            pts = [(runs[n][s][r][col], runs[n][s][r][3]) for s in spps]
            out.append(time_to(pts, target))
        return [t for t, _ in out], any(e for _, e in out)

    def cell(v):
        return "%.3g (%.3g–%.3g)" % (median(v), min(v), max(v))

    print("\ntime to a common relMSE (median over repeats, min–max); Cycles ÷ ophis > 1: ophis "
          "is faster")
    print("%-26s %-4s %9s %25s %25s %25s" % ("ophis configuration", "", "target", "render",
                                           "process", "cpu"))
    best = None
    for n in runs:
        if n == "cycles":
            continue
        lo = max(min(curves[n]), min(curves["cycles"]))
        hi = min(max(curves[n]), max(curves["cycles"]))
        targets = [("mid", math.sqrt(lo * hi)), ("low", lo * 1.0001)] if lo < hi else \
            [("extr", lo)]
        for label, target in targets:
            ext_any = False
            row_o, row_c, row_r = [], [], []
            for col in range(3):
                to, e1 = times(n, col, target)
                tc, e2 = times("cycles", col, target)
                ext_any |= e1 or e2
                ratios = [c / o for c, o in zip(tc, to)]
                row_o.append(cell(to))
                row_c.append(cell(tc))
                row_r.append(cell(ratios))
                if col == 0 and label != "mid" and (best is None or median(ratios) > best[2]):
                    best = (n, target, median(ratios))
            flag = " (extrapolated)" if ext_any else ""
            print("%-26s %-4s %9.3g %25s %25s %25s%s" % (n, label, target, *row_o, flag))
            print("%-26s %-4s %9s %25s %25s %25s" % ("  cycles", "", "", *row_c))
            print("%-26s %-4s %9s %25s %25s %25s" % ("  Cycles ÷ ophis", "", "", *row_r))
    if best:
        print("best ophis configuration at the low target (render time): %s, relMSE %.3g, "
              "Cycles ÷ ophis %.2f" % best)


def mean(v):
    return sum(v) / len(v)


def fmt_rgb(c):
    return "(%.4f, %.4f, %.4f)" % tuple(c)


def sphere_mean(img):
    """Mean over the pixels the sphere covers (a disc of the projected radius)."""
    import numpy as np
    h, w, _ = img.shape
    # The sphere of radius 1 at distance 5 subtends asin(1/5); the half-width is tan(15°).
    r = math.tan(math.asin(0.2)) / math.tan(math.radians(15.0)) * w / 2 * 0.95
    y, x = np.mgrid[0:h, 0:w]
    m = (x + 0.5 - w / 2) ** 2 + (y + 0.5 - h / 2) ** 2 < r * r
    return img[m].mean(axis=0)


if __name__ == "__main__":
    if len(sys.argv) > 1 and sys.argv[1] == "--cycles-worker":
        s, seed, out, res, threads = sys.argv[2:7]
        cycles_worker(int(s), int(seed), out, int(res), int(threads))
    else:
        main()
