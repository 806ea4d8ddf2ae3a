"""examples/python_tour.py (the notebook's code) runs, and the notebook is that code."""

import os
import subprocess
import sys



def test_notebook_is_the_script(root):
    r = subprocess.run([sys.executable, str(root / "examples" / "sync_notebook.py"), "--check"],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr


def test_tour_runs(root, tmp_path):
    import matplotlib  # noqa: F401  (the example plots; tools/test.sh installs it)
    env = {**os.environ, "OPHIS_EXAMPLE_QUICK": "1", "OPHIS_EXAMPLE_OUT": str(tmp_path),
           "MPLBACKEND": "Agg"}
    r = subprocess.run([sys.executable, str(root / "examples" / "python_tour.py")], env=env,
                       capture_output=True, text=True, cwd=tmp_path, timeout=600)
    assert r.returncode == 0, r.stderr
    for name in ("tour-snake.png", "tour-film-R.png", "tour-thickness.png", "tour-snake.exr"):
        assert (tmp_path / name).stat().st_size > 0, name
