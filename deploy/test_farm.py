"""The render-farm recipes, run locally: the Slurm array script's body for three task ids, the
merge script, and `ophis merge` refusing what a farm gets wrong.

Run by tools/test.sh (pytest, with the `ophis` package installed for reading EXRs).

What the merged image is checked against. The parts use seeds 1, 2, 3; no single render takes
exactly their samples (a render's samples are fixed by its one seed), so an exact comparison
with "one render with all the samples" does not exist. Two checks do:
- exact arithmetic: the merge is the count-weighted mean of the parts (float rounding only);
- statistics against an independent render S with all the samples (3n spp, another seed):
  per pixel, the merged M and S are unbiased with the same variance 2σ²/(3n) of their
  difference, and the parts give an unbiased estimate of σ²/n per pixel,
  s² = Σᵢ (Xᵢ − X̄)² / 2. So d = M − S and e = (M − S)² − (2/3)s² both have mean 0 in every
  pixel, and Z = Σd / √(Σd²) is about N(0, 1) over the image's independent pixels. |Z| ≤ 4
  for both: the first checks the mean, the second that the merge has the noise of 3n samples
  (a merge that kept one part, or double-counted one, has 2× or 1.5× the variance: Z ≫ 4).
"""

import os
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

import ophis

ROOT = Path(__file__).resolve().parents[1]
SLURM = ROOT / "deploy" / "slurm"
SCENE = ROOT / "tests" / "data" / "reference.xml"
N = 8  # spp of each part


def ophis_bin() -> Path:
    p = Path(os.environ.get("OPHIS_BIN", ROOT / "target" / "release" / "ophis"))
    if not p.is_file():
        pytest.fail(f"{p} is missing: build it with `cargo build --release` or set OPHIS_BIN")
    return p


def sh(script: Path, out: Path, **env) -> subprocess.CompletedProcess:
    """Runs a farm script's body with /bin/sh as a Slurm node would (#SBATCH lines are
    comments to the shell)."""
    e = {**os.environ, "OPHIS": str(ophis_bin()), "OUT": str(out), **env}
    e.pop("SLURM_CPUS_PER_TASK", None)
    return subprocess.run(["sh", str(script)], env=e, capture_output=True, text=True)


def task(out: Path, n: int, **env) -> None:
    r = sh(SLURM / "render.sbatch", out, **{"SLURM_ARRAY_TASK_ID": str(n), "SCENE": str(SCENE),
                                            "SPP": str(N), **env})
    assert r.returncode == 0, r.stderr


def z(d: np.ndarray) -> float:
    return float(d.sum() / np.sqrt((d * d).sum()))


@pytest.fixture(scope="module")
def farm(tmp_path_factory):
    out = tmp_path_factory.mktemp("farm")
    for n in (1, 2, 3):
        task(out / "parts", n)
    r = sh(SLURM / "merge.sbatch", out / "parts", NAME="snake")
    assert r.returncode == 0, r.stderr
    single = out / "single.exr"
    subprocess.run([str(ophis_bin()), "render", str(SCENE), "--spp", str(3 * N), "--seed",
                    "1000", "-q", "-o", str(single)], check=True)
    return out


def test_merged_is_the_weighted_mean_of_the_parts(farm):
    parts = [ophis.read(farm / "parts" / f"part-{n}.exr") for n in (1, 2, 3)]
    merged, info = ophis.read(farm / "parts" / "snake.exr")
    for _, p in parts:
        assert p.spp == N and np.all(p.pixel_spp == N)
    assert sorted(p.seeds[0] for _, p in parts) == [1, 2, 3]
    assert info.spp == 3 * N and info.seeds == (1, 2, 3)
    assert info.samples == 3 * N * merged.shape[0] * merged.shape[1]
    assert info.scene_hash == parts[0][1].scene_hash
    want = sum(img.astype(np.float64) for img, _ in parts) / 3
    assert np.allclose(merged, want, rtol=1e-6, atol=1e-7)


def test_merged_agrees_with_one_render_with_all_the_samples(farm):
    x = np.stack([ophis.read(farm / "parts" / f"part-{n}.exr")[0] for n in (1, 2, 3)])
    x = x.astype(np.float64)
    m = ophis.read(farm / "parts" / "snake.exr")[0].astype(np.float64)
    s = ophis.read(farm / "single.exr")[0].astype(np.float64)
    var_part = ((x - x.mean(axis=0)) ** 2).sum(axis=0) / 2  # estimates σ²/n per pixel
    for c in range(3):
        d = (m - s)[..., c]
        e = d ** 2 - (2 / 3) * var_part[..., c]
        assert abs(z(d)) <= 4, ("mean", c, z(d))
        assert abs(z(e)) <= 4, ("variance", c, z(e))
    # The check can fail: one part alone has the wrong noise for 3n samples.
    d1 = x[0] - s
    e1 = d1 ** 2 - (2 / 3) * var_part
    assert z(e1.ravel()) > 4


def test_a_requeued_task_resumes_from_its_state(farm, tmp_path):
    parts = tmp_path / "parts"
    task(parts, 2)
    first = (parts / "part-2.exr").read_bytes()
    assert (parts / "part-2.ophis-state").is_file()
    (parts / "part-2.exr").unlink()
    task(parts, 2)  # finds the state: resumes (here: nothing left to do) and writes again
    assert (parts / "part-2.exr").read_bytes() == first


def test_merge_refuses_a_repeated_seed_and_another_scene(farm, tmp_path):
    parts = tmp_path / "parts"
    shutil.copytree(farm / "parts", parts)
    (parts / "snake.exr").unlink()
    shutil.copy(parts / "part-1.exr", parts / "part-9.exr")  # a task run twice, same seed
    r = sh(SLURM / "merge.sbatch", parts)
    assert r.returncode == 1
    assert "part-1.exr and " in r.stderr and "part-9.exr both hold samples of seed 1" \
        in r.stderr, r.stderr
    (parts / "part-9.exr").unlink()
    task(parts, 4, DEFINES="-Dspp=3")  # -D of the sample count: the same scene, merges
    # Another scene at the same resolution: the floor's colour changed.
    xml = SCENE.read_text()
    assert xml.count('"0.6, 0.55, 0.45"') == 1
    other_scene = tmp_path / "other.xml"
    other_scene.write_text(xml.replace('"0.6, 0.55, 0.45"', '"0.2, 0.55, 0.45"'))
    task(tmp_path / "other", 5, SCENE=str(other_scene))
    shutil.copy(tmp_path / "other" / "part-5.exr", parts / "part-5.exr")
    r = sh(SLURM / "merge.sbatch", parts)
    assert r.returncode == 1
    assert "part-5.exr renders other.xml (scene hash " in r.stderr, r.stderr
    assert "part-1.exr renders reference.xml (scene hash " in r.stderr, r.stderr
    (parts / "part-5.exr").unlink()
    r = sh(SLURM / "merge.sbatch", parts)
    assert r.returncode == 0, r.stderr
    _, info = ophis.read(parts / "merged.exr")
    assert info.seeds == (1, 2, 3, 4)


def test_the_script_needs_a_task_id(tmp_path):
    r = sh(SLURM / "render.sbatch", tmp_path)
    assert r.returncode != 0 and "SLURM_ARRAY_TASK_ID" in r.stderr


def k8s_command(name: str) -> str:
    """The shell script a Job's container runs: the `- |` block (render) or the
    `["sh", "-c", "…"]` string (merge)."""
    text = (ROOT / "deploy" / "k8s" / name).read_text()
    if "- |\n" in text:
        block = text.split("- |\n", 1)[1].split("        resources:", 1)[0]
        return "\n".join(line[10:] for line in block.splitlines())
    return text.split('["sh", "-c", "', 1)[1].split('"]', 1)[0]


def test_the_kubernetes_commands_run(tmp_path):
    """The Indexed Job's command for indices 0 and 1, and the merge Job's, with /out here."""
    bin_dir = tmp_path / "bin"
    bin_dir.mkdir()
    (bin_dir / "ophis").symlink_to(ophis_bin())
    out = tmp_path / "out"
    out.mkdir()
    env = {**os.environ, "PATH": f"{bin_dir}:{os.environ['PATH']}", "SCENE": str(SCENE),
           "SPP": "2", "DEFINES": "-Dspp=2"}
    for index in (0, 1):
        script = k8s_command("render-job.yaml").replace("/out/", f"{out}/")
        r = subprocess.run(["sh", "-c", script], env={**env, "JOB_COMPLETION_INDEX": str(index)},
                           capture_output=True, text=True)
        assert r.returncode == 0, (script, r.stderr)
    merge = k8s_command("merge-job.yaml").replace("/out/", f"{out}/")
    r = subprocess.run(["sh", "-c", merge], env=env, capture_output=True, text=True)
    assert r.returncode == 0, (merge, r.stderr)
    _, info = ophis.read(out / "merged.exr")
    assert info.seeds == (1, 2) and info.spp == 4
