#!/usr/bin/env python3
"""Reference values for src/optics/filmstack.rs from an independent transfer-matrix code.

Uses the `tmm` package (Byrnes; `pip install tmm`; arXiv:1603.02720), whose conventions ophis
follows: time dependence e^{-i omega t}, n + ik with k > 0 absorbing, r_p = (n_f cos_i - n_i
cos_f)/(n_f cos_i + n_i cos_f), T_p with the conjugated cosines.

Writes tests/data/filmstack_tmm.tsv (tab-separated; one row per stack, side, angle and
wavelength), read by tests/filmstack.rs. Columns:

  case       a label
  ext        outside index (ophis's index syntax)
  stack      the layers, outside in, in ophis's stack syntax (optics/stackspec.rs)
  base       base index
  from_base  1 if the light arrives from the base (tmm gets the stack reversed)
  cos        cos of the angle of incidence in the incident medium
  lambda_nm  vacuum wavelength
  Rs Rp Ts Tp                    tmm's coh_tmm R and T for s and p
  rs_re rs_im rp_re rp_im        complex reflection amplitudes
  ts_re ts_im tp_re tp_im        complex transmission amplitudes

Run from the repository root: python3 tools/tmm_stack_reference.py
Reruns reproduce the file to about 1e-15 (numpy's complex arithmetic may take different SIMD
paths from run to run); the Rust test's tolerance is 1e-9.
"""
import math
import random

import tmm

KERATIN = (1.532, 5890.0)


def index_at(spec, lam):
    """The value of an index written in ophis's syntax (the subset this script writes)."""
    if spec == "keratin":
        a, b = KERATIN
        return complex(a + b / (lam * lam), 0.0)
    if spec.startswith("cauchy("):
        a, b = (float(x) for x in spec[len("cauchy("):-1].split(","))
        return complex(a + b / (lam * lam), 0.0)
    if spec.endswith("i"):
        body = spec[:-1]
        cut = max(i for i, c in enumerate(body) if c in "+-" and i > 0 and body[i - 1] not in "eE")
        return complex(float(body[:cut]), float(body[cut:]))
    return complex(float(spec), 0.0)


def flatten(stack):
    """[(index spec, d)] with groups written out; `stack` is a list of (spec, d) and
    (list, count) items, as written to the file by `fmt`."""
    out = []
    for item in stack:
        if isinstance(item[0], list):
            out += item[0] * item[1]
        else:
            out.append(item)
    return out


def fmt(stack):
    def layer(l):
        return f"{l[0]}:{l[1]!r}"

    parts = []
    for item in stack:
        if isinstance(item[0], list):
            parts.append("(" + ",".join(layer(l) for l in item[0]) + f")x{item[1]}")
        else:
            parts.append(layer(item))
    return ",".join(parts)


def cx(z):
    return f"{z.real!r}\t{z.imag!r}"


ROWS = []


def add(case, ext, stack, base, angles_deg, lambdas, from_base=False):
    layers = flatten(stack)
    for ang in angles_deg:
        th0 = math.radians(ang)
        for lam in lambdas:
            n_layers = [index_at(s, lam) for s, _ in layers]
            d_layers = [d for _, d in layers]
            n_ext, n_base = index_at(ext, lam), index_at(base, lam)
            if from_base:
                n_list = [n_base] + n_layers[::-1] + [n_ext]
                d_list = [math.inf] + d_layers[::-1] + [math.inf]
            else:
                n_list = [n_ext] + n_layers + [n_base]
                d_list = [math.inf] + d_layers + [math.inf]
            res = {p: tmm.coh_tmm(p, n_list, d_list, th0, lam) for p in "sp"}
            ROWS.append("\t".join([
                case, ext, fmt(stack), base, "1" if from_base else "0",
                repr(math.cos(th0)), repr(float(lam)),
                repr(float(res["s"]["R"])), repr(float(res["p"]["R"])),
                repr(float(res["s"]["T"])), repr(float(res["p"]["T"])),
                cx(complex(res["s"]["r"])), cx(complex(res["p"]["r"])),
                cx(complex(res["s"]["t"])), cx(complex(res["p"]["t"])),
            ]))


def main():
    vis = [380.0, 450.0, 500.0, 550.0, 600.0, 650.0, 720.0, 800.0]
    fine = [360.0 + 10.0 * i for i in range(48)]

    # Bragg mirrors: quarter-wave at 550 nm, high/low 2.3 / 1.38 (TiO2-like / MgF2-like).
    h = ("2.3", 550.0 / (4 * 2.3))
    l = ("1.38", 550.0 / (4 * 1.38))
    add("bragg10", "1.0", [([h, l], 10)], "1.52", [0, 30, 60, 89], fine)
    add("bragg10-cap", "1.0", [([h, l], 10), h], "1.52", [0, 45, 89.9], vis)
    add("bragg10-from-base", "1.0", [([h, l], 10), h], "1.52", [0, 20, 40], vis, from_base=True)
    add("bragg32", "1.33", [([h, l], 32)], "1.0", [0, 45], [540.0, 550.0, 560.0, 700.0])

    # Keratin lamellae: keratin / air, and keratin / a melanin-like absorber (n 1.7, k 0.03).
    add("keratin-air", "1.0", [([("keratin", 100.0), ("1.0", 90.0)], 5)], "keratin",
        [0, 25, 50, 75, 89], vis)
    add("keratin-melanin", "1.0", [([("keratin", 110.0), ("1.7+0.03i", 80.0)], 6), ("keratin", 60.0)],
        "keratin", [0, 40, 70], vis)
    add("keratin-melanin-from-base", "1.0", [([("keratin", 110.0), ("1.7+0.03i", 80.0)], 6)],
        "keratin", [0, 30], vis, from_base=True)

    # An absorbing layer, and dispersive Cauchy layers.
    add("absorber", "1.0", [("1.5", 100.0), ("2.0+0.5i", 30.0), ("1.4", 200.0)], "1.52",
        [0, 35, 70, 89], vis)
    add("absorber-from-base", "1.0", [("1.5", 100.0), ("2.0+0.5i", 30.0), ("1.4", 200.0)], "1.52",
        [0, 35, 60], vis, from_base=True)
    add("cauchy", "1.0", [("cauchy(1.6,8000)", 140.0), ("cauchy(1.45,3500)", 95.0)], "1.5",
        [0, 60], vis)

    # Metal bases (gold- and silver-like n + ik) and a thin metal layer.
    add("film-on-gold", "1.0", [("keratin", 300.0)], "0.43+2.45i", [0, 30, 60, 89], vis)
    add("stack-on-silver", "1.0", [("1.38", 95.0), ("2.3", 60.0), ("1.38", 95.0)], "0.05+3.3i",
        [0, 45, 85], vis)
    add("thin-silver", "1.0", [("1.5", 80.0), ("0.05+3.3i", 20.0), ("1.5", 80.0)], "1.5",
        [0, 50], vis)

    # Grazing incidence.
    add("grazing", "1.0", [("1.56", 300.0), ("1.33", 200.0), ("2.0", 50.0)], "1.5",
        [89.0, 89.9, 89.99], vis)

    # Total internal reflection: from glass into air beyond the critical angle (41.8 deg);
    # frustrated TIR through a low-index gap; evanescent waves in one layer of a stack; TIR
    # inside a keratin/air stack lit from the keratin base.
    add("tir-to-air", "1.5", [("1.8", 120.0), ("1.2", 200.0)], "1.0", [30, 45, 60, 80], vis)
    add("ftir-gap", "1.5", [("1.0", 150.0)], "1.5", [50, 60, 70], vis)
    add("ftir-gap-stack", "1.5", [("1.7", 80.0), ("1.0", 300.0), ("1.7", 80.0), ("1.0", 1500.0)],
        "1.5", [45, 55, 65], vis)
    add("tir-inside-from-base", "1.0", [([("keratin", 100.0), ("1.0", 90.0)], 3)], "keratin",
        [20, 45, 60], vis, from_base=True)

    # Random stacks (seeded): 2-16 layers, indices 1-2.6, some absorbing, both sides.
    for seed in range(8):
        rng = random.Random(1000 + seed)
        n = rng.randint(2, 16)
        stack = []
        for _ in range(n):
            nr = 1.0 + 1.6 * rng.random()
            d = 400.0 * rng.random()
            if rng.random() < 0.3:
                stack.append((f"{nr!r}+{0.2 * rng.random()!r}i", d))
            else:
                stack.append((repr(nr), d))
        ext = repr(1.0 + 0.5 * rng.random())
        base = repr(1.0 + 1.6 * rng.random())
        angles = sorted(round(89.5 * rng.random(), 3) for _ in range(4))
        lams = sorted(round(360.0 + 470.0 * rng.random(), 2) for _ in range(6))
        add(f"random{seed}", ext, stack, base, angles, lams)
        add(f"random{seed}-from-base", ext, stack, base, angles[:2], lams[:3], from_base=True)

    header = ("case\text\tstack\tbase\tfrom_base\tcos\tlambda_nm\tRs\tRp\tTs\tTp\t"
              "rs_re\trs_im\trp_re\trp_im\tts_re\tts_im\ttp_re\ttp_im")
    with open("tests/data/filmstack_tmm.tsv", "w") as f:
        f.write("# generated by tools/tmm_stack_reference.py (tmm, Byrnes); do not edit\n")
        f.write(header + "\n")
        for r in ROWS:
            f.write(r + "\n")
    print(f"wrote {len(ROWS)} rows to tests/data/filmstack_tmm.tsv")


if __name__ == "__main__":
    main()
