"""Writing and reading images: EXR exactly with its header, PNG to 8 bits, errors."""

import numpy as np
import pytest

import ophis


def test_exr_round_trip_is_exact_with_metadata(tmp_path):
    rng = np.random.default_rng(1)
    img = rng.random((5, 7, 3), dtype=np.float32) * 4
    ophis.write(tmp_path / "a.exr", img, {"note": "hello", "ophis.seed": "9"})
    back, info = ophis.read(tmp_path / "a.exr")
    assert back.dtype == np.float32 and np.array_equal(back, img)
    assert info.metadata["note"] == "hello" and info.seeds == (9,)
    assert info.pixel_spp is None and info.spp is None
    grey = np.linspace(0, 1, 12, dtype=np.float64).reshape(3, 4)
    ophis.write(tmp_path / "g.exr", grey)
    back, _ = ophis.read(tmp_path / "g.exr")
    assert np.array_equal(back, np.repeat(grey.astype(np.float32)[:, :, None], 3, axis=2))


def test_png_is_srgb_encoded_to_8_bits(tmp_path):
    img = np.linspace(0, 1, 2 * 8 * 3, dtype=np.float32).reshape(2, 8, 3)
    ophis.write(tmp_path / "a.png", img)
    back, info = ophis.read(tmp_path / "a.png")
    assert info.metadata == {}

    def encode(v):
        return np.where(v <= 0.0031308, 12.92 * v, 1.055 * v ** (1 / 2.4) - 0.055)
    # One 8-bit step in the encoded values, half a step of rounding.
    assert np.abs(encode(back) - encode(img)).max() <= 0.5 / 255 + 1e-6


def test_cli_exr_counts(tmp_path, cli, reference_xml):
    cli("render", reference_xml, "--spp", 3, "--seed", 4, "-q", "-o", tmp_path / "c.exr")
    _, info = ophis.read(tmp_path / "c.exr")
    assert info.spp == 3 and info.samples == 3 * 64 * 48 and info.seeds == (4,)
    assert info.pixel_spp.shape == (48, 64) and np.all(info.pixel_spp == 3)
    assert info.scene == "reference.xml" and len(info.scene_hash) == 16


def test_bad_images_raise(tmp_path):
    with pytest.raises(ValueError, match="H × W × 3"):
        ophis.write(tmp_path / "x.exr", np.zeros((2, 2, 4)))
    with pytest.raises(ValueError, match="empty"):
        ophis.write(tmp_path / "x.exr", np.zeros((0, 2, 3)))
    with pytest.raises(ValueError, match="real numbers"):
        ophis.write(tmp_path / "x.exr", np.zeros((2, 2, 3), dtype=complex))
    with pytest.raises(ValueError, match=r"\.exr or \.png"):
        ophis.write(tmp_path / "x.tiff", np.zeros((2, 2, 3)))
    with pytest.raises(OSError):
        ophis.write(tmp_path / "no" / "such" / "dir.exr", np.zeros((2, 2, 3)))
    with pytest.raises(ValueError, match="Latin-1"):
        ophis.write(tmp_path / "x.exr", np.zeros((2, 2, 3)), {"k": "蛇"})
    with pytest.raises(FileNotFoundError):
        ophis.read(tmp_path / "absent.exr")
    (tmp_path / "junk.exr").write_bytes(b"not an image at all")
    with pytest.raises(ValueError, match="junk.exr"):
        ophis.read(tmp_path / "junk.exr")
