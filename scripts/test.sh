#!/usr/bin/env bash
# The tests, on a fresh machine with a Rust toolchain and Python 3: cargo's tests, then
# the Python module's. It makes its own virtual environment (target/python/venv),
# installs python/requirements-test.txt into it from PyPI (maturin, NumPy, pandas,
# matplotlib, Dask, Ray, pytest), builds the `filippov` module into it with maturin (release:
# the ensembles' tests run ten thousand runs three ways), builds the Rust side the
# Python tests compare against (examples/python_reference.rs), and runs pytest on
# python/tests (which starts its own two-worker Dask cluster and a local Ray).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD

# The Python glue and the wheel are built (optimised) by maturin below; built here too
# they would only compile PyO3 twice.
# Each phase's time is printed at its end (the CI log keeps them).
phase() { echo "scripts/test.sh: $1 in $((SECONDS - start)) s"; start=$SECONDS; }
start=$SECONDS
cargo test --workspace --exclude filippov-python --exclude filippov-wheel
phase "cargo's tests built and run"

venv=$root/target/python/venv
if [ ! -x "$venv/bin/python" ]; then
    python3 -m venv "$venv"
fi
"$venv/bin/python" -m pip install --quiet --disable-pip-version-check -r python/requirements-test.txt
phase "the virtual environment made"
(cd python/wheel && VIRTUAL_ENV=$venv PATH="$venv/bin:$PATH" maturin develop --quiet --release)
phase "the module built (release)"
# In the test profile, so that everything but the facade (here with its URDF robots)
# is cargo test's build.
cargo build --quiet --profile test --features urdf --example python_reference
phase "the Rust reference built"
"$venv/bin/python" -m pytest python/tests -q
phase "pytest run"
