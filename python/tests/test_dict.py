"""Mitsuba 3's dictionary form: the same scene as XML, errors that name the dictionary path."""

import warnings

import numpy as np
import pytest

import ophis
from ophis import Transform


def rgb(*v):
    return {"type": "rgb", "value": list(v)}


def reference_dict():
    """tests/data/reference.xml, written as a Mitsuba 3 dictionary."""
    return {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": 6},
        "sensor": {
            "type": "perspective",
            "fov": 40.0,
            "to_world": Transform.look_at(origin=[0, 1.0, 4.2], target=[0, 0.35, 0],
                                          up=[0, 1, 0]),
            "sampler": {"type": "independent", "sample_count": 64},
            "film": {"type": "hdrfilm", "width": 64, "height": 48,
                     "rfilter": {"type": "box"}},
        },
        "sky": {"type": "constant", "radiance": rgb(0.15, 0.18, 0.25)},
        "floor": {"type": "rectangle",
                  "to_world": Transform().rotate([1, 0, 0], -90).scale(4),
                  "bsdf": {"type": "diffuse", "reflectance": rgb(0.6, 0.55, 0.45)}},
        "gold": {"type": "sphere", "center": [-0.75, 0.45, 0], "radius": 0.45,
                 "bsdf": {"type": "roughconductor", "material": "Au",
                          "distribution": "ggx", "alpha": 0.2}},
        "glass": {"type": "sphere", "center": [0.3, 0.45, 0.2], "radius": 0.45,
                  "bsdf": {"type": "dielectric", "int_ior": 1.5}},
        "box": {"type": "cube",
                "to_world": Transform().translate([1.2, 0.3, -0.5]).rotate([0, 1, 0], 30)
                .scale(0.3),
                "bsdf": {"type": "roughplastic", "diffuse_reflectance": rgb(0.1, 0.3, 0.6),
                         "alpha": 0.15}},
        "lamp": {"type": "rectangle",
                 "to_world": Transform().translate([0, 2.5, 0.5]).rotate([1, 0, 0], 90)
                 .scale(0.6),
                 "emitter": {"type": "area", "radiance": rgb(8, 7, 6)}},
    }


def test_dict_renders_exactly_as_the_xml(reference_xml):
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no unused parameters, no unknown plugins
        d = ophis.load_dict(reference_dict())
    x = ophis.load_file(reference_xml)
    assert (d.width, d.height, d.spp) == (64, 48, 64)
    a = ophis.render(d, spp=2, progress=False)
    b = ophis.render(x, spp=2, progress=False)
    assert np.array_equal(a, b)
    assert d.name == "<dict>"


def test_refs_ids_spectra_and_matrices():
    m = np.eye(4)
    m[:3, 3] = [0, 0, -3]

    class MitsubaLike:  # like mi.ScalarTransform4f: a .matrix of 4 × 4 numbers
        matrix = m.tolist()

    base = {
        "type": "scene",
        "camera": {"type": "perspective",
                   "to_world": Transform.look_at(origin=[0, 0, 2], target=[0, 0, -3],
                                                 up=[0, 1, 0]),
                   "film": {"type": "hdrfilm", "width": 16, "height": 16}},
        "red": {"type": "diffuse", "reflectance": {"type": "spectrum",
                                                   "value": [(400, 0.1), (700, 0.9)]}},
        "ball": {"type": "sphere", "to_world": m, "bsdf": {"type": "ref", "id": "red"}},
        "sun": {"type": "directional", "direction": [0, -1, -1],
                "irradiance": {"type": "blackbody", "temperature": 5800}},
    }
    s1 = ophis.load_dict(base)
    s2 = ophis.load_dict({**base, "ball": {**base["ball"], "to_world": MitsubaLike()}})
    s3 = ophis.load_dict({**base, "ball": {**base["ball"],
                                           "to_world": Transform.translate([0, 0, -3])}})
    imgs = [ophis.render(s, spp=1, progress=False) for s in (s1, s2, s3)]
    assert imgs[0].max() > 0
    assert np.array_equal(imgs[0], imgs[1]) and np.array_equal(imgs[0], imgs[2])
    e = ophis.bsdf_albedo(s1, "red", wavelengths=[400, 700], samples=100)
    assert e.mean == pytest.approx([0.1, 0.9], rel=1e-5)


def test_transform_composes_like_mitsuba():
    # T · R · S: scale first, then rotate, then translate.
    t = Transform().translate([1, 2, 3]).rotate([0, 0, 1], 90).scale(2)
    assert [op for op, _ in t._ops] == ["scale", "rotate", "translate"]
    assert [op for op, _ in Transform.scale(2)._ops] == ["scale"]


@pytest.mark.parametrize("scene, path, words", [
    ({"type": "scene", "ball": {"type": "sphere", "radius": -1.0}},
     "scene['ball']['radius']", "positive"),
    ({"type": "scene", "ball": {"type": "sphere", "bsdf": {"type": "diffuse",
                                                            "reflectance": rgb(1, 2)}}},
     "scene['ball']['bsdf']['reflectance']", "three numbers"),
    ({"type": "scene", "ball": {"type": "sphere", "bsdf": {"type": "ref", "id": "nope"}}},
     "scene['ball']['bsdf']", "nope"),
    ({"type": "scene", "ball": {"type": "blob"}}, "scene['ball']", "unknown plugin type 'blob'"),
    ({"type": "scene", "ball": {"type": "sphere", "radius": None}},
     "scene['ball']['radius']", "NoneType"),
    ({"type": "scene", "ball": 3}, "scene['ball']", "expected an object"),
    ({"type": "scene", "ball": {"type": "sphere", "bsdf": {"reflectance": 0.5}}},
     "scene['ball']['bsdf']", "'type'"),
    ({"type": "bsdf"}, "scene", "'type': 'scene'"),
    ({"type": "scene", "ball": {"type": "sphere", "to_world": [[1, 0], [0, 1]]}},
     "scene['ball']['to_world']", "cannot express"),
    ({"type": "scene", "ball": {"type": "sphere", "center": [0, 0, float("nan")]}},
     "scene['ball']['center']", "nan"),
])
def test_errors_name_the_dict_path(scene, path, words):
    with pytest.raises(ophis.SceneError) as e:
        ophis.load_dict(scene)
    msg = str(e.value)
    assert msg.startswith(path + ":"), msg
    assert words.lower() in msg.lower(), msg
    assert "<dict>:" not in msg
    assert e.value.path == path


def test_warnings_name_the_dict_path():
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        ophis.load_dict({"type": "scene", "sky": {"type": "constant"},
                         "ball": {"type": "sphere", "radiuss": 1.0}})
    msgs = [str(x.message) for x in w if issubclass(x.category, ophis.SceneWarning)]
    assert any(m.startswith("scene['ball']['radiuss']") for m in msgs), msgs
