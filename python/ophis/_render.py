"""Rendering: the image as a numpy array, a progress bar, and Ctrl-C that keeps the samples."""

from __future__ import annotations

import sys
import time
from dataclasses import dataclass, field
from typing import Callable, Optional, Union

import numpy as np

from . import _ophis
from ._scene import Scene

ProgressFn = Callable[[int, int], None]


@dataclass
class RenderResult:
    """One render: the image and what the EXR header of ``ophis render`` would hold.

    Attributes:
        image: H × W × C float32, linear sRGB; C = 3 (R, G, B). Channels that a scene asks
            for beyond RGB (AOVs) will follow R, G, B, named in ``channels``.
        channels: the name of each channel.
        spp: samples every pixel received; after an interruption some 32 × 32 tiles hold one
            pass more (see ``metadata['ophis.tile_spp']``).
        samples: total samples taken.
        seconds: wall-clock time of the render.
        seed: the seed of the sample sequences.
        interrupted: the render stopped early (Ctrl-C, or an exception from ``progress``).
        metadata: the EXR header (``ophis.spp``, ``ophis.samples``, ``ophis.tile_spp``,
            ``ophis.seed``, ``ophis.scene``, ``ophis.scene_hash``); ``ophis.write(path,
            result)`` writes it, so the file merges with ``ophis merge``.
    """

    image: np.ndarray
    channels: tuple[str, ...]
    spp: int
    samples: int
    seconds: float
    seed: int
    interrupted: bool
    metadata: dict[str, str] = field(default_factory=dict)


class _TextBar:
    """A small progress bar on stderr, for when tqdm is not installed."""

    def __init__(self):
        self.t0 = time.monotonic()
        self.last = 0.0
        self.finished = False

    def __call__(self, done: int, total: int) -> None:
        now = time.monotonic()
        if self.finished or (done < total and now - self.last < 0.5):
            return
        self.finished = done >= total
        self.last = now
        frac = done / total if total else 1.0
        n = int(30 * frac)
        elapsed = now - self.t0
        eta = elapsed * (1 - frac) / frac if frac > 0 else float("nan")
        sys.stderr.write(f"\r[{'=' * n}{' ' * (30 - n)}] {100 * frac:5.1f}%  "
                         f"{elapsed:6.1f} s, ETA {eta:6.1f} s")
        if done >= total:
            sys.stderr.write("\n")
        sys.stderr.flush()


def _bar() -> tuple[ProgressFn, Callable[[], None]]:
    """A progress callback and the function that closes it: tqdm's bar where installed
    (in a notebook, its widget), else a text bar on stderr."""
    try:
        from tqdm.auto import tqdm
    except ImportError:
        return _TextBar(), lambda: None
    bar = tqdm(total=1, unit="sample", unit_scale=True, leave=False, desc="ophis")

    def update(done: int, total: int) -> None:
        if bar.total != total:
            bar.total = total
        bar.update(done - bar.n)

    return update, bar.close


def render(scene: Scene, spp: Optional[int] = None, seed: int = 0,
           threads: Optional[int] = None,
           progress: Union[bool, ProgressFn, None] = True,
           adaptive: Optional[bool] = None) -> np.ndarray:
    """Renders a scene and returns its image, H × W × 3 float32 linear sRGB.

    Args:
        scene: from :func:`ophis.load_file` and friends.
        spp: samples per pixel; the scene's sampler's ``sample_count`` without it.
        seed: seed of the sample sequences (replaces the sampler's ``seed``, as Mitsuba's
            ``mi.render``). Renders with different seeds are independent and merge.
        threads: worker threads; all cores without it. The image does not depend on it.
        progress: ``True`` for a progress bar (tqdm's where installed, else text on stderr),
            ``False`` for none, or a function called with (samples done, samples in all)
            about ten times a second from the calling thread.
        adaptive: ``True`` spends the same samples unevenly, more where neighbouring pixels
            are noisy (``ophis render --adaptive on``; README, "Adaptive sampling"), ``False``
            evenly; without it, as the scene's sampler says (the built-in scene: adaptive).

    The GIL is released while rendering. Ctrl-C (KeyboardInterrupt) stops the render once the
    tiles in flight finish: the image of the samples taken, each pixel normalised by its own
    count, is stored as ``scene.last_render`` (a :class:`RenderResult`, ``interrupted=True``),
    then the KeyboardInterrupt is raised again. An exception raised by ``progress`` stops it
    the same way. Every render, finished or not, is kept as ``scene.last_render``.

    The same scene, spp and seed give the same image bit for bit, whatever ``threads``.
    """
    if not isinstance(scene, Scene):
        raise TypeError(f"render expects an ophis.Scene, got {type(scene).__name__}")
    if spp is not None and (isinstance(spp, bool) or int(spp) != spp or spp < 1):
        raise ValueError(f"spp must be a whole number ≥ 1, got {spp!r}")
    if isinstance(seed, bool) or int(seed) != seed or not 0 <= seed < 2**64:
        raise ValueError(f"seed must be a whole number in [0, 2^64), got {seed!r}")
    if threads is not None and (isinstance(threads, bool) or int(threads) != threads
                                or threads < 1):
        raise ValueError(f"threads must be a whole number ≥ 1, got {threads!r}")
    if adaptive is not None and not isinstance(adaptive, bool):
        raise TypeError(f"adaptive must be True, False or None, got {adaptive!r}")
    close = lambda: None  # noqa: E731
    if progress is True:
        callback, close = _bar()
    elif progress is False or progress is None:
        callback = None
    elif callable(progress):
        callback = progress
    else:
        raise TypeError(f"progress must be True, False or a function, got {progress!r}")
    try:
        data, h, w, channels, meta, stats, stopped_by = _ophis.render(
            scene._native, None if spp is None else int(spp), int(seed),
            None if threads is None else int(threads), callback, adaptive)
    finally:
        close()
    image = np.frombuffer(data, dtype=np.float32).reshape(h, w, len(channels))
    result = RenderResult(image=image, channels=tuple(channels), spp=stats["spp"],
                          samples=stats["samples"], seconds=stats["seconds"],
                          seed=stats["seed"], interrupted=stopped_by is not None,
                          metadata=dict(meta))
    scene.last_render = result
    if stopped_by is not None:
        if hasattr(stopped_by, "add_note"):  # Python 3.11+
            stopped_by.add_note(
                f"ophis: the render stopped after {result.samples} samples ({result.spp} "
                "complete spp); the image is in scene.last_render.image")
        raise stopped_by
    return image
