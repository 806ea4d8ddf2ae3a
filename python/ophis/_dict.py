"""Mitsuba 3's dictionary scene form, turned into Mitsuba XML for the library's loader.

The XML is generated one element per line, and the dictionary path of each line is kept, so
that an error the loader reports at ``<dict>:LINE:COL`` is re-raised naming the path
(``scene['sphere']['bsdf']['reflectance']``) instead of a line nobody can see. Going through
the XML loader means a dictionary scene gets exactly the plugins, parameter checks and
warnings that a file gets.

Conversions (as Mitsuba 3's ``load_dict``):

=====================================  ================================================
dictionary value                        XML
=====================================  ================================================
``{"type": "diffuse", ...}``            a nested object; its tag (``bsdf``) from its type
``{"type": "rgb", "value": [r,g,b]}``   ``<rgb>`` (``"srgb"`` likewise)
``{"type": "spectrum", "value": v}``    ``<spectrum>``: a number, ``[(λ, v), ...]`` pairs,
                                        or ``"filename"``
``{"type": "blackbody", ...}``          ``<blackbody temperature= scale=>``
``{"type": "ref", "id": "x"}``          ``<ref id="x">``
``bool`` / ``int`` / ``float`` / str    ``<boolean>`` / ``<integer>`` / ``<float>`` /
                                        ``<string>``
three numbers                           ``<point>``
4×4 numbers, ``Transform``, or any      ``<transform>`` (a ``<matrix>``, or the
object with a 4×4 ``.matrix``           ``Transform``'s operations)
=====================================  ================================================

Objects at the top level take their key as ``id`` (unless they give ``"id"``), so that
``{"type": "ref", "id": key}`` finds them; nested objects take their key as ``name``.
A ``$`` in a string is read as a ``$parameter``, as in XML files.
"""

from __future__ import annotations

import numbers
import re
from typing import Any, Iterable, Sequence
from xml.sax.saxutils import quoteattr

# Plugin type -> XML tag, for the plugins ophis has (and common Mitsuba ones it reports as
# unsupported, so that the message is about the plugin, not about a missing tag).
_TAGS: dict[str, Iterable[str]] = {
    "shape": ("sphere disk rectangle cube obj ply torus snake serialized cylinder "
              "shapegroup instance"),
    "bsdf": ("diffuse dielectric thindielectric roughdielectric conductor roughconductor "
             "plastic roughplastic twosided null bumpmap normalmap thinfilm roughthinfilm "
             "thinfilmconductor roughthinfilmconductor multilayered absorption Absorption "
             "dielectricThinFilm roughdielectricThinFilm conductorThinFilm principled "
             "blendbsdf mask"),
    "emitter": "area point directional constant envmap sunsky sun sky spot projector",
    "texture": "bitmap checkerboard scales reptileSkin reptile_skin per_scale",
    "sensor": "perspective thinlens orthographic radiancemeter irradiancemeter",
    "film": "hdrfilm specfilm",
    "sampler": "independent stratified multijitter ldsampler orthogonal sobol",
    "rfilter": "box tent gaussian mitchell catmullrom lanczos",
    "integrator": "path direct volpath volpathmis aov ptracer moment depth",
    "phase": "isotropic hg",
    "medium": "homogeneous heterogeneous",
}
TAG_OF: dict[str, str] = {p: tag for tag, ps in _TAGS.items() for p in ps.split()}
_TAG_NAMES = set(_TAGS)
_VALUE_TYPES = {"rgb", "srgb", "spectrum", "blackbody", "ref"}


class DictError(ValueError):
    """A dictionary that is not a scene; ``path`` is where (``scene['a']['b']``)."""

    def __init__(self, path: str, message: str):
        super().__init__(f"{path}: {message}")
        self.path = path
        self.message = message


class Transform:
    """A transform in Mitsuba's style, for ``to_world`` and the like.

    ``Transform().translate([0, 0, 1]).rotate([0, 1, 0], 90)`` is ``T · R``: the rotation is
    applied to points first, as with ``mi.ScalarTransform4f``. The methods work on the class
    too (``Transform.look_at(origin=..., target=..., up=...)``). A ``Transform`` holds XML
    operations, so ophis's own ``lookat`` and ``rotate`` conventions apply exactly.
    """

    def __init__(self, matrix: Any = None):
        # Operations in the order they apply to a point (XML document order).
        self._ops: list[tuple[str, dict[str, str]]] = []
        if matrix is not None:
            self._ops.append(("matrix", {"value": _matrix_text(matrix, "matrix")}))

    def _then(self, op: str, attrs: dict[str, str]) -> "Transform":
        t = Transform()
        t._ops = [(op, attrs)] + self._ops
        return t

    def translate(self, v: Sequence[float]) -> "Transform":
        """``self · translate(v)``."""
        return self._then("translate", {"value": _vec_text(v, "translate")})

    def scale(self, v: float | Sequence[float]) -> "Transform":
        """``self · scale(v)``; ``v`` is one factor or three."""
        text = _num(v, "scale") if isinstance(v, numbers.Real) else _vec_text(v, "scale")
        return self._then("scale", {"value": text})

    def rotate(self, axis: Sequence[float], angle: float) -> "Transform":
        """``self · rotate(axis, angle)``, the angle in degrees."""
        return self._then("rotate", {"value": _vec_text(axis, "rotate"),
                                     "angle": _num(angle, "rotate")})

    def look_at(self, origin: Sequence[float], target: Sequence[float],
                up: Sequence[float]) -> "Transform":
        """``self · look_at(origin, target, up)``: a camera at ``origin`` facing ``target``."""
        return self._then("lookat", {"origin": _vec_text(origin, "look_at"),
                                     "target": _vec_text(target, "look_at"),
                                     "up": _vec_text(up, "look_at")})

    def __repr__(self) -> str:
        return "Transform(" + ", ".join(f"{op}{attrs}" for op, attrs in self._ops) + ")"


class _Hybrid:
    """Lets ``Transform.translate(v)`` (on the class) mean ``Transform().translate(v)``."""

    def __init__(self, f):
        self.f = f
        self.__doc__ = f.__doc__

    def __get__(self, obj, cls):
        target = obj if obj is not None else cls()
        return self.f.__get__(target, cls)


for _name in ("translate", "scale", "rotate", "look_at"):
    setattr(Transform, _name, _Hybrid(getattr(Transform, _name)))


def _num(x: Any, path: str) -> str:
    if isinstance(x, bool) or not isinstance(x, numbers.Real):
        raise DictError(path, f"expected a number, found {x!r}")
    return repr(float(x))


def _vec_text(v: Any, path: str) -> str:
    try:
        items = list(v)
    except TypeError:
        raise DictError(path, f"expected three numbers, found {v!r}") from None
    if len(items) != 3:
        raise DictError(path, f"expected three numbers, found {len(items)}: {v!r}")
    return ", ".join(_num(x, path) for x in items)


def _matrix_rows(m: Any) -> list[list[Any]] | None:
    """The rows of a 4×4 matrix given as nested sequences (lists, numpy), else None."""
    if hasattr(m, "matrix") and not isinstance(m, (list, tuple)):
        m = m.matrix  # mi.ScalarTransform4f and friends
    if hasattr(m, "tolist"):
        m = m.tolist()
    try:
        rows = [list(r) for r in m]
    except TypeError:
        return None
    if len(rows) == 4 and all(len(r) == 4 for r in rows):
        return rows
    return None


def _matrix_text(m: Any, path: str) -> str:
    rows = _matrix_rows(m)
    if rows is None:
        raise DictError(path, f"expected a 4×4 matrix, found {m!r}")
    return " ".join(_num(x, path) for r in rows for x in r)


def _is_vec3(v: Any) -> bool:
    if isinstance(v, (str, bytes, dict)):
        return False
    try:
        items = list(v)
    except TypeError:
        return False
    return len(items) == 3 and all(
        isinstance(x, numbers.Real) and not isinstance(x, bool) for x in items)


class _Writer:
    """Accumulates XML lines and the dictionary path of each."""

    def __init__(self):
        self.lines: list[str] = []
        self.paths: list[str] = []

    def line(self, depth: int, text: str, path: str) -> None:
        self.lines.append("    " * depth + text)
        self.paths.append(path)


def _attrs(**kv: str | None) -> str:
    return "".join(f" {k}={quoteattr(v)}" for k, v in kv.items() if v is not None)


def to_xml(scene: dict) -> tuple[str, list[str]]:
    """The XML text of a scene dictionary, and the dictionary path of each of its lines."""
    root = "scene"
    if not isinstance(scene, dict):
        raise DictError(root, f"expected a dict, found {type(scene).__name__}")
    if scene.get("type") != "scene":
        raise DictError(root, "expected 'type': 'scene' at the top level, found "
                        f"{scene.get('type')!r}")
    w = _Writer()
    w.line(0, '<scene version="3.0.0">', root)
    for key, value in scene.items():
        if key == "type":
            continue
        path = f"{root}[{key!r}]"
        _check_key(key, root)
        if not (isinstance(value, dict) and "type" in value):
            raise DictError(path, "expected an object (a dict with a 'type'), found "
                            f"{_what(value)}")
        if value["type"] in _VALUE_TYPES:
            raise DictError(path, f"a '{value['type']}' value belongs inside an object, "
                            "not at the top level of the scene")
        _object(w, 1, key, value, path, top=True)
    w.line(0, "</scene>", root)
    return "\n".join(w.lines) + "\n", w.paths


def _check_key(key: Any, path: str) -> None:
    if not isinstance(key, str) or not key:
        raise DictError(path, f"keys must be non-empty strings, found {key!r}")


def _what(v: Any) -> str:
    if isinstance(v, dict):
        return "a dict without 'type'"
    return f"{type(v).__name__} {v!r}"


def _object(w: _Writer, depth: int, key: str, d: dict, path: str, top: bool) -> None:
    plugin = d["type"]
    if not isinstance(plugin, str):
        raise DictError(f"{path}['type']", f"expected a plugin name, found {plugin!r}")
    tag = TAG_OF.get(plugin) or (key if key in _TAG_NAMES else None)
    if tag is None:
        known = ", ".join(sorted(TAG_OF))
        raise DictError(path, f"unknown plugin type '{plugin}' (ophis knows: {known})")
    ident = d.get("id", key if top else None)
    if ident is not None and not isinstance(ident, str):
        raise DictError(f"{path}['id']", f"expected a string, found {ident!r}")
    name = None if top else key
    w.line(depth, f"<{tag}{_attrs(type=plugin, id=ident, name=name)}>", path)
    for k, v in d.items():
        if k in ("type", "id"):
            continue
        _check_key(k, path)
        _property(w, depth + 1, k, v, f"{path}[{k!r}]")
    w.line(depth, f"</{tag}>", path)


def _property(w: _Writer, depth: int, name: str, v: Any, path: str) -> None:
    a = lambda **kv: _attrs(name=name, **kv)  # noqa: E731
    if isinstance(v, dict):
        if "type" not in v:
            raise DictError(path, "expected a dict with a 'type', found one without")
        t = v["type"]
        if t in ("rgb", "srgb"):
            _only(v, path, "value")
            val = v.get("value")
            text = _num(val, path) if isinstance(val, numbers.Real) else _vec_text(val, path)
            w.line(depth, f"<{t}{a(value=text)}/>", path)
        elif t == "spectrum":
            _only(v, path, "value", "filename")
            w.line(depth, f"<spectrum{a(**_spectrum(v, path))}/>", path)
        elif t == "blackbody":
            _only(v, path, "temperature", "scale")
            if "temperature" not in v:
                raise DictError(path, "a blackbody needs 'temperature' (kelvin)")
            scale = _num(v["scale"], path) if "scale" in v else None
            w.line(depth, f"<blackbody{a(temperature=_num(v['temperature'], path), scale=scale)}/>",
                   path)
        elif t == "ref":
            _only(v, path, "id")
            if not isinstance(v.get("id"), str):
                raise DictError(path, "a ref needs 'id', the id of an object to refer to")
            w.line(depth, f"<ref{a(id=v['id'])}/>", path)
        else:
            _object(w, depth, name, v, path, top=False)
    elif isinstance(v, bool):
        w.line(depth, f"<boolean{a(value='true' if v else 'false')}/>", path)
    elif isinstance(v, numbers.Integral):
        w.line(depth, f"<integer{a(value=str(int(v)))}/>", path)
    elif isinstance(v, numbers.Real):
        w.line(depth, f"<float{a(value=repr(float(v)))}/>", path)
    elif isinstance(v, str):
        w.line(depth, f"<string{a(value=v)}/>", path)
    elif isinstance(v, Transform):
        w.line(depth, f"<transform{a()}>", path)
        for op, attrs in v._ops:
            w.line(depth + 1, f"<{op}{_attrs(**attrs)}/>", path)
        w.line(depth, "</transform>", path)
    elif _is_vec3(v):
        w.line(depth, f"<point{a(value=_vec_text(v, path))}/>", path)
    elif _matrix_rows(v) is not None:
        w.line(depth, f"<transform{a()}>", path)
        w.line(depth + 1, f"<matrix{_attrs(value=_matrix_text(v, path))}/>", path)
        w.line(depth, "</transform>", path)
    else:
        raise DictError(path, f"cannot express {_what(v)} in a scene: expected a number, "
                        "string, bool, three numbers, a 4×4 matrix or transform, or a dict "
                        "with a 'type'")


def _only(d: dict, path: str, *allowed: str) -> None:
    for k in d:
        if k != "type" and k not in allowed:
            raise DictError(f"{path}[{k!r}]", f"a '{d['type']}' takes only "
                            f"{', '.join(repr(x) for x in allowed)}")


def _spectrum(v: dict, path: str) -> dict[str, str]:
    if ("value" in v) == ("filename" in v):
        raise DictError(path, "a spectrum needs exactly one of 'value' and 'filename'")
    if "filename" in v:
        return {"filename": str(v["filename"])}
    val = v["value"]
    if isinstance(val, numbers.Real) and not isinstance(val, bool):
        return {"value": _num(val, path)}
    try:
        pairs = [tuple(p) for p in val]
    except TypeError:
        raise DictError(path, f"expected a number or (wavelength, value) pairs, found {val!r}") \
            from None
    if not pairs or any(len(p) != 2 for p in pairs):
        raise DictError(path, f"expected (wavelength, value) pairs, found {val!r}")
    return {"value": ", ".join(f"{_num(l, path)}:{_num(x, path)}" for l, x in pairs)}


_LOC = re.compile(r"<dict>:(\d+):(\d+)")


def relocate(message: str, paths: list[str]) -> str:
    """Replaces every ``<dict>:LINE:COL`` in a loader message by the dictionary path."""
    def sub(m: re.Match) -> str:
        line = int(m.group(1))
        return paths[line - 1] if 1 <= line <= len(paths) else m.group(0)
    return _LOC.sub(sub, message)
