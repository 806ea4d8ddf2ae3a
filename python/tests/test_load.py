"""Loading scenes from files, strings and the built-in scene; errors and warnings."""

import subprocess
import warnings

import pytest

import ophis

BAD = """<scene version="3.0.0">
    <shape type="sphere">
        <float name="radius" value="-2"/>
    </shape>
</scene>
"""


def test_load_file_with_defines(reference_xml):
    s = ophis.load_file(reference_xml)
    assert (s.width, s.height, s.spp) == (64, 48, 64)
    assert s.name == "reference.xml"
    assert len(s.scene_hash) == 16
    t = ophis.load_file(reference_xml, spp=5)
    assert t.spp == 5 and t.name == "reference.xml -Dspp=5"
    # The sampler's sample count does not change what the scene is.
    assert t.scene_hash == s.scene_hash
    assert "reference.xml" in repr(s)


def test_load_string_and_builtin(reference_xml):
    xml = reference_xml.read_text()
    s = ophis.load_string(xml, spp=3)
    assert (s.width, s.height, s.spp) == (64, 48, 3)
    # The hash is of the scene, not of where it was read from.
    assert s.scene_hash == ophis.load_file(reference_xml).scene_hash
    x = ophis.load_xenopeltis(width=32, height=18, spp=2)
    assert (x.width, x.height, x.spp) == (32, 18, 2)
    assert x.name == "xenopeltis.xml -Dwidth=32 -Dheight=18 -Dspp=2"


def test_scene_hash_matches_the_cli(tmp_path, cli, reference_xml):
    """Parts rendered from Python and from the command line merge: same identity."""
    cli("render", reference_xml, "-Dspp=1", "-q", "-o", tmp_path / "c.exr")
    _, info = ophis.read(tmp_path / "c.exr")
    assert info.scene_hash == ophis.load_file(reference_xml, spp=1).scene_hash
    assert info.scene == "reference.xml -Dspp=1"
    # The built-in scene too (`ophis render` without a scene).
    cli("render", "-Dwidth=16", "-Dheight=9", "--spp", 1, "-q", "-o", tmp_path / "x.exr")
    _, info = ophis.read(tmp_path / "x.exr")
    assert info.scene_hash == ophis.load_xenopeltis(width=16, height=9).scene_hash
    assert info.scene == "xenopeltis.xml -Dwidth=16 -Dheight=9"


def test_scene_error_carries_the_location_the_cli_prints(tmp_path, ophis_bin):
    p = tmp_path / "bad.xml"
    p.write_text(BAD)
    with pytest.raises(ophis.SceneError) as e:
        ophis.load_file(p)
    err = e.value
    assert isinstance(err, ValueError)
    assert (err.file, err.line) == (str(p), 3)
    assert err.column > 0
    assert "radius" in err.message and "-2" in err.message
    r = subprocess.run([str(ophis_bin), "render", str(p), "-q", "-o", str(tmp_path / "x")],
                       capture_output=True, text=True)
    assert r.returncode == 1
    assert r.stderr.strip() == f"error: {err}"


def test_malformed_and_missing_files(tmp_path):
    with pytest.raises(ophis.SceneError) as e:
        ophis.load_string('<scene version="3.0.0">\n  <shape type="sphere">\n</scene>')
    assert e.value.file == "<string>" and e.value.line == 3
    assert "malformed XML" in str(e.value)
    with pytest.raises(FileNotFoundError):
        ophis.load_file(tmp_path / "absent.xml")
    with pytest.raises(OSError):
        ophis.load_file(tmp_path)
    with pytest.raises(ophis.SceneError, match="nosuchparam"):
        ophis.load_string('<scene version="3.0.0"><shape type="sphere">'
                          '<float name="radius" value="$nosuchparam"/></shape></scene>')


def test_warnings_name_the_place():
    xml = ('<scene version="3.0.0">\n<emitter type="constant"/>\n<shape type="sphere">\n'
           '  <float name="radiuss" value="1"/>\n</shape>\n</scene>\n')
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        ophis.load_string(xml, name="typo.xml")
    msgs = [str(x.message) for x in w if issubclass(x.category, ophis.SceneWarning)]
    assert any(m.startswith("typo.xml:4:") and "radiuss" in m for m in msgs), msgs


def test_internal_errors_are_exceptions_not_crashes():
    with pytest.raises(RuntimeError, match="internal error in ophis"):
        ophis._ophis._panic()
