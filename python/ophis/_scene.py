"""Loading scenes: Mitsuba XML files and strings, Mitsuba 3 dictionaries, the built-in scene."""

from __future__ import annotations

import os
import warnings
from typing import Any, Optional

from . import _ophis
from ._dict import DictError, relocate, to_xml

SceneError = _ophis.SceneError
try:  # shows as ophis.SceneError in tracebacks
    SceneError.__module__ = "ophis"
except (AttributeError, TypeError):
    pass


class SceneWarning(UserWarning):
    """Something suspicious in a scene that does not stop it loading: an unknown plugin, a
    parameter nothing read. The message starts with ``file:line:column``."""


class Scene:
    """A loaded scene, ready to :func:`ophis.render`.

    Attributes:
        width, height: the image size in pixels.
        spp: the sampler's samples per pixel (what ``render(scene)`` takes).
        name: the scene's file name and ``-D`` values, as written in EXR headers.
        scene_hash: the ``ophis.scene_hash`` of its renders (``ophis merge`` compares it).
        last_render: the :class:`ophis.RenderResult` of the latest render, kept also when the
            render was interrupted; ``None`` before the first.
    """

    def __init__(self, native: Any):
        self._native = native
        self.last_render = None

    width = property(lambda self: self._native.width)
    height = property(lambda self: self._native.height)
    spp = property(lambda self: self._native.spp)
    name = property(lambda self: self._native.name)
    scene_hash = property(lambda self: self._native.scene_hash)

    def __repr__(self) -> str:
        return (f"<ophis.Scene {self.name!r}: {self.width}×{self.height}, {self.spp} spp, "
                f"hash {self.scene_hash}>")


def _define_text(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        return repr(v)
    return str(v)


def _defines(defines: dict[str, Any]) -> list[tuple[str, str]]:
    return [(k, _define_text(v)) for k, v in defines.items()]


def _finish(result: tuple, paths: Optional[list[str]] = None) -> Scene:
    native, found = result
    for file, line, col, message in found:
        if paths is not None and file == "<dict>":
            text = relocate(f"<dict>:{line}:{col}: {message}", paths)
        else:
            text = f"{file}:{line}:{col}: {message}"
        warnings.warn(text, SceneWarning, stacklevel=3)
    return Scene(native)


def load_file(path: str | os.PathLike, **defines: Any) -> Scene:
    """Loads a Mitsuba XML scene file (3.x or 0.6 dialect).

    ``defines`` fill ``$name`` parameters and override ``<default>`` values, as Mitsuba's
    ``-D name=value`` (``ophis.load_file("snake.xml", thickness=320)``).

    Raises:
        SceneError: the scene is malformed; ``file``, ``line``, ``column`` say where.
        FileNotFoundError: the file does not exist.
    Warnings (:class:`SceneWarning`) report unknown plugins and unused parameters.
    """
    return _finish(_ophis.load_file(os.fspath(path), _defines(defines)))


def load_string(xml: str, name: str = "<string>", **defines: Any) -> Scene:
    """Loads a scene from Mitsuba XML text; ``name`` stands for the file in messages, and
    relative paths (meshes, textures) are taken from the current directory."""
    return _finish(_ophis.load_string(xml, name, _defines(defines)))


def load_xenopeltis(**defines: Any) -> Scene:
    """Loads the built-in flagship scene, the sunbeam snake (``scenes/xenopeltis.xml``).

    Its parameters include ``width``, ``height``, ``spp``, ``thickness``, ``spread``, ``tilt``,
    ``hour`` and ``exposure``: ``load_xenopeltis(width=320, height=180, spp=16)`` is a preview.
    """
    return _finish(_ophis.load_xenopeltis(_defines(defines)))


def load_dict(scene: dict) -> Scene:
    """Loads a scene given in Mitsuba 3's dictionary form::

        ophis.load_dict({
            "type": "scene",
            "sensor": {"type": "perspective", "fov": 40,
                       "to_world": ophis.Transform.look_at(origin=[0, 0, 4], target=[0, 0, 0],
                                                           up=[0, 1, 0]),
                       "film": {"type": "hdrfilm", "width": 64, "height": 64}},
            "red": {"type": "diffuse", "reflectance": {"type": "rgb", "value": [0.8, 0.1, 0.1]}},
            "ball": {"type": "sphere", "bsdf": {"type": "ref", "id": "red"}},
            "sky": {"type": "constant"},
        })

    Errors and warnings name the dictionary path (``scene['ball']['bsdf']``) rather than a
    line of the XML it is turned into (see ``ophis._dict`` for the conversions).
    """
    try:
        xml, paths = to_xml(scene)
    except DictError as e:
        raise _dict_error(e.path, e.message) from None
    try:
        result = _ophis.load_string(xml, "<dict>", [])
    except SceneError as e:
        if getattr(e, "file", None) != "<dict>":
            raise
        line = e.line
        path = paths[line - 1] if 1 <= line <= len(paths) else "scene"
        raise _dict_error(path, relocate(e.message, paths)) from None
    return _finish(result, paths)


def _dict_error(path: str, message: str) -> SceneError:
    e = SceneError(f"{path}: {message}")
    e.file, e.line, e.column, e.message, e.path = "<dict>", 0, 0, message, path
    return e
