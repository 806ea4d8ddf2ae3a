"""Type stubs of the native module ``ophis._ophis`` (the public API is ``ophis``)."""

from typing import Callable, Optional

class SceneError(ValueError):
    file: str
    line: int
    column: int
    message: str

class Scene:
    width: int
    height: int
    spp: int
    name: str
    scene_hash: str

Warnings = list[tuple[str, int, int, str]]
Pairs = list[tuple[str, str]]

def load_file(path: str, defines: Pairs) -> tuple[Scene, Warnings]: ...
def load_string(xml: str, name: str, defines: Pairs) -> tuple[Scene, Warnings]: ...
def load_xenopeltis(defines: Pairs) -> tuple[Scene, Warnings]: ...
def render(
    scene: Scene,
    spp: Optional[int] = None,
    seed: int = 0,
    threads: Optional[int] = None,
    progress: Optional[Callable[[int, int], None]] = None,
    adaptive: Optional[bool] = None,
) -> tuple[bytearray, int, int, list[str], Pairs, dict, Optional[BaseException]]: ...
def write(path: str, width: int, height: int, data: bytes, metadata: Pairs,
          extra_names: list[str] = ..., extra: Optional[bytes] = ...) -> None: ...
def read(path: str) -> tuple[int, int, bytearray, Pairs, Optional[bytearray]]: ...
def thinfilm(
    film_ior: str,
    thickness: float,
    ext_ior: str,
    int_ior: Optional[str],
    int_eta: Optional[float],
    int_k: Optional[float],
    wavelengths: list[float],
    angles: list[float],
    stack: Optional[str],
) -> tuple[list[float], list[float], list[float], list[float], list[float]]: ...
def bsdf_albedo(
    scene: Scene, id: str, theta_i: float, wavelengths: Optional[list[float]],
    samples: int, seed: int,
) -> list[tuple[float, float]]: ...
def bsdf_eval(
    scene: Scene, id: str, theta_i: float, theta_o: float, phi_o: float,
    wavelengths: Optional[list[float]], samples: int, seed: int,
) -> list[tuple[float, float]]: ...
def _panic() -> None: ...
