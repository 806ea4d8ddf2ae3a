"""Shared fixtures: the repository's paths and the `ophis` binary the tests compare against.

The binary is `target/release/ophis` of this checkout (the test script builds it first with
`cargo test --release`), or `$OPHIS_BIN`. A missing binary is an error, not a skip: the
comparisons with the command line are the point of several tests.
"""

import os
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def root() -> Path:
    return ROOT


@pytest.fixture(scope="session")
def ophis_bin() -> Path:
    p = Path(os.environ.get("OPHIS_BIN", ROOT / "target" / "release" / "ophis"))
    if not p.is_file():
        pytest.fail(f"{p} is missing: build it with `cargo build --release` "
                    "(tools/test.sh does) or set OPHIS_BIN")
    return p


@pytest.fixture(scope="session")
def cli(ophis_bin):
    """Runs `ophis ARGS…`, returning stdout; fails the test on a non-zero exit."""
    def run(*args, cwd=None) -> str:
        r = subprocess.run([str(ophis_bin), *map(str, args)], capture_output=True, text=True,
                           cwd=cwd)
        assert r.returncode == 0, f"ophis {' '.join(map(str, args))} failed:\n{r.stderr}"
        return r.stdout
    return run


@pytest.fixture(scope="session")
def reference_xml() -> Path:
    """A 64 × 48 scene with a diffuse floor, a gold, a glass and a plastic object."""
    return ROOT / "tests" / "data" / "reference.xml"
