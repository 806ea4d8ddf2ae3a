#!/usr/bin/env python3
"""Reference values for src/optics/thinfilm.rs from the transfer-matrix method.

Uses the `tmm` package (Byrnes; pip install tmm), which is independent of ophis's Airy-sum code.
Prints one line per case: cos_theta0, n0, n1, d_nm, n2 (re, im), lambda_nm, R_s, R_p, T_s, T_p.
"""
import math

import tmm

CASES = [
    # (theta0 deg, n0, n1, d nm, n2, lambda nm)
    (30.0, 1.0, 1.56, 900.0, complex(0.43, 2.45), 550.0),
    (70.0, 1.0, 1.33, 450.0, complex(0.2, 3.1), 620.0),
    (50.0, 1.33, 1.8, 250.0, complex(1.5, 0.0), 480.0),
    (20.0, 1.5, 1.2, 1000.0, complex(1.0, 0.0), 700.0),
    (85.0, 1.0, 2.2, 120.0, complex(1.45, 0.0), 400.0),
]

for th, n0, n1, d, n2, lam in CASES:
    th0 = math.radians(th)
    out = []
    for pol in "sp":
        r = tmm.coh_tmm(pol, [n0, n1, n2], [math.inf, d, math.inf], th0, lam)
        out.append((r["R"], r["T"]))
    out = [(float(a), float(b)) for a, b in out]
    print(f"({math.cos(th0)!r}, {n0}, {n1}, {d}, ({n2.real}, {n2.imag}), {lam}, "
          f"{out[0][0]!r}, {out[1][0]!r}, {out[0][1]!r}, {out[1][1]!r}),")
