"""ophis — a spectral path tracer for structural colour (thin-film iridescence, layered
materials), reading Mitsuba XML scenes; the library itself, not a wrapper of the command line.

>>> import ophis
>>> scene = ophis.load_file("scenes/cornell-box.xml")
>>> image = ophis.render(scene, spp=16)            # H × W × 3 float32, linear sRGB
>>> ophis.write("box.exr", scene.last_render)      # with sample counts: merges with `ophis merge`
>>> film = ophis.thinfilm(thickness=300, angles=[0, 30, 60])
>>> film.R.shape                                   # wavelengths × angles
(81, 3)

Loading: :func:`load_file`, :func:`load_string`, :func:`load_dict` (Mitsuba 3's dictionary
form, with :class:`Transform`), :func:`load_xenopeltis`. Rendering: :func:`render`, keeping a
:class:`RenderResult` as ``scene.last_render``. Images: :func:`write`, :func:`read`. Optics:
:func:`thinfilm`, :func:`bsdf_albedo`, :func:`bsdf_eval`. Errors: :class:`SceneError` (a
``ValueError`` with ``file``, ``line``, ``column``), :class:`SceneWarning`.
"""

from ._dict import Transform
from ._image import ImageInfo, read, write
from ._optics import Estimate, ThinFilm, bsdf_albedo, bsdf_eval, thinfilm
from ._render import RenderResult, render
from ._scene import (Scene, SceneError, SceneWarning, load_dict, load_file, load_string,
                     load_xenopeltis)

__version__ = "0.1.0"

__all__ = [
    "Estimate", "ImageInfo", "RenderResult", "Scene", "SceneError", "SceneWarning",
    "ThinFilm", "Transform", "bsdf_albedo", "bsdf_eval", "load_dict", "load_file",
    "load_string", "load_xenopeltis", "read", "render", "thinfilm", "write",
]
