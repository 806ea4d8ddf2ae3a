#!/usr/bin/env python3
"""The two-lights check of the flagship (issue 14): the same snake and camera under dull light
(an overcast sky, no sun) and under strong, low sun, measured on the snake's own pixels.

Field descriptions of the sunbeam snake (../shared/research/anchors.md): "under dull light they
look plain brown with a lighter underbelly; in strong sunlight" an iridescent sheen appears. So,
on the dorsal skin: dull light should give a low mean chroma and a brown hue, and a belly lighter
than the back; sun should give highlights whose colours are saturated and whose hues spread
around the hue circle.

The script renders scenes/xenopeltis.xml twice with `ophis render` — unchanged except that its
`path` integrator is wrapped in Mitsuba's `aov` integrator to record which shape each pixel shows
(`shape_index`) and the surfaces' albedo — from the flagship's camera, once as it is (sun and
sky) and once with -Dsun=0 -Dsky=0 -Dovercast=1. The dorsal skin is the `snake.body` part (the header's
`ophis.shapes` legend says which index that is), the belly `snake.belly`; pixels whose 3×3
neighbourhood is not all the same part are dropped (edges and defocus mix parts, and an average
of two other indices could equal this one's).

Colour is CIE L*a*b* of the linear sRGB pixels, seen as an observer adapted to the scene's own
light sees them. The white is what a white Lambertian surface lit like the open ground would
show, found through the albedo AOV over the lit soil pixels, those whose Y / albedo_Y is at least
half its 90th percentile over the soil (in sun the sunlit ground, not the ground in the shade of
the snake, the leaves and the crumbs, an order of magnitude darker and lit by the bluer sky
alone; under the overcast sky all but occluded crevices): its luminance Y_n is the median of
Y / albedo_Y over them (so both lights are exposed alike), and its colour the median, channel by
channel, of RGB / albedo. Pixels are taken to XYZ, adapted from that white to D65 by the
Bradford transform (von Kries scaling in Bradford's sharpened cone space, as in CIECAM97s and
ICC colour management), and converted to L*a*b* against D65 with Y = Y_n. Why: the issue's
description of the animal ("plain brown" in dull light, a rainbow sheen in sun) comes from
observers and photographs, and both are adapted to the light they are in: the eye adapts, and
a photograph is white-balanced. Referenced to D65 instead, everything under the low sun is
pulled towards orange (a white surface under it has a* ≈ +3, b* ≈ +19: the script prints the
illuminant's white before adaptation), so a neutral surface would already count as nearly
"saturated" and the highlights' hues would be the sun's colour rather than the skin's. The
adaptation is the same for both lights and for every criterion below; under the overcast sky
(a grey `constant` emitter) the white is D65 within 0.5 in a* and b*, so the dull-light figures
are the same either way. `--reference d65` measures without adaptation, as the script did
before (the README's figures before 2026-12-02's second change were taken so).

Printed for each light: the dorsal skin's
mean L*, mean chroma C*ab and mean hue angle; a histogram of hue (12 bins of 30°) over the dorsal
pixels with C* > 8 (hue means nothing for greys); the same for the highlights (the brightest 10 %
of dorsal pixels), counting only the saturated ones (C* > 20); and the belly's mean L* (a belly
pixel is one of the `snake.belly` part whose albedo confirms it, as the belly shows only as a
strip where a stretch of the coil lies tilted).

The check passes when every criterion below holds; each is printed with its threshold and
PASS or FAIL (the exit status stays 0: this is a measurement, not a test). The thresholds come
from the descriptions of the animal and colour charts, not from the renders:

  dull light, dorsal skin
    plain     mean C*ab < 10. The animal is "dark brown to blackish" above. In the Munsell soil
              colour charts dark brown (7.5YR 3/2) and very dark brown (10YR 2/2) have Munsell
              chroma 2, which is C*ab 12.5 and 11.7; blackish ones (10YR 2/1, 3/1) chroma 1,
              C*ab 5.8 and 6.3 (Munsell renotation data converted with colour-science 0.4.7,
              illuminant C adapted to D65 by Bradford). Between the two: below 10.
    brown     hue angle of the mean a*b* within 40–80°. The browns of those charts, 5YR to
              10YR at chroma 2, lie at 54–72°; the interval allows half a hue page either side.
    belly     the belly's mean L* at least 10 above the back's: "a lighter underbelly", one
              Munsell value step (≈ 10 L*) or more.
  strong sun, highlights (the brightest 10 % of the dorsal pixels)
    saturated mean C*ab > 20, the cut this script has always used for a saturated pixel.
              With the adapted white a neutral surface has C* 0 under either light, so the
              cut measures the skin's own colour; against D65 a white surface under the low
              sun had C* ≈ 19 by itself. Same threshold, a stricter test.
    hues      the saturated highlight pixels (C* > 20) fill more than 6 of the 12 hue bins of
              30° (a bin counts when it holds > 2 % of them): most of the hue circle, hue
              being taken around the adapted white, as an observer names the colours.

Also printed, not judged: the colour spread of the dorsal skin, the r.m.s. distance of its
pixels' a*b* from their mean (how far from uniform the back is: bands and speckle raise it).

    python3 tools/two_lights.py                    # 480×270, 128 spp
    python3 tools/two_lights.py --res 320x180 --spp 32 --keep out/   # also keeps the EXRs/PNGs
    python3 tools/two_lights.py --res 240x135 --spp 32 -D base_ior=1.45   # explore a parameter
    python3 tools/two_lights.py --seed 2           # another, independent pair of renders
    python3 tools/two_lights.py --measure out/     # measure renders kept by --keep again
    python3 tools/two_lights.py --reference d65    # no chromatic adaptation (see above)

Changes on 2026-12-02 (issue 14): the criteria and their PASS/FAIL lines, the colour spread, and
-D; then the chromatic adaptation to the scene's white (above; the mask as before), --seed,
--measure and --reference; then Y_n from the lit soil only. It was the median over all soil
pixels, which in sun fell just inside the sunlit cluster when a little under half the soil was
shaded (480x270: 48 %, Y_n 0.25 against the lit soil's 0.375) and into the shade when more was
(-Dhour=17.6: Y_n 0.025), exposing the snake for the shade and raising its L* and C* with it:
the flagship's highlight C*ab (with n2 = 1.46) was 24.6 so, 21.5 against the lit soil.

-D NAME=VALUE sets a scene parameter for both renders (the lights' own settings come after it
and win); the figures the README quotes come from the script without -D.

Needs numpy and a built `target/release/ophis` (or --ophis PATH).
"""

import argparse
import os
import re
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from exr_read import read_exr  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
AOVS = "id:shape_index,alb:albedo"
LIGHTS = {
    "dull (overcast, no sun)": ["-Dsun=0", "-Dsky=0", "-Dovercast=1"],
    "strong low sun": [],
}
# The flagship's own view (a stretch of its outer coil lies tilted, showing the belly); other
# views can be given as -Deye=… -Daim=… -Dfocus=… here.
VIEW = []


def with_aovs(xml):
    """The flagship with its integrator wrapped in an `aov` integrator."""
    m = re.search(r"<integrator type=\"path\">.*?</integrator>", xml, re.S)
    if not m:
        raise SystemExit("the scene has no <integrator type=\"path\"> block")
    inner = m.group(0).replace('<integrator type="path">', '<integrator type="path" name="image">')
    wrapped = f'<integrator type="aov">\n<string name="aovs" value="{AOVS}"/>\n{inner}\n</integrator>'
    return xml[: m.start()] + wrapped + xml[m.end() :]


SRGB_TO_XYZ = np.array(
    [[0.4124, 0.3576, 0.1805], [0.2126, 0.7152, 0.0722], [0.0193, 0.1192, 0.9505]]
)
D65 = np.array([0.95047, 1.0, 1.08883])
# Bradford's cone-response matrix (Lam 1985; as in CIECAM97s and ICC profiles).
BRADFORD = np.array(
    [[0.8951, 0.2664, -0.1614], [-0.7502, 1.7135, 0.0367], [0.0389, -0.0685, 1.0296]]
)


def adaptation(white_rgb):
    """Bradford (von Kries in sharpened cone space) matrix taking XYZ seen under the illuminant
    whose white is `white_rgb` (linear sRGB, any scale) to XYZ under D65, the white keeping Y."""
    w = SRGB_TO_XYZ @ white_rgb
    w = w / w[1]
    gain = (BRADFORD @ D65) / (BRADFORD @ w)
    return np.linalg.inv(BRADFORD) @ np.diag(gain) @ BRADFORD


def lab(rgb, yn, adapt=np.eye(3)):
    """CIE L*a*b* (D65 white, Y_n = yn) of linear sRGB pixels (N × 3), after the chromatic
    adaptation `adapt` (an XYZ → XYZ matrix)."""
    xyz = rgb @ (adapt @ SRGB_TO_XYZ).T / yn
    t = xyz / D65
    f = np.where(t > (6 / 29) ** 3, np.cbrt(np.maximum(t, 0)), t / (3 * (6 / 29) ** 2) + 4 / 29)
    L = 116 * f[:, 1] - 16
    a = 500 * (f[:, 0] - f[:, 1])
    b = 200 * (f[:, 1] - f[:, 2])
    return L, a, b


def erode(mask):
    """True where the pixel and its 8 neighbours are all True."""
    out = mask.copy()
    h, w = mask.shape
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            sh = np.zeros_like(mask)
            sh[max(0, dy) : h + min(0, dy), max(0, dx) : w + min(0, dx)] = mask[
                max(0, -dy) : h + min(0, -dy), max(0, -dx) : w + min(0, -dx)
            ]
            out &= sh
    return out


def index_of(legend, label):
    index = [int(k) for k, v in legend.items() if v == label]
    if not index:
        raise SystemExit(f"no shape {label} in the legend {legend}")
    return index[0]


def part_mask(planes, legend, label):
    return erode(np.abs(planes["id.I"] - index_of(legend, label)) < 1e-4)


def hue_histogram(h, weights=None):
    counts, _ = np.histogram(h % 360, bins=12, range=(0, 360), weights=weights)
    return counts


def report(name, planes, legend, reference):
    rgb = np.stack([planes["R"], planes["G"], planes["B"]], axis=-1)
    alb = np.stack([planes["alb.R"], planes["alb.G"], planes["alb.B"]], axis=-1)
    lum = rgb @ np.array([0.2126, 0.7152, 0.0722])
    alb_y = alb @ np.array([0.2126, 0.7152, 0.0722])
    soil = part_mask(planes, legend, "soil") & (alb_y > 0.02)
    irradiance = lum[soil] / alb_y[soil]
    # The lit ground: in sun, the sunlit soil and the soil in shade (the snake's, the leaves',
    # the crumbs' own) form two clusters an order of magnitude apart, and a median over both
    # lands wherever the shaded fraction puts it; soil at least half as lit as the 90th
    # percentile is the sunlit cluster (under the overcast sky, all but occluded crevices).
    lit = irradiance >= 0.5 * np.quantile(irradiance, 0.9)
    yn = float(np.median(irradiance[lit]))
    # The illuminant's colour: what a white Lambertian surface lit like that ground would show,
    # channel by channel (in shade the ground sees the bluer sky only).
    white = np.median(rgb[soil][lit] / np.maximum(alb[soil][lit], 1e-3), axis=0)
    adapt = adaptation(white) if reference == "scene" else np.eye(3)
    _, wa, wb = lab((white / (white @ np.array([0.2126, 0.7152, 0.0722])))[None, :], 1.0)
    dorsal = part_mask(planes, legend, "snake.body")
    # The pale band is a thin strip from this view: instead of eroding it away, a pixel counts as
    # belly when every sample saw it, which its albedo confirms (mixtures with the dark back or
    # the soil have albedos far below the band's ~0.7).
    belly = (np.abs(planes["id.I"] - index_of(legend, "snake.belly")) < 1e-4) & (alb_y > 0.4)
    L, a, b = lab(rgb[dorsal], yn, adapt)
    C = np.hypot(a, b)
    h = np.degrees(np.arctan2(b, a)) % 360
    Lb, _, _ = lab(rgb[belly], yn, adapt)
    print(f"\n{name}")
    print(f"  white reference Y_n = {yn:.4g} (from {lit.sum()} lit of {soil.sum()} soil pixels); "
          f"the illuminant's white in D65 Lab: a* {wa[0]:+.1f}, b* {wb[0]:+.1f} "
          + ("(adapted to D65 by Bradford)" if reference == "scene" else "(not adapted)"))
    hue_mean = np.degrees(np.arctan2(b.mean(), a.mean())) % 360
    spread = float(np.sqrt(np.mean((a - a.mean()) ** 2 + (b - b.mean()) ** 2)))
    print(f"  dorsal skin: {dorsal.sum()} pixels, mean L* {L.mean():.1f}, mean C*ab {C.mean():.1f}, "
          f"hue of the mean a*b* {hue_mean:.0f}°, colour spread (r.m.s. Δa*b*) {spread:.1f}")
    print(f"  belly: {belly.sum()} pixels, mean L* {Lb.mean():.1f}" if belly.sum() else "  belly: not in view")
    bins = " ".join(f"{lo:>3}" for lo in range(0, 360, 30))
    print(f"  hue bins (°)              {bins}")
    sat = C > 8
    print(f"  dorsal, C* > 8 ({sat.sum():>5})      " + " ".join(f"{c:>3}" for c in hue_histogram(h[sat])))
    top = L >= np.quantile(L, 0.9)
    hs = top & (C > 20)
    occupied = int((hue_histogram(h[hs]) > 0.02 * max(hs.sum(), 1)).sum())
    print(f"  highlights, C* > 20 ({hs.sum():>5}) " + " ".join(f"{c:>3}" for c in hue_histogram(h[hs])))
    print(f"  highlights ({top.sum()} px): mean L* {L[top].mean():.1f}, mean C*ab {C[top].mean():.1f}, "
          f"{hs.sum()} saturated (C* > 20), whose hues fill {occupied} of 12 bins (> 2 % each)")
    return dict(L=L.mean(), C=C.mean(), hue=hue_mean, spread=spread,
                Lbelly=Lb.mean() if belly.sum() else float("nan"), Ctop=C[top].mean(), bins=occupied)


def verdicts(d, s):
    """The criteria of the module header: (light, name, measured, threshold, passed)."""
    belly = d["Lbelly"] - d["L"]
    return [
        ("dull", "plain: dorsal mean C*ab", f"{d['C']:.1f}", "< 10", d["C"] < 10),
        ("dull", "brown: hue of the dorsal mean a*b*", f"{d['hue']:.0f}°", "40–80°",
         40 <= d["hue"] <= 80),
        ("dull", "belly lighter: belly L* − dorsal L*", f"{belly:.1f}", ">= 10", belly >= 10),
        ("sun", "saturated: highlight mean C*ab", f"{s['Ctop']:.1f}", "> 20", s["Ctop"] > 20),
        ("sun", "hues: bins of 30° filled by saturated highlights", f"{s['bins']} of 12", "> 6",
         s["bins"] > 6),
    ]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--res", default="480x270")
    ap.add_argument("--spp", type=int, default=128)
    ap.add_argument("--ophis", default=os.path.join(ROOT, "target", "release", "ophis"))
    ap.add_argument("--keep", help="folder to keep the renders in (EXR with AOVs, PNG)")
    ap.add_argument("--scene", default=os.path.join(ROOT, "scenes", "xenopeltis.xml"),
                    help="a variant of the flagship to measure instead (same parts and -D names)")
    ap.add_argument("-D", dest="defines", action="append", default=[], metavar="NAME=VALUE",
                    help="a scene parameter for both renders (e.g. -D base_ior=1.45), to explore")
    ap.add_argument("--reference", choices=["scene", "d65"], default="scene",
                    help="the white colour is referenced to: the scene's lit ground, adapted to D65 "
                    "by Bradford (default), or D65 itself with no adaptation (the script before "
                    "2026-12-02's second change)")
    ap.add_argument("--measure", metavar="DIR",
                    help="measure the renders a previous --keep left in DIR instead of rendering")
    ap.add_argument("--seed", type=int, help="seed of both renders (ophis render --seed)")
    args = ap.parse_args()
    w, h = args.res.split("x")
    xml = with_aovs(open(args.scene, encoding="utf-8").read())
    out_dir = args.measure or args.keep or tempfile.mkdtemp(prefix="two-lights-")
    os.makedirs(out_dir, exist_ok=True)
    scene = os.path.join(out_dir, "xenopeltis-aov.xml")
    open(scene, "w", encoding="utf-8").write(xml)
    results = {}
    for i, (name, defines) in enumerate(LIGHTS.items()):
        out = os.path.join(out_dir, ["dull", "sun"][i])
        seed = ["--seed", str(args.seed)] if args.seed is not None else []
        cmd = [args.ophis, "render", scene, "-q", "--spp", str(args.spp), *seed, f"-Dwidth={w}",
               f"-Dheight={h}", *VIEW, *[f"-D{d}" for d in args.defines], *defines, "-o", out]
        if not args.measure:
            print(" ".join(cmd), flush=True)
            subprocess.run(cmd, check=True)
        planes, text = read_exr(out + ".exr")
        legend = dict(item.split("=", 1) for item in text["ophis.shapes"].split(";"))
        results[name] = report(name, planes, legend, args.reference)
    d, s = results.values()
    print("\nsummary: dull vs sun")
    print(f"  dorsal mean chroma C*ab   {d['C']:.1f} vs {s['C']:.1f}")
    print(f"  highlight mean chroma     {d['Ctop']:.1f} vs {s['Ctop']:.1f}")
    print(f"  highlight hue bins used   {d['bins']} vs {s['bins']} of 12")
    print(f"  belly minus dorsal L*     {d['Lbelly'] - d['L']:.1f} vs {s['Lbelly'] - s['L']:.1f}")
    print(f"  dorsal colour spread      {d['spread']:.1f} vs {s['spread']:.1f}")
    print("\ncriteria (thresholds and their reasons: the header of tools/two_lights.py)")
    checks = verdicts(d, s)
    for light, name, value, threshold, ok in checks:
        print(f"  {'PASS' if ok else 'FAIL'}  {light:4}  {name:50} {value:>8}  (needs {threshold})")
    print(f"  {'PASS' if all(c[-1] for c in checks) else 'FAIL'}  overall")
    if args.keep:
        print(f"renders kept in {out_dir}")


if __name__ == "__main__":
    main()
