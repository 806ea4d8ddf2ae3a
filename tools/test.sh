#!/usr/bin/env bash
# The test suite, as CI runs it (.ci/run calls this script): the Rust tests, then the Python
# package built into a fresh virtual environment and its tests, the example notebook's script
# and the render-farm recipes (deploy/). Needs a Rust toolchain and Python 3.9+ with pip and
# venv; pip fetches maturin, numpy, pytest and matplotlib from PyPI.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD

cargo test --release
# The binary the Python tests compare against (already built by the tests above).
cargo build --release --bin ophis

python=${PYTHON:-python3}
venv="$root/target/test-venv"
rm -rf "$venv"
"$python" -m venv "$venv"
# Sharing the root's target directory reuses the dependencies `cargo test` just built.
CARGO_TARGET_DIR="$root/target" "$venv/bin/pip" install --quiet --disable-pip-version-check \
    ./python pytest matplotlib
# From target/ so that `import ophis` is the installed package, not the python/ophis sources.
cd "$root/target"
OPHIS_BIN="$root/target/release/ophis" "$venv/bin/python" -m pytest -q -p no:cacheprovider \
    "$root/python/tests" "$root/deploy"
