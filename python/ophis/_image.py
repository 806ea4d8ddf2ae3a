"""Images: writing EXR and PNG, reading them back with ophis's sample counts."""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from typing import Any, Mapping, Optional, Union

import numpy as np

from . import _ophis
from ._render import RenderResult


@dataclass
class ImageInfo:
    """What an image's header says about the render that made it (EXR; PNGs carry nothing).

    Attributes:
        spp: samples every pixel received (``ophis.spp``).
        samples: total samples (``ophis.samples``).
        pixel_spp: H × W uint64, the samples of each pixel (from ``ophis.tile_spp``).
        seeds: the seed, or the seeds of a merged image (``ophis.seed``).
        scene: the scene's file name and ``-D`` values (``ophis.scene``).
        scene_hash: ``ophis.scene_hash``, which ``ophis merge`` compares.
        metadata: every text attribute of the header.
    """

    spp: Optional[int] = None
    samples: Optional[int] = None
    pixel_spp: Optional[np.ndarray] = None
    seeds: Optional[tuple[int, ...]] = None
    scene: Optional[str] = None
    scene_hash: Optional[str] = None
    metadata: dict[str, str] = field(default_factory=dict)


def write(path: Union[str, os.PathLike], image: Union[np.ndarray, RenderResult],
          metadata: Optional[Mapping[str, Any]] = None) -> None:
    """Writes an image: ``.exr`` (float32 linear RGB, ``metadata`` as header text attributes)
    or ``.png`` (sRGB-encoded, 8 bit, clipped to [0, 1]).

    ``image`` is H × W × 3 (or H × W, written as grey), or a :class:`RenderResult`, whose
    header (sample counts, seed, scene identity) then goes into the EXR so that the file
    merges with others by ``ophis merge``. ``metadata`` entries are added to (or replace)
    those; names and values must be Latin-1 text.
    """
    header: dict[str, str] = {}
    extra_names: list[str] = []
    extra = b""
    if isinstance(image, RenderResult):
        header.update(image.metadata)
        # AOV channels go into an EXR beside R, G, B under their names (a PNG holds RGB).
        extra_names = list(image.channels[3:])
        if extra_names and os.fspath(path).lower().endswith(".exr"):
            planes = np.moveaxis(np.asarray(image.image[..., 3:], dtype=np.float32), 2, 0)
            extra = np.ascontiguousarray(planes).tobytes()
        else:
            extra_names = []
        image = image.image[..., :3]
    if metadata:
        header.update({str(k): str(v) for k, v in metadata.items()})
    for k, v in header.items():
        try:
            k.encode("latin-1"), v.encode("latin-1")
        except UnicodeEncodeError:
            raise ValueError(f"metadata {k!r}: {v!r}: EXR header text must be Latin-1") \
                from None
    a = np.asarray(image)
    if a.ndim == 2:
        a = np.repeat(a[:, :, None], 3, axis=2)
    if a.ndim != 3 or a.shape[2] != 3:
        raise ValueError(f"expected an H × W × 3 (or H × W) image, got shape {a.shape}; "
                         "for images with extra channels write image[..., :3]")
    if not np.issubdtype(a.dtype, np.number) or np.issubdtype(a.dtype, np.complexfloating):
        raise ValueError(f"expected real numbers, got an array of {a.dtype}")
    h, w, _ = a.shape
    if h == 0 or w == 0:
        raise ValueError(f"cannot write an empty image ({w} × {h})")
    data = np.ascontiguousarray(a, dtype=np.float32).tobytes()
    _ophis.write(os.fspath(path), w, h, data, list(header.items()), extra_names, extra)


def read(path: Union[str, os.PathLike]) -> tuple[np.ndarray, ImageInfo]:
    """Reads an EXR, Radiance HDR or PNG image as H × W × 3 float32 linear RGB, with what its
    header says about its samples (an :class:`ImageInfo`; empty for PNG and HDR)."""
    w, h, data, meta, counts = _ophis.read(os.fspath(path))
    image = np.frombuffer(data, dtype=np.float32).reshape(h, w, 3)
    m = dict(meta)

    def number(key: str) -> Optional[int]:
        v = m.get(key)
        return int(v) if v is not None and v.isdigit() else None

    seeds = m.get("ophis.seed")
    try:
        seed_tuple = tuple(int(s) for s in seeds.split(",")) if seeds else None
    except ValueError:
        seed_tuple = None
    info = ImageInfo(
        spp=number("ophis.spp"),
        samples=number("ophis.samples"),
        pixel_spp=None if counts is None
        else np.frombuffer(counts, dtype=np.uint64).reshape(h, w),
        seeds=seed_tuple,
        scene=m.get("ophis.scene"),
        scene_hash=m.get("ophis.scene_hash"),
        metadata=m,
    )
    return image, info
