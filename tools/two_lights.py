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

Colour is CIE L*a*b* (D65) of the linear sRGB pixels. The white reference Y_n is what a white
Lambertian surface lit like the ground would show: the median over soil pixels of Y / albedo_Y
(the albedo AOV), so both lights are exposed alike. Printed for each light: the dorsal skin's
mean L*, mean chroma C*ab and mean hue angle; a histogram of hue (12 bins of 30°) over the dorsal
pixels with C* > 8 (hue means nothing for greys); the same for the highlights (the brightest 10 %
of dorsal pixels), counting only the saturated ones (C* > 20); and the belly's mean L* (a belly pixel is one of the `snake.belly` part whose
albedo confirms it, as the belly shows only as a strip where a stretch of the coil lies tilted).

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
    hues      the saturated highlight pixels (C* > 20) fill more than 6 of the 12 hue bins of
              30° (a bin counts when it holds > 2 % of them): most of the hue circle.

Also printed, not judged: the colour spread of the dorsal skin, the r.m.s. distance of its
pixels' a*b* from their mean (how far from uniform the back is: bands and speckle raise it).

    python3 tools/two_lights.py                    # 480×270, 128 spp
    python3 tools/two_lights.py --res 320x180 --spp 32 --keep out/   # also keeps the EXRs/PNGs
    python3 tools/two_lights.py --res 240x135 --spp 32 -D base_ior=1.45   # explore a parameter

Changes on 2026-12-02 (issue 14): the criteria and their PASS/FAIL lines, the colour spread, and
-D; the mask, the white reference (exposure) and the Lab conversion are as before. Note that Lab
is taken against D65 scaled to the soil's white luminance, with no white balance: the low sun
is warm (a white surface under it has b* ≈ +18), which pulls the sun highlights' hues towards
orange and yellow.

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


def lab(rgb, yn):
    """CIE L*a*b* (D65 white, Y_n = yn) of linear sRGB pixels (N × 3)."""
    m = np.array(
        [[0.4124, 0.3576, 0.1805], [0.2126, 0.7152, 0.0722], [0.0193, 0.1192, 0.9505]]
    )
    xyz = rgb @ m.T / yn
    white = np.array([0.95047, 1.0, 1.08883])
    t = xyz / white
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


def report(name, planes, legend):
    rgb = np.stack([planes["R"], planes["G"], planes["B"]], axis=-1)
    alb = np.stack([planes["alb.R"], planes["alb.G"], planes["alb.B"]], axis=-1)
    lum = rgb @ np.array([0.2126, 0.7152, 0.0722])
    alb_y = alb @ np.array([0.2126, 0.7152, 0.0722])
    soil = part_mask(planes, legend, "soil") & (alb_y > 0.02)
    yn = float(np.median(lum[soil] / alb_y[soil]))
    dorsal = part_mask(planes, legend, "snake.body")
    # The pale band is a thin strip from this view: instead of eroding it away, a pixel counts as
    # belly when every sample saw it, which its albedo confirms (mixtures with the dark back or
    # the soil have albedos far below the band's ~0.7).
    belly = (np.abs(planes["id.I"] - index_of(legend, "snake.belly")) < 1e-4) & (alb_y > 0.4)
    L, a, b = lab(rgb[dorsal], yn)
    C = np.hypot(a, b)
    h = np.degrees(np.arctan2(b, a)) % 360
    Lb, _, _ = lab(rgb[belly], yn)
    print(f"\n{name}")
    print(f"  white reference Y_n = {yn:.4g} (from {soil.sum()} soil pixels)")
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
    args = ap.parse_args()
    w, h = args.res.split("x")
    xml = with_aovs(open(args.scene, encoding="utf-8").read())
    out_dir = args.keep or tempfile.mkdtemp(prefix="two-lights-")
    os.makedirs(out_dir, exist_ok=True)
    scene = os.path.join(out_dir, "xenopeltis-aov.xml")
    open(scene, "w", encoding="utf-8").write(xml)
    results = {}
    for i, (name, defines) in enumerate(LIGHTS.items()):
        out = os.path.join(out_dir, ["dull", "sun"][i])
        cmd = [args.ophis, "render", scene, "-q", "--spp", str(args.spp), f"-Dwidth={w}",
               f"-Dheight={h}", *VIEW, *[f"-D{d}" for d in args.defines], *defines, "-o", out]
        print(" ".join(cmd), flush=True)
        subprocess.run(cmd, check=True)
        planes, text = read_exr(out + ".exr")
        legend = dict(item.split("=", 1) for item in text["ophis.shapes"].split(";"))
        results[name] = report(name, planes, legend)
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
