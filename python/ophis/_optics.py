"""Wave optics and BSDF inspection: film reflectance tables, albedo and f·cos estimates."""

from __future__ import annotations

import numbers
from dataclasses import dataclass
from typing import Optional, Sequence, Union

import numpy as np

from . import _ophis
from ._scene import Scene

Ior = Union[float, str]


@dataclass
class ThinFilm:
    """Reflectance of a film per wavelength and angle (see :func:`thinfilm`).

    Attributes:
        wavelengths: (L,) nm.  angles: (A,) degrees from the normal.
        R, T, Rs, Rp: (L, A): unpolarised reflectance (Rs + Rp)/2, the power transmitted
            into the base, and the s- and p-polarised reflectances.
        rgb: (A, 3) linear sRGB of D65 daylight reflected at each angle, integrated over
            360–830 nm at 1 nm; a perfect mirror is (1, 1, 1).
    """

    wavelengths: np.ndarray
    angles: np.ndarray
    R: np.ndarray
    T: np.ndarray
    Rs: np.ndarray
    Rp: np.ndarray
    rgb: np.ndarray


def _ior_text(v: Ior, name: str) -> str:
    if isinstance(v, str):
        return v
    if isinstance(v, numbers.Real) and not isinstance(v, bool):
        return repr(float(v))
    raise TypeError(f"{name} must be a number or an index name, got {v!r}")


def _floats(v, name: str) -> list[float]:
    a = np.atleast_1d(np.asarray(v, dtype=np.float64))
    if a.ndim != 1 or a.size == 0:
        raise ValueError(f"{name}: expected a non-empty list of numbers, got {v!r}")
    return a.tolist()


def _stack_text(stack) -> str:
    """``[(n, d_nm), …]`` (or a string already in ``--stack`` syntax) as ``--stack`` text."""
    if isinstance(stack, str):
        return stack
    items = []
    for i, layer in enumerate(stack):
        try:
            n, d = layer
        except (TypeError, ValueError):
            raise ValueError(f"stack[{i}]: expected (index, thickness_nm), got {layer!r}") from None
        if isinstance(n, complex):
            n = f"{n.real}{n.imag:+}i"
        items.append(f"{_ior_text(n, f'stack[{i}]')}:{float(d)!r}")
    if not items:
        raise ValueError("stack: expected at least one (index, thickness_nm) layer")
    return ",".join(items)


def thinfilm(*, film_ior: Ior = 1.56, thickness: float = 900.0,
             wavelengths: Optional[Sequence[float]] = None,
             angles: Sequence[float] = (0.0,), ext_ior: Ior = 1.0,
             int_ior: Optional[Ior] = None, int_eta: Optional[float] = None,
             int_k: Optional[float] = None, stack=None) -> ThinFilm:
    """Exact reflectance of a thin film or a film stack, as ``ophis thinfilm`` computes it.

    Args:
        film_ior: the film's index: a number, ``"keratin"`` (1.532 + 5890/λ²), or a named
            dielectric (``"water"``, ``"bk7"``, …).
        thickness: film thickness, nm.
        wavelengths: nm; 380, 385, …, 780 without it.
        angles: angles of incidence, degrees (0–90).
        ext_ior: index of the medium the light comes from.
        int_ior: a dielectric base under the film (number or name); without it and without
            ``int_eta``/``int_k`` the base is air (a free-standing film, a soap bubble).
        int_eta, int_k: a metal base n + ik instead.
        stack: instead of ``film_ior``/``thickness``, layers outside in: a list of
            ``(index, thickness_nm)`` (index a number, a complex ``n+kj``, ``"keratin"`` or a
            name), or a string in ``ophis thinfilm --stack`` syntax, e.g.
            ``"(2.3:59.78,1.38:99.64)x6"`` for a six-pair Bragg mirror.

    Raises ValueError naming the argument for negative thickness, angles outside 0–90°,
    non-positive wavelengths or indices, unknown index names.
    """
    if wavelengths is None:
        wavelengths = np.arange(380.0, 781.0, 5.0)
    wl = _floats(wavelengths, "wavelengths")
    an = _floats(angles, "angles")
    if isinstance(thickness, bool) or not isinstance(thickness, numbers.Real):
        raise TypeError(f"thickness must be a number of nm, got {thickness!r}")
    r, t, rs, rp, rgb = _ophis.thinfilm(
        _ior_text(film_ior, "film_ior"), float(thickness), _ior_text(ext_ior, "ext_ior"),
        None if int_ior is None else _ior_text(int_ior, "int_ior"),
        None if int_eta is None else float(int_eta),
        None if int_k is None else float(int_k), wl, an,
        None if stack is None else _stack_text(stack))
    shape = (len(wl), len(an))
    return ThinFilm(
        wavelengths=np.array(wl), angles=np.array(an),
        R=np.array(r).reshape(shape), T=np.array(t).reshape(shape),
        Rs=np.array(rs).reshape(shape), Rp=np.array(rp).reshape(shape),
        rgb=np.array(rgb).reshape(len(an), 3))


@dataclass
class Estimate:
    """A Monte Carlo estimate: ``mean`` and its standard error ``std_err``, one per
    wavelength in ``wavelengths``, or three (linear sRGB under D65) when that is None."""

    mean: np.ndarray
    std_err: np.ndarray
    wavelengths: Optional[np.ndarray]


def _estimate(pairs, wavelengths) -> Estimate:
    a = np.array(pairs, dtype=np.float64).reshape(-1, 2)
    return Estimate(mean=a[:, 0], std_err=a[:, 1],
                    wavelengths=None if wavelengths is None else np.array(wavelengths))


def _wl32(wavelengths) -> Optional[list[float]]:
    return None if wavelengths is None else _floats(wavelengths, "wavelengths")


def bsdf_albedo(scene: Scene, id: str, theta_i: float = 0.0,
                wavelengths: Optional[Sequence[float]] = None, samples: int = 100_000,
                seed: int = 1) -> Estimate:
    """Directional albedo (delta lobes included) of the ``<bsdf id=…>`` of a scene for light
    arriving at ``theta_i`` degrees (negative: from below), by sampling the BSDF: the numbers
    ``ophis bsdf SCENE --id ID --albedo`` prints for the same arguments and seed."""
    return _estimate(_ophis.bsdf_albedo(scene._native, id, float(theta_i),
                                        _wl32(wavelengths), int(samples), int(seed)),
                     wavelengths)


def bsdf_eval(scene: Scene, id: str, theta_i: float = 0.0, theta_o: float = 0.0,
              phi_o: float = 180.0, wavelengths: Optional[Sequence[float]] = None,
              samples: int = 100_000, seed: int = 1) -> Estimate:
    """f·|cos θo| of a scene's ``<bsdf id=…>`` for the pair (θi, φ = 0) → (θo, φo), degrees
    (φo = 180 is the mirror side), averaged over ``samples`` (layered BSDFs are stochastic):
    what ``ophis bsdf SCENE --id ID --eval`` prints."""
    return _estimate(_ophis.bsdf_eval(scene._native, id, float(theta_i), float(theta_o),
                                      float(phi_o), _wl32(wavelengths), int(samples),
                                      int(seed)),
                     wavelengths)
