"""Film tables and BSDF estimates: the numbers the command line prints."""

import csv
import io

import numpy as np
import pytest

import ophis


def cli_table(cli, *args):
    return list(csv.DictReader(io.StringIO(cli("thinfilm", *args))))


@pytest.mark.parametrize("py, args", [
    (dict(film_ior=1.56, thickness=900), ["--film-ior", "1.56", "--thickness", "900"]),
    (dict(film_ior="keratin", thickness=300, int_eta=0.43, int_k=2.45),
     ["--film-ior", "keratin", "--thickness", "300", "--int-eta", "0.43", "--int-k", "2.45"]),
    (dict(film_ior="water", thickness=120.5, ext_ior=1.33, int_ior="bk7"),
     ["--film-ior", "water", "--thickness", "120.5", "--ext-ior", "1.33", "--int-ior", "bk7"]),
    (dict(stack=[(2.3, 59.78), (1.38, 99.64)] * 6, int_ior=1.52),
     ["--stack", "(2.3:59.78,1.38:99.64)x6", "--int-ior", "1.52"]),
    (dict(stack="keratin:100,1.7+0.03i:80,keratin:100", int_ior="keratin"),
     ["--stack", "keratin:100,1.7+0.03i:80,keratin:100", "--int-ior", "keratin"]),
])
def test_thinfilm_matches_the_cli(cli, py, args):
    angles, wl = [0.0, 30.0, 60.0, 89.0], np.arange(380.0, 781.0, 20.0)
    f = ophis.thinfilm(angles=angles, wavelengths=wl, **py)
    assert f.R.shape == (len(wl), len(angles)) and f.rgb.shape == (len(angles), 3)
    rows = cli_table(cli, *args, "--angles", "0,30,60,89", "--wavelengths", "380:780:20")
    assert len(rows) == f.R.size
    for row in rows:  # angles outer, wavelengths inner; printed to 8 decimals
        i = list(wl).index(float(row["wavelength_nm"]))
        j = angles.index(float(row["angle_deg"]))
        for name, arr in [("R_s", f.Rs), ("R_p", f.Rp), ("R", f.R), ("T", f.T)]:
            assert arr[i, j] == pytest.approx(float(row[name]), abs=5e-9), (name, row)
    rgb = cli_table(cli, *args, "--angles", "0,30,60,89", "--rgb")
    for j, row in enumerate(rgb):
        for c, k in enumerate("rgb"):
            assert f.rgb[j, c] == pytest.approx(float(row[k]), abs=5e-7)


def test_thinfilm_physics_and_defaults():
    f = ophis.thinfilm(film_ior=1.5, thickness=250, angles=[0, 45])
    assert f.wavelengths[0] == 380 and f.wavelengths[-1] == 780
    # A lossless film: R + T = 1.
    assert np.allclose(f.R + f.T, 1, atol=1e-12)
    assert np.allclose(f.R, (f.Rs + f.Rp) / 2)
    white = ophis.thinfilm(thickness=0, ext_ior=1.0, int_ior=1.0)
    assert np.allclose(white.R, 0, atol=1e-15)


@pytest.mark.parametrize("kw, words", [
    (dict(thickness=-1), "thickness"), (dict(angles=[95]), "angles"),
    (dict(wavelengths=[0]), "wavelengths"), (dict(film_ior=-1.2), "film_ior"),
    (dict(film_ior="unobtainium"), "film_ior"), (dict(int_eta=1.0), "int_eta and int_k"),
    (dict(int_ior=1.5, int_eta=1.0, int_k=1.0), "not both"), (dict(angles=[]), "angles"),
    (dict(stack=[]), "stack"), (dict(stack=[(1.5,)]), r"stack\[0\]"),
    (dict(stack="glass:100"), "stack"),
])
def test_thinfilm_errors_name_the_argument(kw, words):
    with pytest.raises(ValueError, match=words):
        ophis.thinfilm(**kw)


def parse_bsdf(out):
    """`ophis bsdf` lines `  NAME V ± E` → [(V, E)]."""
    vals = []
    for line in out.splitlines():
        if "±" in line:
            head, err = line.split("±")
            vals.append((float(head.split()[-1]), float(err)))
    return vals


# The scene declares three BSDFs and uses one: the other two's parameters are "never used".
@pytest.mark.filterwarnings("ignore::ophis.SceneWarning")
def test_bsdf_estimates_match_the_cli(cli, root):
    xml = root / "scenes" / "layered-skin.xml"
    scene = ophis.load_file(xml, closed="false")
    cases = [
        (ophis.bsdf_albedo(scene, "skin", theta_i=45, wavelengths=[450, 650], samples=4000,
                           seed=7),
         ["--albedo", "--theta-i", "45", "--lambda", "450,650", "--samples", "4000", "--seed",
          "7"]),
        (ophis.bsdf_eval(scene, "rough", theta_i=30, theta_o=60, samples=3000),
         ["--eval", "--theta-i", "30", "--theta-o", "60", "--samples", "3000"]),
    ]
    for est, args in cases:
        bsdf_id = "skin" if args[0] == "--albedo" else "rough"
        want = parse_bsdf(cli("bsdf", xml, "-D", "closed=false", "--id", bsdf_id, *args))
        assert len(want) == len(est.mean)
        for (m, e), got_m, got_e in zip(want, est.mean, est.std_err):
            assert got_m == pytest.approx(m, abs=5e-7) and got_e == pytest.approx(e, abs=5e-7)
    assert cases[1][0].wavelengths is None and cases[1][0].mean.shape == (3,)


@pytest.mark.filterwarnings("ignore::ophis.SceneWarning")
def test_bsdf_errors(root):
    scene = ophis.load_file(root / "scenes" / "layered-skin.xml")
    with pytest.raises(ValueError, match="ids: skin, rough, pigment"):
        ophis.bsdf_albedo(scene, "nope")
    with pytest.raises(ValueError, match="samples"):
        ophis.bsdf_albedo(scene, "skin", samples=1)
    with pytest.raises(ValueError, match="wavelengths"):
        ophis.bsdf_eval(scene, "skin", wavelengths=[-5])
