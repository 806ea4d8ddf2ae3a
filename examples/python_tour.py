# %% [markdown]
# # ophis from Python
#
# Three studies in a few lines each: the sunbeam snake (*Xenopeltis unicolor*) at preview
# quality, the reflectance spectrum R(λ) of its keratin film at several angles, and a sweep of
# film thickness as a grid of small renders.
#
# Install the package from the repository root with `pip install ./python` (and
# `pip install matplotlib` for the plots). `python_tour.ipynb` is this script as a notebook
# (`python examples/sync_notebook.py` writes it); a test runs the script.

# %%
import os
from pathlib import Path

import matplotlib
import numpy as np

try:
    get_ipython  # noqa: B018 (defined in Jupyter and IPython: figures show inline)
except NameError:
    matplotlib.use("Agg")  # run as a script: write PNGs instead of showing windows
import matplotlib.pyplot as plt

import ophis

# The test sets OPHIS_EXAMPLE_QUICK=1 for tiny renders and OPHIS_EXAMPLE_OUT for the figures.
QUICK = os.environ.get("OPHIS_EXAMPLE_QUICK") == "1"
OUT = os.environ.get("OPHIS_EXAMPLE_OUT", ".")
# The repository (for scenes/studio.hdr): above this script, or above the notebook's folder.
ROOT = Path(__file__).resolve().parents[1] if "__file__" in globals() else Path.cwd().parent


def display(img):
    """Linear sRGB → sRGB-encoded values in [0, 1], for imshow."""
    img = np.clip(img, 0.0, 1.0)
    return np.where(img <= 0.0031308, 12.92 * img, 1.055 * img ** (1 / 2.4) - 0.055)


def save(fig, name):
    fig.savefig(os.path.join(OUT, name), dpi=100, bbox_inches="tight")


# %% [markdown]
# ## The flagship at preview quality
#
# `load_xenopeltis` loads the built-in scene; its parameters (`width`, `height`, `spp`,
# `thickness`, `spread`, `tilt`, `hour`, `exposure`) are Mitsuba's `-D` values. Ctrl-C (or the
# notebook's stop button) stops the render and keeps the samples in `snake.last_render`.

# %%
w, h, spp = (64, 36, 1) if QUICK else (320, 180, 16)
snake = ophis.load_xenopeltis(width=w, height=h, spp=spp)
image = ophis.render(snake)
fig, ax = plt.subplots(figsize=(8, 4.5))
ax.imshow(display(image))
ax.set_axis_off()
ax.set_title(f"Xenopeltis unicolor, {w}×{h}, {spp} spp, {snake.last_render.seconds:.1f} s")
save(fig, "tour-snake.png")
ophis.write(os.path.join(OUT, "tour-snake.exr"), snake.last_render)  # merges with `ophis merge`

# %% [markdown]
# ## R(λ) of the keratin film at several angles
#
# A 300 nm keratin film (n = 1.532 + 5890/λ²) in air. The legend swatches are the colour of
# daylight the film reflects at each angle (at full brightness).

# %%
angles = [0, 30, 45, 60, 75]
film = ophis.thinfilm(film_ior="keratin", thickness=300, angles=angles,
                      wavelengths=np.arange(360.0, 831.0, 2.0))
fig, ax = plt.subplots(figsize=(7, 4))
for j, a in enumerate(film.angles):
    ax.plot(film.wavelengths, film.R[:, j], lw=2, label=f"{a:.0f}°",
            color=display(film.rgb[j] / film.rgb[j].max()) * 0.8)
ax.set_xlabel("wavelength (nm)")
ax.set_ylabel("reflectance R")
ax.set_title("300 nm keratin film in air")
ax.legend(title="incidence")
save(fig, "tour-film-R.png")

# %% [markdown]
# ## Thickness sweep: a grid of small renders
#
# A glossy sphere coated with a keratin film over a black core (`scenes/thinfilm-sphere.xml`,
# here as a Mitsuba 3 dictionary) in a studio environment, rendered once per thickness.


# %%
def coated_sphere(thickness, res):
    return {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": 12},
        "sensor": {
            "type": "perspective", "fov": 30,
            "to_world": ophis.Transform.look_at(origin=[0, 0, 5], target=[0, 0, 0],
                                                up=[0, 1, 0]),
            "film": {"type": "hdrfilm", "width": res, "height": res},
        },
        "studio": {"type": "envmap", "filename": str(ROOT / "scenes" / "studio.hdr")},
        "shell": {"type": "sphere",
                  "bsdf": {"type": "roughthinfilm", "distribution": "ggx", "alpha": 0.05,
                           "int_ior": 1.5, "film_ior": "keratin",
                           "film_thickness": float(thickness)}},
        "core": {"type": "sphere", "radius": 0.98,
                 "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": 0.02}}},
    }


thicknesses = [150, 300, 450] if QUICK else [100, 200, 300, 400, 500, 600, 700, 800]
res, spp = (16, 1) if QUICK else (96, 64)
renders = [ophis.render(ophis.load_dict(coated_sphere(d, res)), spp=spp, progress=False)
           for d in thicknesses]
fig, axes = plt.subplots(1, len(thicknesses), figsize=(2 * len(thicknesses), 2.4))
for ax, d, img in zip(axes, thicknesses, renders):
    ax.imshow(display(img))
    ax.set_title(f"{d} nm")
    ax.set_axis_off()
save(fig, "tour-thickness.png")
