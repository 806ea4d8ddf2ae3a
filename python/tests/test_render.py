"""Rendering from Python: the CLI's image bit for bit, progress, the GIL, Ctrl-C."""

import _thread
import signal
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import ophis


@pytest.fixture
def scene(reference_xml):
    return ophis.load_file(reference_xml)


def test_render_is_the_cli_render(tmp_path, cli, reference_xml, scene):
    """Same scene, spp and seed: the same pixels and the same header as `ophis render`."""
    cli("render", reference_xml, "--spp", 6, "--seed", 3, "-q", "-o", tmp_path / "c.exr")
    want, info = ophis.read(tmp_path / "c.exr")
    got = ophis.render(scene, spp=6, seed=3, progress=False)
    assert got.shape == (48, 64, 3) and got.dtype == np.float32
    assert np.array_equal(got, want)
    r = scene.last_render
    ophis_keys = {k: v for k, v in info.metadata.items() if k.startswith("ophis.")}
    assert r.metadata == ophis_keys
    assert (r.spp, r.samples, r.seed, r.interrupted) == (6, 6 * 64 * 48, 3, False)
    assert r.channels == ("R", "G", "B")
    assert info.spp == 6 and info.seeds == (3,)


def test_adaptive_is_the_cli_adaptive_and_lasts_one_render(tmp_path, cli, reference_xml, scene):
    """`adaptive=True` renders as `ophis render --adaptive on`, bit for bit; the next render
    without it goes back to the scene's own sampler (uniform here)."""
    cli("render", reference_xml, "--spp", 8, "--seed", 3, "--adaptive", "on", "-q",
        "-o", tmp_path / "a.exr")
    want, _ = ophis.read(tmp_path / "a.exr")
    uniform = ophis.render(scene, spp=8, seed=3, progress=False)
    got = ophis.render(scene, spp=8, seed=3, progress=False, adaptive=True)
    assert np.array_equal(got, want) and not np.array_equal(got, uniform)
    # The same budget, each pixel's share rounded to whole samples.
    assert abs(scene.last_render.samples - 8 * 64 * 48) <= 0.001 * 8 * 64 * 48
    assert np.array_equal(ophis.render(scene, spp=8, seed=3, progress=False), uniform)
    assert np.array_equal(ophis.render(scene, spp=8, seed=3, progress=False, adaptive=False),
                          uniform)


def test_threads_do_not_change_the_image_and_seeds_do(scene, reference_xml):
    a = ophis.render(scene, spp=3, seed=1, threads=1, progress=False)
    b = ophis.render(scene, spp=3, seed=1, threads=3, progress=False)
    c = ophis.render(scene, spp=3, seed=2, progress=False)
    assert np.array_equal(a, b)
    assert not np.array_equal(a, c)
    # The scene's own spp without `spp=`.
    small = ophis.load_file(reference_xml, spp=2)
    ophis.render(small, progress=False)
    assert small.last_render.spp == 2


def test_progress_callback_sees_every_sample(scene):
    calls = []
    ophis.render(scene, spp=8, progress=lambda d, t: calls.append((d, t)))
    total = 8 * 64 * 48
    assert calls and calls[-1] == (total, total)
    assert all(t == total for _, t in calls)
    done = [d for d, _ in calls]
    assert done == sorted(done)


def test_an_exception_in_progress_stops_the_render_and_keeps_the_samples(scene):
    def stop(done, total):
        if done > 0:
            raise RuntimeError("enough")
    with pytest.raises(RuntimeError, match="enough"):
        ophis.render(scene, spp=100_000, progress=stop)
    r = scene.last_render
    assert r.interrupted and 0 < r.samples < 100_000 * 64 * 48


def test_the_gil_is_released_while_rendering(scene):
    ticks, finished = [], []

    def work():
        ophis.render(scene, spp=96, progress=False)
        finished.append(time.monotonic())

    t = threading.Thread(target=work)
    t.start()
    while t.is_alive():
        ticks.append(time.monotonic())
        time.sleep(0.001)
    t.join()
    # Without releasing the GIL this thread would not run until the render ended.
    assert sum(1 for x in ticks if x < finished[0]) > 10


def tile_exact(tmp_path, scene, result):
    """Each 32 × 32 tile of an interrupted render equals a whole render with that tile's
    sample count: samples depend on (seed, pixel, index) and passes are whole per tile."""
    ophis.write(tmp_path / "partial.exr", result)
    img, info = ophis.read(tmp_path / "partial.exr")
    assert np.array_equal(img, result.image)
    counts = info.pixel_spp
    assert int(counts.sum()) == result.samples
    for c in np.unique(counts):
        if c == 0:
            assert np.all(img[counts == 0] == 0)
            continue
        full = ophis.render(scene, spp=int(c), seed=result.seed, progress=False)
        assert np.array_equal(img[counts == c], full[counts == c]), c


@pytest.fixture
def sigint_raises():
    """SIGINT raises KeyboardInterrupt, as in an interactive Python. A process started in the
    background by a non-interactive shell inherits SIGINT ignored, and Python then keeps it
    ignored; `_thread.interrupt_main` and SIGINT would do nothing."""
    old = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, old)


def deadline(seconds):
    """A progress callback that stops a render that should have stopped by now."""
    t0 = time.monotonic()

    def check(done, total):
        if time.monotonic() - t0 > seconds:
            raise AssertionError(f"the render was still running after {seconds} s")
    return check


def test_keyboard_interrupt_keeps_the_samples_taken(tmp_path, scene, sigint_raises):
    timer = threading.Timer(0.4, _thread.interrupt_main)
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        ophis.render(scene, spp=10_000_000, seed=5, progress=deadline(120))
    timer.join()
    r = scene.last_render
    assert r.interrupted and r.samples > 0 and r.seed == 5
    assert 0 <= r.spp < 10_000_000
    tile_exact(tmp_path, scene, r)


CHILD = r"""
import signal, sys, time, ophis
signal.signal(signal.SIGINT, signal.default_int_handler)  # see sigint_raises
scene = ophis.load_file(sys.argv[1])
started = []
def progress(done, total):
    if done and not started:
        started.append(time.monotonic())
        print("rendering", flush=True)
    if started and time.monotonic() - started[0] > 120:
        raise SystemExit("SIGINT did not stop the render")
try:
    ophis.render(scene, spp=10_000_000, progress=progress)
except KeyboardInterrupt:
    ophis.write(sys.argv[2], scene.last_render)
    print("kept", scene.last_render.samples, flush=True)
    sys.exit(130)
"""


def test_sigint_to_a_python_process_rendering(tmp_path, reference_xml, scene):
    out = tmp_path / "sigint.exr"
    p = subprocess.Popen([sys.executable, "-c", CHILD, str(reference_xml), str(out)],
                         stdout=subprocess.PIPE, text=True)
    assert p.stdout.readline().strip() == "rendering"
    p.send_signal(signal.SIGINT)
    try:
        rest = p.communicate(timeout=180)[0]
    except subprocess.TimeoutExpired:
        p.kill()
        raise
    assert p.returncode == 130, rest
    kept = int(rest.split()[-1])
    _, info = ophis.read(out)
    assert kept > 0 and info.samples == kept
    assert int(info.pixel_spp.sum()) == kept


@pytest.mark.parametrize("kw, err", [
    ({"spp": 0}, ValueError), ({"spp": -3}, ValueError), ({"spp": 1.5}, ValueError),
    ({"seed": -1}, ValueError), ({"threads": 0}, ValueError), ({"progress": 3}, TypeError),
    ({"adaptive": "on"}, TypeError), ({"adaptive": 1}, TypeError),
])
def test_bad_arguments_raise(scene, kw, err):
    with pytest.raises(err):
        ophis.render(scene, **{"progress": False, **kw})


def test_render_needs_a_scene():
    with pytest.raises(TypeError, match="ophis.Scene"):
        ophis.render("scene.xml")


AOV_XML = """<scene version="3.0.0">
  <integrator type="aov">
    <string name="aovs" value="dd:depth,nn:sh_normal,id:shape_index"/>
    <integrator type="path" name="image"/>
  </integrator>
  <sensor type="perspective">
    <transform name="to_world"><lookat origin="0, 0, 4" target="0, 0, 0" up="0, 1, 0"/></transform>
    <sampler type="independent"><integer name="sample_count" value="2"/></sampler>
    <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="12"/></film>
  </sensor>
  <emitter type="constant"/>
  <shape type="sphere"/>
</scene>"""


def test_aov_channels_follow_rgb_as_the_cli_writes_them(tmp_path, cli, root):
    """An `aov` scene: the extra channels come after R, G, B with the CLI's names and values,
    and `ophis.write` puts them into the EXR, marked so that `ophis merge` refuses it."""
    sys.path.insert(0, str(root / "tools"))
    from exr_read import read_exr
    path = tmp_path / "aov.xml"
    path.write_text(AOV_XML)
    cli("render", path, "--seed", 2, "-q", "-o", tmp_path / "c.exr")
    want, header = read_exr(tmp_path / "c.exr")
    scene = ophis.load_file(path)
    img = ophis.render(scene, seed=2, progress=False)
    r = scene.last_render
    assert r.channels[:3] == ("R", "G", "B") and len(r.channels) > 3
    assert img.shape == (12, 16, len(r.channels))
    for k, name in enumerate(r.channels):
        assert name in want, (name, sorted(want))
        assert np.array_equal(img[..., k], want[name]), name
    ophis.write(tmp_path / "p.exr", r)
    got, got_header = read_exr(tmp_path / "p.exr")
    for name in r.channels:
        assert np.array_equal(got[name], want[name]), name
    assert set(got_header["ophis.aovs"].split(",")) == set(r.channels[3:])
    assert set(r.channels[3:]) <= set(header["ophis.aovs"].split(","))
